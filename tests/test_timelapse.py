"""``core paint --timelapse N``: the painting being painted, as a painted shot's folder committed with the painting."""

import json
from pathlib import Path

import numpy as np
import pytest
from oracles import one_sentence, same_bytes

from core import Params
from core.api import paint_file
from core.cli import main
from core.errors import Cancelled, OutputError, ParameterError
from core.files import reading, shot_files, timelapse, writing
from core.files.maps import CANVAS_MAPS, check_maps
from core.methods.registry import paint
from core.motion.source import STILL_MOTION, two_way_motion
from core.strokes.snapshots import Snapshots, frame_strokes

FRAMES = 6


@pytest.fixture(scope="module")
def photo(tmp_path_factory, half_textured):
    """A 40 x 56 photograph-like image."""
    path = tmp_path_factory.mktemp("input") / "photo.png"
    writing.write_png(path, half_textured(40, 56))
    return path


@pytest.fixture(scope="module")
def painted(photo, tmp_path_factory):
    out = tmp_path_factory.mktemp("painted")
    assert main(["paint", str(photo), "-o", str(out), "-q", "--seed", "3", "--timelapse", str(FRAMES)]) == 0
    return out


def frame_maps(folder, number):
    return {name: reading.read_exr(folder / shot_files.numbered_name(f"{name}.exr", number))[0]
            for name in ("color", "height", "opacity")}


def test_the_timelapse_is_a_shot_folder_of_n_frames(painted):
    folder = painted / timelapse.TIMELAPSE_DIR
    report = shot_files.read_report(folder)
    assert shot_files.is_shot_report(report) and report["complete"]
    assert report["frames"] == list(range(1, FRAMES + 1)) and report["motion"] == STILL_MOTION
    expected = {name for n in report["frames"] for name in shot_files.frame_file_names(n, False)}
    assert {p.name for p in folder.iterdir()} == expected | {"report.json"}
    assert check_maps(folder, [shot_files.numbered_name(m, FRAMES) for m in CANVAS_MAPS]) == (56, 40)
    still = json.loads((painted / "report.json").read_text())
    assert still["timelapse"]["frames"] == FRAMES and still["timelapse"]["strokes"] == still["strokes"]
    strokes = [entry["strokes"] for entry in report["per_frame"]]
    assert strokes[-1] == still["strokes"] and all(a < b for a, b in zip(strokes[:-1], strokes[1:], strict=True))


def test_coverage_never_drops_and_strokes_appear(painted):
    folder = painted / timelapse.TIMELAPSE_DIR
    maps = [frame_maps(folder, n) for n in range(1, FRAMES + 1)]
    for before, after in zip(maps[:-1], maps[1:], strict=True):
        assert np.all(after["opacity"] >= before["opacity"])
    assert maps[0]["opacity"].mean() < maps[-1]["opacity"].mean()
    assert not np.array_equal(maps[0]["color"], maps[-1]["color"])


def test_the_last_frame_is_the_painting(painted):
    last = frame_maps(painted / timelapse.TIMELAPSE_DIR, FRAMES)
    for name in ("color", "height", "opacity"):
        assert np.array_equal(last[name], reading.read_exr(painted / f"{name}.exr")[0]), name
    assert np.array_equal(reading.read_image(painted / timelapse.TIMELAPSE_DIR / "painting_0006.png"),
                          reading.read_image(painted / "painting.png"))


def test_same_bytes_twice_and_the_painting_unchanged(photo, painted, tmp_path):
    again, plain = tmp_path / "again", tmp_path / "plain"
    assert main(["paint", str(photo), "-o", str(again), "-q", "--seed", "3", "--timelapse", str(FRAMES)]) == 0
    same_bytes(painted / timelapse.TIMELAPSE_DIR, again / timelapse.TIMELAPSE_DIR)
    assert main(["paint", str(photo), "-o", str(plain), "-q", "--seed", "3"]) == 0
    for name in ("color.exr", "height.exr", "opacity.exr", "painting.png", "strokes.json"):
        assert (plain / name).read_bytes() == (painted / name).read_bytes(), name


