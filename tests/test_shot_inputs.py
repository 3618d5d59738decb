"""A shot's inputs checked from their names and headers before anything is painted, its report.json strict JSON,
and its method the one it is painted with.

- ``-o`` the folder of frames is refused (the painted frames would be read as frames on the next run); a pattern
  or listed files whose folder is the output folder keep working when no frame bears an output's name, and a
  frame that does is refused (it would be written over). ``core batch`` writes each still into a folder of its
  own, so ``-o`` the stills' folder works again and again.
- Frame numbers above Blender's last frame (``frames.MAX_FRAME``) are refused by name, before any painting;
  ``--frames`` takes numbers up to it.
- A Vector pass with values no motion can have (1e30 px) leaves the frame quietly: no warning, and the same
  bytes as a pass whose motion is exactly the frame's reach.
- report.json is strict JSON, null where a figure has no value.
- A shot asked for with Hertzmann 1998 is refused in one sentence saying shots are painted with the paper's
  method: through ``core.paint_sequence_files``, the command line and Paint Animation in Blender.
"""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from blender_run import need_bpy, run_checks
from oracles import folder_bytes, one_sentence, one_sentence_run
from test_frames import write_multilayer
from tiny_shot import shot

import core
from core.errors import InputError, ParameterError
from core.files import frames, writing
from core.motion.warp import reach
from core.params import Params

REPO = Path(__file__).resolve().parent.parent


def run(*arguments, warnings_as_errors=False):
    """``python -m core ARGUMENTS -q`` in a process of its own (NumPy's warnings raised as errors when asked)."""
    flags = ["-W", "error"] if warnings_as_errors else []
    return subprocess.run([sys.executable, *flags, "-m", "core", *map(str, arguments), "-q"], capture_output=True,
                          text=True, cwd=REPO, timeout=600)


def strict_json(path: Path):
    """The file ``path`` parsed as strict JSON: NaN, Infinity and -Infinity are refused."""
    def refuse(constant):
        raise ValueError(f"{path} holds {constant}, which is not JSON")
    return json.loads(path.read_text(encoding="utf-8"), parse_constant=refuse)


def painted_bytes(folder: Path, inputs=()):
    """``folder_bytes`` of a painted folder without its input frames (``inputs``, paths) and report.json."""
    return folder_bytes(folder, ("report.json", *(Path(p).name for p in inputs)))


@pytest.fixture(scope="module")
def footage(tmp_path_factory):
    """Two frames of the tiny shot (frame_0011.png, frame_0012.png) in a folder of their own."""
    return shot(tmp_path_factory.mktemp("footage") / "frames", frames=2)


@pytest.fixture(scope="module")
def painted(footage, tmp_path_factory):
    """The footage painted into a folder of its own by the command line."""
    out = tmp_path_factory.mktemp("painted") / "shot"
    result = run("sequence", footage, "-o", out, "--measures")
    assert result.returncode == 0, result.stderr
    return out


# --- 1. the output folder is never read as frames --------------------------------------------------------------

@pytest.mark.parametrize("spelling", ["{}", "{}/", "{}/."])
def test_the_folder_of_frames_as_output_folder_is_refused_before_anything_is_written(tmp_path, spelling):
    folder = shot(tmp_path / "frames", frames=2)
    before = folder_bytes(folder, ())
    result = run("sequence", folder, "-o", spelling.format(folder))
    sentence = one_sentence_run(result)
    assert result.returncode == 2 and f"is the folder of frames {folder}" in sentence
    assert "paint into another folder" in sentence
    assert folder_bytes(folder, ()) == before and sorted(p.name for p in folder.iterdir()) == sorted(before)


def test_the_folder_of_frames_is_refused_as_output_folder_through_the_api(tmp_path):
    folder = shot(tmp_path / "frames", frames=2)
    before = folder_bytes(folder, ())
    with pytest.raises(InputError) as caught:
        core.paint_sequence_files(folder, folder, Params())
    assert "is the folder of frames" in one_sentence(str(caught.value))
    assert folder_bytes(folder, ()) == before


def test_a_pattern_into_its_own_folder_paints_and_goes_on_to_the_same_bytes(tmp_path, painted, footage):
    """render/frame_####.png with -o render: the painted files bear no frame's name, so the same command runs
    again (a complete shot: nothing more to paint) and the painting is the one painted elsewhere."""
    folder = shot(tmp_path / "render", frames=2)
    pattern = str(folder / "frame_####.png")
    inputs = sorted(folder.iterdir())
    first = run("sequence", pattern, "-o", folder)
    assert first.returncode == 0, first.stderr
    painted_here = painted_bytes(folder, inputs)
    assert painted_here == painted_bytes(painted)
    again = run("sequence", pattern, "-o", folder)
    assert again.returncode == 0 and not again.stderr.strip(), again.stderr
    assert painted_bytes(folder, inputs) == painted_here
    assert strict_json(folder / "report.json")["complete"] is True


