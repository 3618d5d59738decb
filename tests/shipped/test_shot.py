"""The shot flow from the installed zip: the scene's 4-frame animation painted, the animated canvas, two
Cycles frames, the ``animate`` command (tests/shipped/shot.py), on every Blender `make test-shipped` builds."""

import pytest
from conftest import script_results
from conftest import step as _step

FIRST, FRAMES = 11, 4
NAMES = ["{:04d}.png".format(n) for n in range(FIRST, FIRST + FRAMES)]


@pytest.fixture(scope="module")
def shot(package_zip, tmp_path_factory):
    return script_results("shot.py", package_zip, tmp_path_factory.mktemp("shot"))


def test_paint_animation_paints_the_scenes_animation(shot):
    assert shot["install"]["result"] == ["FINISHED"] and shot["install"]["enabled"]
    assert shot["libraries"]["problem"] is None
    found = _step(shot, "paint_the_scenes_animation")
    assert found["result"] == ["FINISHED"], found["error"]
    assert found["frames"] == list(range(FIRST, FIRST + FRAMES)) and found["motion"] == "vector pass"
    assert found["files"] == ["height_{:04d}.exr".format(n) for n in range(FIRST, FIRST + FRAMES)]
    assert found["painting_dir"].endswith("scene_painted")


def test_the_animated_canvas_follows_the_frame(shot):
    found = _step(shot, "animated_canvas")
    assert found["result"] == ["FINISHED"], found["error"]
    assert found["frame_range"] == [FIRST, FIRST + FRAMES - 1]
    # Colour, height and opacity nodes and the Displace modifier's texture: image sequences shown frame by frame.
    assert len(found["readers"]) == 4, found["readers"]
    for reader in found["readers"]:
        assert (reader["source"], reader["duration"], reader["start"], reader["offset"], reader["auto"]) == (
            "SEQUENCE", FRAMES, FIRST, FIRST - 1, True), reader
    assert found["height_max"] > 0 and found["heights_differ"] > 1e-5, found
    assert found["same_frame_again"] == 0.0


def test_two_frames_render_with_cycles(shot):
    found = _step(shot, "two_cycles_frames")
    assert all(result == ["FINISHED"] for result, _ in found["results"]), found["results"]
    assert found["shape"] == [48, 64, 3] and min(found["std"]) > 0.02
    assert found["difference"] > 0.01, "the two rendered frames are the same"


def test_the_animate_command(shot):
    found = _step(shot, "animate_command")
    assert (found["code"], found["bad"]) == (0, 1)
    assert found["relit"] == NAMES and found["paper"] == NAMES
    assert {"animation.gif", "animation.json", "animation.md", "scene.blend"} <= set(found["files"])
    assert ("animation.mp4" in found["files"]) == found["movie_available"]
