"""Paint Animation inside Blender: the scene's render leaves the scene as it found it, a stopped run keeps
complete frames and goes on to the same bytes, and every kind of source names the right frames.

tests/blender/paint_shot_checks.py runs every step in one subprocess (``bpy``
can be imported once per process; BLENDER_USER_RESOURCES in a temporary
folder) on a 64 x 48 px, 4-frame Cycles scene at 2 samples, and prints its
findings as JSON; each test here asserts on one step. The pure helpers of
addon/values.py are tested without Blender.
"""

import json
import os
import re
from pathlib import Path

import pytest
from addon_values import values
from blender_run import need_bpy, run_checks
from oracles import one_sentence

from core.files import shot_files

REPO = Path(__file__).resolve().parent.parent
HELPER = REPO / "tests" / "blender" / "paint_shot_checks.py"


# --- pure helpers -------------------------------------------------------------

def test_numbered_file_reads_the_last_run_of_digits_as_blender_does():
    assert shot_files.numbered_file("/a/shot_0005.png") == ("/a/shot_####.png", 5)
    assert shot_files.numbered_file("/a/take2_v3_012.exr") == ("/a/take2_v3_###.exr", 12)
    with pytest.raises(ValueError, match="holds no frame number"):
        shot_files.numbered_file("/a/still.png")


def test_pattern_file_pads_and_grows_as_blender_writes():
    assert shot_files.pattern_file("/a/shot_####.png", 12) == "/a/shot_0012.png"
    assert shot_files.pattern_file("/a/shot_##.png", 123) == "/a/shot_123.png"
    assert shot_files.pattern_file(*shot_files.numbered_file("/b/f_007.exr")) == "/b/f_007.exr"


def test_render_file_names_refuse_negative_frames():
    assert values.render_file_stem(0) == "frame_0000" and values.render_file_stem(12345) == "frame_12345"
    with pytest.raises(ValueError, match="negative"):
        values.render_file_stem(-1)


def test_render_paths_keep_braces_literal_where_blender_reads_templates():
    assert values.escape_render_path("/x/a{b}/f", True) == "/x/a{{b}}/f"
    assert values.escape_render_path("/x/a{b}/f", False) == "/x/a{b}/f"


def test_render_progress_fills_half_by_rendering():
    assert values.render_progress(0, 4, 0.0) == 0.0
    assert values.render_progress(2, 4, 0.0) == 0.25
    assert values.render_progress(4, 4, 0.5) == 0.75
    assert values.render_progress(0, 0, 0.3) == 0.3  # nothing to render (a sequence on disk)


def test_sequence_folder_state(tmp_path):
    assert values.sequence_folder_state(tmp_path / "none") == "empty"
    cases = {"still": {"strokes": 10}, "unfinished": {"sequence": "k", "complete": False, "input": ["a"]},
             "complete": {"sequence": "k", "complete": True, "input": ["a", "b"]}}
    for state, report in cases.items():
        (tmp_path / state).mkdir()
        (tmp_path / state / "report.json").write_text(json.dumps(report))
        assert values.sequence_folder_state(tmp_path / state) == state
    assert values.sequence_folder_inputs(tmp_path / "complete") == ["a", "b"]
    assert values.sequence_folder_inputs(tmp_path / "still") is None
    (tmp_path / "broken").mkdir()
    (tmp_path / "broken" / "report.json").write_text("{")
    assert values.sequence_folder_state(tmp_path / "broken") == "unreadable"


def test_is_inside(tmp_path):
    assert values.is_inside(tmp_path / "a" / "b", tmp_path / "a")
    assert values.is_inside(tmp_path / "a", tmp_path / "a")
    assert not values.is_inside(tmp_path / "ab", tmp_path / "a")


def test_only_an_installed_extensions_folder_is_guarded(tmp_path):
    """Blender deletes a package folder of its extension repositories on update or removal, not a checkout loaded
    by path, nor a checkout linked into a repository (it removes the link)."""
    repository, user = tmp_path / "extensions" / "user_default", tmp_path / "extensions" / ".user" / "x" / "pkg"
    installed, checkout = repository / "paint_relief", tmp_path / "work" / "paint_relief"
    for folder in (installed, checkout, tmp_path / "elsewhere"):
        folder.mkdir(parents=True)
    (tmp_path / "elsewhere" / "paint_relief").symlink_to(checkout, target_is_directory=True)
    repositories = [str(repository), "", str(tmp_path / "elsewhere")]
    assert values.guarded_folders(str(installed), repositories, str(user)) == [str(installed), str(user)]
    assert values.guarded_folders(str(installed), [str(tmp_path / "extensions")]) == [str(installed)]
    assert values.guarded_folders(str(checkout), repositories) == []
    assert values.guarded_folders(str(tmp_path / "elsewhere" / "paint_relief"), repositories) == []
    assert values.guarded_folders(str(checkout), [], str(user)) == [str(user)]