def test_listed_frames_into_their_own_folder_go_on_after_a_stop(tmp_path, painted):
    """Files listed by name (Blender's rendered frames) whose folder is the output folder: frame 11 painted, then
    both, to the bytes of the shot painted at once elsewhere."""
    folder = shot(tmp_path / "render", frames=2)
    inputs = sorted(folder.iterdir())
    assert run("sequence", *inputs, "-o", folder, "--frames", "11").returncode == 0
    rest = run("sequence", *inputs, "-o", folder)
    assert rest.returncode == 0, rest.stderr
    assert painted_bytes(folder, inputs) == painted_bytes(painted)


@pytest.mark.parametrize("name", ["color_####.exr", "painting_####.png"])
def test_a_frame_bearing_an_output_name_in_the_output_folder_is_refused(painted, name):
    """The painted files of a shot given back as frames into the same folder would be written over."""
    before = folder_bytes(painted)
    result = run("sequence", painted / name, "-o", painted)
    sentence = one_sentence_run(result)
    assert str(painted / name.replace("####", "0011")) in sentence and "would be written over" in sentence
    assert folder_bytes(painted) == before


def test_a_painting_into_a_folder_inside_the_folder_of_frames_is_painted(tmp_path, painted):
    """A folder's subfolders are not read as frames: the output folder may sit inside the folder of frames."""
    folder = shot(tmp_path / "frames", frames=2)
    for _ in range(2):
        result = run("sequence", folder, "-o", folder / "painted")
        assert result.returncode == 0, result.stderr
    assert painted_bytes(folder / "painted") == painted_bytes(painted)


def test_a_batch_into_the_folder_of_its_stills_keeps_its_paintings_and_paints_anew_with_fresh(tmp_path, half_textured):
    """core batch writes each still into <stem>_001: its outputs are never among its inputs. Run again it keeps
    them; with --fresh it paints each again into <stem>_002, the same bytes."""
    folder = tmp_path / "stills"
    folder.mkdir()
    stills = [folder / "a.png", folder / "b.png"]
    for seed, path in enumerate(stills):
        writing.write_png(path, half_textured(32, 40, seed))
    for counter, options in (("001", ()), ("001", ()), ("002", ("--fresh",))):
        result = run("batch", *stills, "-o", folder, *options)
        assert result.returncode == 0, result.stderr
        assert [line.split(" -> ")[1] for line in result.stdout.splitlines()] == [
            str(folder / f"{path.stem}_{counter}") for path in stills]
    for path in stills:
        assert folder_bytes(folder / f"{path.stem}_001") == folder_bytes(folder / f"{path.stem}_002")


# --- 2. frame numbers Blender can hold --------------------------------------------------------------------------

@pytest.mark.parametrize("number", ["12345678901234567890", "1048575"])
def test_a_frame_number_above_blenders_last_frame_is_refused_by_name(tmp_path, footage, number):
    folder = tmp_path / "frames"
    folder.mkdir()
    first = folder / f"f_{number}.png"
    first.write_bytes((footage / "frame_0011.png").read_bytes())
    (folder / f"f_{int(number) + 1}.png").write_bytes((footage / "frame_0012.png").read_bytes())
    result = run("sequence", folder, "-o", tmp_path / "out")
    sentence = one_sentence_run(result)
    assert result.returncode == 2
    assert sentence == (f"paint-relief: error: The frame {first} is numbered {number} by its name, above 1048574, "
                        f"the last frame Blender can hold: number the frames from 0 to 1048574.")
    assert not (tmp_path / "out").exists()


def test_blenders_last_frame_is_a_frame(tmp_path, footage):
    folder = tmp_path / "frames"
    folder.mkdir()
    (folder / "f_1048573.png").write_bytes((footage / "frame_0011.png").read_bytes())
    (folder / "f_1048574.png").write_bytes((footage / "frame_0012.png").read_bytes())
    assert frames.find_frames([str(folder)]).numbers == (1048573, 1048574)


def test_a_frame_number_outside_the_selection_is_not_checked(tmp_path, footage):
    folder = tmp_path / "frames"
    folder.mkdir()
    (folder / "f_0001.png").write_bytes((footage / "frame_0011.png").read_bytes())
    (folder / "f_99999999999.png").write_bytes((footage / "frame_0012.png").read_bytes())
    assert frames.find_frames([str(folder)], "1").numbers == (1,)