def test_catching_the_canvas_changes_no_stroke(half_textured):
    image = half_textured(40, 56)
    for method in ({"method": "huang11"}, {"method": "hertzmann98"}, {"renderer": "lines"}):
        params = Params(seed=2, **method)
        caught = Snapshots(image.shape[:2], 4)
        alone, with_snapshots = paint(image, params), paint(image, params, snapshots=caught)
        assert caught.count == len(alone.strokes)
        for name in ("colour", "height", "opacity", "coverage"):
            assert np.array_equal(getattr(alone, name), getattr(with_snapshots, name)), (method, name)


def test_frames_are_spread_over_the_strokes():
    assert frame_strokes(100, 4, 16) == [16, 48, 64, 100]
    assert frame_strokes(3, 5, 1) == [1, 1, 2, 2, 3]
    shown = frame_strokes(6692, 100, 64)
    assert len(shown) == 100 and shown[-1] == 6692 and all(a < b for a, b in zip(shown[:-1], shown[1:], strict=True))
    assert all(abs(s - round(k * 6692 / 100)) < 64 for k, s in enumerate(shown[:-1], start=1))


@pytest.mark.parametrize("frames", ["0", "1001", "-3", "ten", "2.5"])
def test_bad_frame_counts_are_refused_in_one_sentence(photo, tmp_path, capsys, frames):
    with pytest.raises(SystemExit) as exit_info:
        main(["paint", str(photo), "-o", str(tmp_path / "out"), "-q", "--timelapse", frames])
    assert exit_info.value.code == 2
    assert "from 1 to 1000" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("frames", [0.5, 1001, True, "4"])
def test_bad_frame_counts_are_refused_by_the_api(photo, tmp_path, frames):
    with pytest.raises(ParameterError) as error:
        paint_file(photo, tmp_path / "out", Params(), timelapse=frames)
    one_sentence(str(error.value))
    assert not (tmp_path / "out").exists()


def test_a_stopped_run_leaves_no_timelapse(photo, painted, tmp_path):
    out = tmp_path / "out"
    calls = {"n": 0}

    def cancel():
        calls["n"] += 1
        return calls["n"] > 3

    with pytest.raises(Cancelled):
        paint_file(photo, out, Params(seed=3), cancel=cancel, timelapse=FRAMES)
    assert not out.exists()


def test_a_failed_write_leaves_the_folder_as_it_was(photo, painted, tmp_path, monkeypatch):
    import shutil

    out = tmp_path / "out"
    shutil.copytree(painted, out)
    before = {p.relative_to(out): p.read_bytes() for p in out.rglob("*") if p.is_file()}
    real = timelapse.FrameFiles.write

    def failing(files, folder, number, *args):
        if number == 4:
            raise OutputError(f"Cannot write {folder / 'color_0004.exr'}: no space is left on the device.")
        return real(files, folder, number, *args)

    monkeypatch.setattr(timelapse.FrameFiles, "write", failing)
    with pytest.raises(OutputError) as error:
        paint_file(photo, out, Params(seed=4), timelapse=FRAMES)
    one_sentence(str(error.value))
    assert {p.relative_to(out): p.read_bytes() for p in out.rglob("*") if p.is_file()} == before


def test_a_new_timelapse_replaces_the_old_one(photo, painted, tmp_path):
    import shutil

    out = tmp_path / "out"
    shutil.copytree(painted, out)
    paint_file(photo, out, Params(seed=3), timelapse=3)
    report = shot_files.read_report(out / timelapse.TIMELAPSE_DIR)
    assert report["frames"] == [1, 2, 3]
    assert not (out / timelapse.TIMELAPSE_DIR / "color_0006.exr").exists()
    assert [p.name for p in out.iterdir() if p.name.startswith(".")] == []


def test_a_file_in_the_way_is_refused_before_painting(photo, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / timelapse.TIMELAPSE_DIR).write_text("mine")
    with pytest.raises(OutputError) as error:
        paint_file(photo, out, Params(), timelapse=2)
    one_sentence(str(error.value), naming=out / timelapse.TIMELAPSE_DIR)
    assert (out / timelapse.TIMELAPSE_DIR).read_text() == "mine" and not (out / "report.json").exists()


