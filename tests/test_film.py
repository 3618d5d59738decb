# SPDX-License-Identifier: GPL-3.0-or-later
"""sample_scenes/animate.py end to end on a tiny shot: painted, staged, rendered, lit in 2-D, measured, saved.

The script runs in subprocesses with the bpy module (BLENDER_USER_RESOURCES
in a temporary folder); the saved scene.blend is opened again by
tests/blender/blend_checks.py. The figures of animation.json are recomputed
from the written frames by tests/test_film_statistics.py's kind of check
in core; here the whole run, its files, its scene and its refusals.
"""

import json
import os
from functools import partial
from pathlib import Path

import pytest
from blender_run import need_bpy, run_checks, run_script
from oracles import one_sentence_run
from tiny_shot import FIRST, FRAMES, shot

from core.evaluation.film import read_relit
from core.files import reading

REPO = Path(__file__).resolve().parent.parent
SCRIPT = REPO / "sample_scenes" / "animate.py"
BLEND_CHECKS = REPO / "tests" / "blender" / "blend_checks.py"
NUMBERS = list(range(FIRST, FIRST + FRAMES))
FILM_W, FILM_H = 64, 43  # the tiny shot's 96 x 64 px with a longer side of 64 px


_animate = partial(run_script, SCRIPT)


@pytest.fixture(scope="module")
def end_to_end(tmp_path_factory):
    need_bpy()
    work = tmp_path_factory.mktemp("animate")
    frames = shot(work / "frames")
    out = work / "out"
    first = _animate([frames, "-o", out, "--samples", 2, "--size", 64, "--seed", 4], work)
    assert first.returncode == 0, first.stdout[-3000:] + first.stderr[-3000:]
    painted_bytes = {p.name: p.read_bytes() for p in (out / "painted").glob("*.exr")}
    # Again on the painted folder itself, into another output folder.
    again = _animate([out / "painted", "-o", work / "again", "--samples", 2, "--size", 64, "--azimuth", 0], work)
    assert again.returncode == 0, again.stdout[-3000:] + again.stderr[-3000:]
    return {"work": work, "out": out, "first": first, "again": again, "painted_bytes": painted_bytes,
            "blend": run_checks(BLEND_CHECKS, work, out / "scene.blend", timeout=600)}


@pytest.mark.blender
def test_animate_writes_every_frame_of_both_films(end_to_end):
    out = end_to_end["out"]
    for number in NUMBERS:
        name = "{:04d}.png".format(number)
        for folder in ("relit", "paper", "side_by_side"):
            assert (out / folder / name).is_file(), (folder, name)
        assert read_relit(out / "relit", number).shape == (FILM_H, FILM_W, 3)
        assert reading.read_image(out / "paper" / name).shape == (FILM_H, FILM_W, 3)
        assert (out / "painted" / "height_{:04d}.exr".format(number)).is_file()
    relit = [read_relit(out / "relit", n) for n in NUMBERS]
    assert all(frame.std() > 0.02 for frame in relit), "a relit frame is blank"
    assert abs(relit[0] - relit[-1]).mean() > 0.01, "the relit film does not move"
    for name in ("animation.gif", "animation.json", "animation.md", "scene.blend"):
        assert (out / name).is_file(), name
    assert not [p for p in out.rglob(".*tmp*")], "temporary files left behind"


@pytest.mark.blender
def test_animation_json_holds_both_lightings(end_to_end):
    result = json.loads((end_to_end["out"] / "animation.json").read_text())
    assert result["frames"] == NUMBERS and result["film_size"] == [FILM_W, FILM_H]
    statistics = result["warping_error"]
    for film in ("relit", "paper"):
        assert [e["frame"] for e in statistics[film]["per_frame"]] == NUMBERS[:-1]
        assert statistics[film]["mean"] > 0 and statistics[film]["ratio"] == pytest.approx(
            statistics[film]["mean"] / statistics["footage"]["mean"])
    render = result["render"]
    assert render["samples"] == 2 and len(render["seconds"]) == FRAMES and render["seconds_per_frame"] > 0
    assert result["light"] == {"azimuth_deg": 135.0, "elevation_deg": 30.0}