# --- inside Blender ---------------------------------------------------------------

@pytest.fixture(scope="module")
def results(tmp_path_factory):
    need_bpy()
    work = tmp_path_factory.mktemp("animation")
    return run_checks(HELPER, work, work / "checks")


def _step(results, name, painter=False):
    if painter and not results["painter"]:
        pytest.skip("the painter's libraries are missing here: " + results[name]["skipped"])
    step = results[name]
    assert "exception" not in step, step.get("exception")
    return step


def _frame_files(number):
    return set(shot_files.frame_file_names(number, normal_map=False))


@pytest.mark.blender
def test_rendering_the_scene_puts_every_setting_back(results):
    step = _step(results, "render_frames_restore_the_scene")
    # Render, image format, colour management, Cycles, every view layer and its passes, the frame, the
    # compositor's nodes and links: all as before (checked after every frame too).
    assert step["differences"] == []
    assert step["rendered"] == 4 and step["files"] == ["frame_{:04d}.exr".format(n) for n in range(1, 5)]
    assert step["frame_current"] == 3 and not step["user_frames"]
    channels = step["channels"]
    if channels is not None:  # with OpenImageIO's Python module: the file holds the render, not the composite
        assert {"ViewLayer.Combined.R", "ViewLayer.Vector.X", "ViewLayer.Vector.W"} <= set(channels)
        assert not any(name.startswith(("Composite.", "Background.")) for name in channels), channels
        # The user's own passes are rendered as they are set.
        assert {"ViewLayer.Depth.Z", "ViewLayer.Normal.X", "ViewLayer.user_aov.R"} <= set(channels)


@pytest.mark.blender
def test_a_video_or_exr_output_is_put_back_too(results):
    step = _step(results, "other_output_formats")
    for file_format in ("FFMPEG", "OPEN_EXR"):
        assert step[file_format]["differences"] == [], file_format
        assert step[file_format]["files"] == ["frame_0001.exr"], file_format


@pytest.mark.blender
def test_paint_animation_of_the_scene_leaves_it_as_it_found_it(results):
    step = _step(results, "paint_the_scene", painter=True)
    assert step["result"] == ["FINISHED"], step["error"]
    assert step["differences"] == []
    assert step["motion"] == "vector pass" and step["complete"] and step["frames"] == [1, 2, 3, 4]
    assert [Path(p).parent.name for p in step["inputs"]] == ["scene_render"] * 4
    assert set().union(*(_frame_files(n) for n in range(1, 5))) <= set(step["files"])
    assert "scene_render" not in step["files"]  # the rendered frames go once every frame is painted
    assert step["painting_dir"].endswith("scene_painted") and step["animation_key"] == ""


@pytest.mark.blender
def test_esc_keeps_complete_frames_and_paint_animation_goes_on_to_the_same_bytes(results):
    """The interactive operator (its modal steps driven as a window drives them), stopped twice by Esc."""
    step = _step(results, "cancel_and_resume", painter=True)
    # Esc while rendering: the frame being rendered ends, two complete frames stay, nothing half written,
    # the scene as it was, the progress bar and the status text gone.
    stopped = step["after_render_stop"]
    assert stopped["outcome"] == ["CANCELLED"] and stopped["reports"][-1][0] == "WARNING"
    assert "2 of 4 frames" in one_sentence(stopped["reports"][-1][1])
    assert stopped["differences"] == [] and not stopped["running"]
    assert set(stopped["files"]) == {"scene_render/frame_0001.exr", "scene_render/frame_0002.exr"}
    assert any("rendering frame 2 (2/4)" in (text or "") for text in stopped["texts"]), stopped["texts"]
    assert stopped["texts"][-1] is None and stopped["progress"][-2:] == ["timer removed", "end"]
    # The folder the operator picked, beside the saved .blend file, is picked again by the next press.
    assert step["folder"] == os.path.join(step["parent"], "Shot_001")
    assert step["after_paint_stop"]["folder"] == step["folder_again"] == step["folder"]
    # Esc while painting frame 3: whole frames only (1, 2 and perhaps 3), the rendered footage kept.
    painted = step["after_paint_stop"]
    assert painted["outcome"] == ["CANCELLED"] and painted["reports"][-1][0] == "WARNING"
    assert "cancelled" in one_sentence(painted["reports"][-1][1]) and not painted["running"]
    frames = painted["frames"]
    assert frames in ([1, 2], [1, 2, 3]), frames
    kept = {"report.json", "strokes.lives", ".sequence-state.npz"}.union(*(_frame_files(n) for n in frames))
    kept |= {"scene_render/frame_{:04d}.exr".format(n) for n in range(1, 5)}
    assert set(painted["files"]) == kept
    # Progress names the frame and the stage within it.
    assert any(re.search(r"Frame \d \(\d/4\): \w", text or "") for text in painted["texts"]), painted["texts"]
    # Paint Animation again goes on after the last complete frame (frame 1 is not painted again) and ends
    # with the bytes of a run never stopped; the rendered footage goes, the scene is as it was.
    assert step["outcome"] == ["FINISHED"], step["reports"]
    assert step["resumed_frames"] == [1, 2, 3, 4] and step["complete"]
    assert step["resumed_first_frame"] == painted["first_frame"]
    assert not any(name.startswith("scene_render") for name in step["resumed_files"])
    assert step["differences"] == []
    assert step["reference_result"] == ["FINISHED"], step["reference_error"]
    assert step["differing"] == []