def test_a_still_has_no_motion():
    picture = np.zeros((4, 5, 3), np.float32)
    forward, backward = two_way_motion(picture, picture, STILL_MOTION)
    assert forward.shape == (4, 5, 2) and not forward.any() and not backward.any()


@pytest.fixture(scope="module")
def blender_results(tmp_path_factory, half_textured):
    from blender_run import need_bpy, run_checks

    need_bpy()
    work = tmp_path_factory.mktemp("timelapse_blender")
    writing.write_png(work / "photo.png", half_textured(40, 56))
    return run_checks(Path(__file__).parent / "blender" / "timelapse_checks.py", work, work)


@pytest.mark.blender
def test_the_panel_paints_a_timelapse_that_build_canvas_animates(blender_results):
    from blender_run import step

    painted = step(blender_results, "paint")
    assert painted["result"] == ["FINISHED"] and "color_0003.exr" in painted["files"]
    built = step(blender_results, "build")
    assert built["result"] == ["FINISHED"] and built["sequence"] == [1, 3] and built["frame_range"] == [1, 3]
    assert built["heights"]["3"] > built["heights"]["1"]


def test_a_run_cancelled_while_writing_frames_leaves_the_folder_as_it_was(photo, painted, tmp_path):
    import shutil

    out = tmp_path / "out"
    shutil.copytree(painted, out)
    before = {p.relative_to(out): p.read_bytes() for p in out.rglob("*") if p.is_file()}

    def cancel():
        return any(out.glob(f".staging-*/{timelapse.TIMELAPSE_DIR}/color_0002.exr"))

    with pytest.raises(Cancelled) as stopped:
        paint_file(photo, out, Params(seed=4), cancel=cancel, timelapse=FRAMES)
    one_sentence(str(stopped.value))
    assert {p.relative_to(out): p.read_bytes() for p in out.rglob("*") if p.is_file()} == before


def test_half_tables_convert_as_the_writers_do():
    from core.colour import srgb_to_linear

    linear, png = timelapse.half_tables()
    values = np.random.default_rng(1).random((30, 40, 3)).astype(np.float16)
    assert np.array_equal(linear[values.view(np.uint16)],
                          srgb_to_linear(values.astype(np.float32)).astype(np.float16))
    quantised = np.floor(values.astype(np.float32) * np.float32(255.0) + np.float32(0.5)).astype(np.uint8)
    assert np.array_equal(png[values.view(np.uint16)], quantised)


def test_an_old_timelapse_left_aside_by_a_killed_commit_is_removed(photo, tmp_path):
    from core.files.staging import RETIRED_PREFIX

    out = tmp_path / "out"
    left = out / f"{RETIRED_PREFIX}.staging-1-00-{timelapse.TIMELAPSE_DIR}"
    left.mkdir(parents=True)
    (left / "color_0001.exr").write_bytes(b"old")
    paint_file(photo, out, Params(seed=3), timelapse=2)
    assert not left.exists() and (out / timelapse.TIMELAPSE_DIR / "color_0002.exr").is_file()


def test_the_free_space_check_counts_the_timelapse(photo, tmp_path, monkeypatch, capsys):
    """Room for the painting alone, not for its frames: refused before painting, naming what it needs."""
    import shutil as shutil_module

    import core.methods.registry
    from core.files import budget

    width, height = reading.probe(photo)[:2]
    alone = budget.estimate_output_bytes(width, height)
    frames = budget.estimate_output_bytes(width, height, timelapse_bytes=50 * timelapse.FRAME_BYTES_PER_PIXEL)
    assert frames == alone + width * height * 50 * 13
    free = alone + (frames - alone) // 2
    monkeypatch.setattr(shutil_module, "disk_usage", lambda path: shutil_module._ntuple_diskusage(1 << 30, 1 << 30,
                                                                                                  free))
    out = tmp_path / "out"
    with monkeypatch.context() as refused:
        refused.setattr(core.methods.registry, "paint", lambda *a, **k: pytest.fail("painting started"))
        assert main(["paint", str(photo), "-o", str(out), "-q", "--timelapse", "50"]) == 2
    err = capsys.readouterr().err
    assert "not enough space" in err and err.count("\n") == 1 and not out.exists()
    assert main(["paint", str(photo), "-o", str(out), "-q"]) == 0