@pytest.mark.parametrize("text", ["1048575", "0-1048575", "1048575-", "-" + "9" * 5000])
def test_the_frames_option_takes_numbers_up_to_blenders_last_frame(tmp_path, footage, text):
    result = run("sequence", footage, "-o", tmp_path / "out", "--frames", text)
    sentence = one_sentence_run(result)
    assert "The option --frames takes frame numbers from 0 to 1048574" in sentence and len(sentence) < 200
    assert not (tmp_path / "out").exists()
    assert frames.parse_frame_range("0-1048574") == (0, 1048574)


# --- 3. a Vector pass with values no motion can have ------------------------------------------------------------

def vector_footage(folder: Path, value: float, rows: int = 24) -> Path:
    """Three 64 x 48 multilayer EXR frames whose Vector pass holds ``value`` in every channel on the upper ``rows``
    rows and a motion of 2 px to the right below."""
    folder.mkdir(parents=True)
    height, width = 48, 64
    rng = np.random.default_rng(0)
    for number in (1, 2, 3):
        rgba = np.ones((height, width, 4), np.float32)
        rgba[..., :3] = rng.random((height, width, 3), dtype=np.float32)
        vector = np.zeros((height, width, 4), np.float32)
        vector[:rows] = value
        vector[rows:, :, 0] = -2.0
        vector[rows:, :, 2] = -2.0
        write_multilayer(folder / f"frame_{number:04d}.exr", [("ViewLayer.Combined", "RGBA", rgba),
                                                              ("ViewLayer.Vector", "XYZW", vector)])
    return folder


def test_a_vector_pass_of_values_no_motion_can_have_leaves_the_frame_quietly(tmp_path):
    """1e30 px: painted without a warning (NumPy's warnings raised as errors), to the bytes of a pass whose motion
    is exactly the frame's reach (every pixel leaves the frame either way)."""
    absurd = vector_footage(tmp_path / "absurd", 1e30)
    within = vector_footage(tmp_path / "within", reach(48, 64))
    for footage_folder in (absurd, within):
        result = run("sequence", footage_folder, "-o", tmp_path / f"{footage_folder.name}_painted",
                     warnings_as_errors=True)
        assert result.returncode == 0 and not result.stderr.strip(), result.stderr
    assert painted_bytes(tmp_path / "absurd_painted") == painted_bytes(tmp_path / "within_painted")
    report = strict_json(tmp_path / "absurd_painted" / "report.json")
    assert report["frames"] == [1, 2, 3] and report["motion"] == "vector pass"


def test_a_shot_whose_every_pixel_leaves_the_frame_goes_on_quietly(tmp_path):
    """Every pixel leaves the frame: no pair has a warping error (null in report.json); a run stopped after two
    frames goes on to the third without a warning, to the bytes of the shot painted at once."""
    footage_folder = tmp_path / "gone"
    vector_footage(footage_folder, 1e30, rows=48)
    at_once, resumed = tmp_path / "at_once", tmp_path / "resumed"
    for arguments in ([at_once], [resumed, "--frames", "1-2"], [resumed]):
        result = run("sequence", footage_folder, "-o", *arguments, "--measures", warnings_as_errors=True)
        assert result.returncode == 0 and not result.stderr.strip(), result.stderr
    assert painted_bytes(resumed) == painted_bytes(at_once)
    assert strict_json(resumed / "report.json")["warping_error"]["footage"] is None

# --- 4. report.json is strict JSON -------------------------------------------------------------------------------

def test_a_shot_report_is_strict_json_with_null_for_a_ratio_to_nothing(painted):
    """Where the footage stands still it does not change: the painting's stillness against it has no value."""
    report = strict_json(painted / "report.json")
    assert report["stillness"]["footage"] == 0.0 and report["stillness"]["ratio"] is None
    assert isinstance(report["warping_error"]["footage"], float)


def test_measures_change_no_painted_byte_and_a_run_without_them_leaves_none_in_the_report(tmp_path, painted,
                                                                                         footage):
    """``--measures`` adds each pair's steadiness to report.json and nothing else; a frame painted without it
    carries none, and the report's figures are those of the run that wrote it last."""
    plain = tmp_path / "plain"
    result = run("sequence", footage, "-o", plain)
    assert result.returncode == 0, result.stderr
    assert painted_bytes(plain) == painted_bytes(painted)
    report = strict_json(plain / "report.json")
    assert "warping_error" not in report and "stillness" not in report
    assert not [entry for entry in report["per_frame"] if "warping_error" in entry or "measures" in entry["seconds"]]
    assert "motion" in report["per_frame"][1]["seconds"] and "motion" in report["seconds"]
    assert "warping_error" in strict_json(painted / "report.json")["per_frame"][1]
    resumed = tmp_path / "resumed"
    for arguments in (["--frames", "11", "--measures"], []):
        result = run("sequence", footage, "-o", resumed, *arguments)
        assert result.returncode == 0, result.stderr
    assert painted_bytes(resumed) == painted_bytes(painted)
    assert "warping_error" not in strict_json(resumed / "report.json")