@pytest.mark.blender
def test_sources_name_their_frames(results):
    step = _step(results, "sources")
    shots = ["shot_{:04d}.png".format(n) for n in range(3, 9)]
    assert step["no_user"] == shots[2:]        # the image's own file and the numbered files after it
    assert step["user_4_to_7"] == shots[1:5]   # an image texture's frame offset and duration
    assert step["user_3_to_102"] == shots      # a duration beyond the last file ends with it
    assert step["user_41_to_42"] == shots[2:4]
    if not results["painter"]:
        return
    expected = {"IMAGE": ([5, 6, 7, 8], shots[2:]), "FOLDER": (list(range(3, 9)), shots),
                "PATTERN": ([1, 2, 3], ["take_001.png", "take_002.png", "take_003.png"])}
    for source, (frames, inputs) in expected.items():
        found = step[source]
        assert found["result"] == ["FINISHED"], (source, found["error"])
        assert found["frames"] == frames and found["inputs"] == inputs, source


@pytest.mark.blender
def test_a_bad_source_or_folder_is_one_sentence_and_writes_nothing(results):
    step = _step(results, "bad_sources", painter=True)
    words = {"image_not_a_sequence": "not an image sequence", "missing_folder": "does not exist",
             "folder_without_frames": "holds no frames", "frames_of_two_sizes": "same size",
             "missing_frame": "frame 2 is missing", "pattern_without_hash": "holds no '#'",
             "pattern_matching_nothing": "No file matches", "no_camera": "no active camera",
             "output_inside_the_extension": "inside the extension's folder",
             "still_inside_the_extension": "inside the extension's folder",
             "into_a_still": "holds a still painting", "into_a_finished_animation": "complete painted animation",
             "into_other_footage": "other footage"}
    assert set(step) == set(words)
    for case, word in words.items():
        found = step[case]
        assert found["result"] is None and word in one_sentence(found["error"]), (case, found["error"])
        assert not found["output_exists"], case


@pytest.mark.blender
def test_paint_and_paint_object_end_alike_finished_or_cancelled(results):
    step = _step(results, "scene_jobs_end", painter=True)
    assert set(step) == {"paint finished", "paint cancelled", "paint_object finished", "paint_object cancelled"}
    for case, found in step.items():
        assert not found["running"] and found["status"] is None, (case, found)
        assert found["progress"][-2:] == ["timer removed", "end"], (case, found)
        assert not found["scratch_left"], (case, found)
        expected = ["FINISHED"] if case.endswith("finished") else ["RUNNING_MODAL"]
        assert found["outcome"] == expected, (case, found)
    assert any("Painted" in text for _, text in step["paint_object finished"]["reports"]), step


@pytest.mark.blender
def test_only_an_installed_extensions_folder_is_refused(results):
    """A checkout loaded by path (as `make demo` loads it) may write into its own out/; the same folder is refused
    while one of Blender's extension repositories holds the checkout, which Blender would delete on removal."""
    step = _step(results, "extension_folder_guard")
    assert step["checkout"] == "" and step["checkout_again"] == "", step
    assert "inside the extension's folder" in one_sentence(step["installed"]), step
    assert any(folder.endswith("user_default") for folder in step["repositories"]), step["repositories"]


@pytest.mark.blender
def test_the_panel_shows_each_source_and_where_it_paints(results):
    step = _step(results, "panel_draws")
    for state, shown in step.items():
        assert shown[0] == "prop animation_source" and shown[-1] == "operator paint_relief.paint_animation", state
    assert any(line.startswith("label Frames 1 to 4, 64 x 48 px, Cycles") for line in step["SCENE"])
    assert "label The scene has no active camera to render" in step["SCENE no camera"]
    assert "prop animation_dir" in step["SCENE stopped"] and "prop animation_dir" not in step["SCENE"]
    assert any(line.endswith(os.sep + "Shot_NNN") for line in step["SCENE"]), step["SCENE"]
    for source, name in (("IMAGE", "animation_image"), ("FOLDER", "animation_folder"),
                         ("PATTERN", "animation_pattern")):
        assert "prop " + name in step[source], source
    assert not any("_NNN" in line for line in step["FOLDER output"])