@pytest.mark.blender
def test_animate_prints_progress_and_its_statistics(end_to_end):
    stdout = end_to_end["first"].stdout
    for number, index in zip(NUMBERS, range(1, FRAMES + 1), strict=True):
        assert "Rendered frame {} ({}/{})".format(number, index, FRAMES) in stdout
        assert "painting frame {} ({}/{})".format(number, index, FRAMES) in stdout
    for step in ("extension", "paint", "scene", "film", "blend", "measures", "total"):
        assert step in stdout.split("Seconds per step:")[1], step
    assert "s per frame at 64 x 43 px" in stdout and "Warping error: footage" in stdout
    assert "Fra:" not in stdout, "Blender's render statistics are hidden"
    again = end_to_end["again"].stdout
    assert "is a painted sequence: using it as it is" in again and "light at 0 degrees" in again


@pytest.mark.blender
def test_a_painted_folder_is_used_as_it_is(end_to_end):
    out, work = end_to_end["out"], end_to_end["work"]
    assert {p.name: p.read_bytes() for p in (out / "painted").glob("*.exr")} == end_to_end["painted_bytes"]
    assert not (work / "again" / "painted").exists()
    result = json.loads((work / "again" / "animation.json").read_text())
    assert result["painted_dir"] == str((out / "painted").resolve()) and result["light"]["azimuth_deg"] == 0.0


@pytest.mark.blender
def test_scene_blend_holds_the_animated_canvas(end_to_end):
    found = end_to_end["blend"]
    assert found["frame_range"] == [FIRST, FIRST + FRAMES - 1]
    assert found["images"] == {"Colour": "SEQUENCE", "Height": "SEQUENCE", "Opacity": "SEQUENCE"}
    assert found["heights_differ"] > 1e-5, found  # the canvas's relief changes between the first and last frame
    assert found["heights_first"] != found["heights_last"]
    render = found["render"]
    assert (render["engine"], render["format"], render["size"], render["samples"]) == ("CYCLES", "PNG", [64, 43], 2)
    assert render["filepath"].endswith(os.path.join("relit", "####"))
    assert len(found["key_lights"]) == 1 and found["camera"]


@pytest.mark.blender
def test_the_movie_where_blender_has_ffmpeg(end_to_end):
    import bpy  # noqa: F401 (only to ask whether this Blender has FFmpeg; the runs were subprocesses)

    out = end_to_end["out"]
    if not bpy.app.build_options.codec_ffmpeg:
        assert not (out / "animation.mp4").exists()
        return
    movie = (out / "animation.mp4").read_bytes()
    assert movie[4:8] == b"ftyp" and len(movie) > 1000
    assert not [p for p in out.iterdir() if p.name.startswith(".movie")]


# --- bad input ----------------------------------------------------------------------

@pytest.mark.blender
def test_bad_input_ends_withone_sentence_run(tmp_path):
    need_bpy()
    empty = tmp_path / "empty"
    empty.mkdir()
    blocker = tmp_path / "a_file"
    blocker.write_text("a file where a folder should be")
    frames = shot(tmp_path / "frames", frames=2)
    out = tmp_path / "out"

    assert "required" in one_sentence_run(_animate([], tmp_path))
    assert "no_such_folder" in one_sentence_run(_animate([tmp_path / "no_such_folder", "-o", out], tmp_path))
    assert not out.exists()
    assert "empty" in one_sentence_run(_animate([empty, "-o", out], tmp_path))
    assert "a_file" in one_sentence_run(_animate([frames, "-o", blocker / "out"], tmp_path))
    run = _animate(["--", frames, "-o", out, "--samples", "0"], tmp_path)
    assert run.returncode == 2 and "at least 1" in one_sentence_run(run)
    run = _animate([frames, "-o", out, "--elevation", "95"], tmp_path)
    assert run.returncode == 2 and "elevation" in one_sentence_run(run)