def test_a_shot_report_where_no_pixel_stands_still_is_strict_json_with_null(tmp_path):
    """No pixel of the footage stands still (half of it leaves the frame, half moves 2 px): each pair's stillness
    and the shot's have no value."""
    footage_folder = vector_footage(tmp_path / "moving", 1e30)
    result = run("sequence", footage_folder, "-o", tmp_path / "painted", "--measures")
    assert result.returncode == 0, result.stderr
    report = strict_json(tmp_path / "painted" / "report.json")
    for pair in report["per_frame"][1:]:
        assert pair["still_pixels"] == 0 and pair["stillness"] == {"footage": None, "painting": None}
    assert report["stillness"] == {"footage": None, "painting": None, "ratio": None}


def test_a_still_report_is_strict_json(tmp_path, half_textured):
    photo = tmp_path / "photo.png"
    writing.write_png(photo, half_textured(32, 40))
    report = core.paint_file(photo, tmp_path / "out", Params())
    assert strict_json(tmp_path / "out" / "report.json")["psnr_db"] == pytest.approx(report["psnr_db"])


# --- 5. a shot is painted with the paper's method ---------------------------------------------------------------

SHOT_METHOD = "Shots are painted with the paper's method (Huang 2011, huang11); Hertzmann 1998 (hertzmann98) " \
              "paints still images only."


def test_a_shot_with_hertzmann_1998_is_refused_before_anything_is_written(tmp_path, footage):
    with pytest.raises(ParameterError) as caught:
        core.paint_sequence_files(footage, tmp_path / "out", Params(method="hertzmann98"))
    assert one_sentence(str(caught.value)) == SHOT_METHOD
    assert not (tmp_path / "out").exists()
    with pytest.raises(ParameterError, match="paper's layout"):
        core.paint_sequence_files(footage, tmp_path / "out", Params(layout="hertzmann98"))
    assert not (tmp_path / "out").exists()


def test_the_sequence_command_has_no_method_to_choose(tmp_path, footage):
    result = run("sequence", footage, "-o", tmp_path / "out", "--method", "hertzmann98")
    assert "Unrecognized arguments: --method hertzmann98" in one_sentence_run(result)
    assert not (tmp_path / "out").exists()


BLENDER_CHECKS = '''
import json, os, sys
sys.path.insert(0, {blender_tests!r})
from recorder import RESULTS, check, load_extension
from paint_shot_checks import _Layout, run_op, write_frame

work = sys.argv[1]
bpy = load_extension(work)
from paint_relief.addon import panels

scene = bpy.context.scene
settings = scene.paint_relief
for number in (1, 2):
    write_frame(bpy, os.path.join(work, "frames", "f_{{:04d}}.png".format(number)), number)
settings.animation_source = "FOLDER"
settings.animation_folder = os.path.join(work, "frames")
settings.animation_output_dir = os.path.join(work, "painted")


@check
def hertzmann_shot():
    settings.method = "HERTZMANN98"
    result, error = run_op(bpy.ops.paint_relief.paint_animation)
    return {{"result": result, "error": error, "output_exists": os.path.exists(os.path.join(work, "painted"))}}


@check
def panel_notes():
    shown = {{}}
    for method in ("HERTZMANN98", "HUANG11"):
        settings.method = method
        layout = _Layout()
        panel = type("Panel", (), {{"layout": layout, "_layout": lambda self: self.layout}})()
        panels.VIEW3D_PT_paint_relief_animation.draw(panel, bpy.context)
        shown[method] = layout.shown
    return shown


print("RESULTS " + json.dumps(RESULTS), flush=True)
'''


@pytest.mark.blender
def test_paint_animation_with_hertzmann_1998_says_so_and_does_nothing(tmp_path):
    need_bpy()
    script = tmp_path / "shot_method_checks.py"
    script.write_text(BLENDER_CHECKS.format(blender_tests=str(REPO / "tests" / "blender")), encoding="utf-8")
    work = tmp_path / "work"
    work.mkdir()
    results = run_checks(script, work, work)
    refused = results["hertzmann_shot"]
    assert "exception" not in refused, refused.get("exception")
    assert refused["result"] is None and one_sentence(refused["error"]) == SHOT_METHOD
    assert not refused["output_exists"]
    notes = results["panel_notes"]
    assert "label Shots are painted with the paper's method: choose Huang 2011 in Paint" in notes["HERTZMANN98"]
    assert "label The Paint panel's painter settings apply" in notes["HUANG11"]
    assert notes["HERTZMANN98"][-1] == "operator paint_relief.paint_animation"
