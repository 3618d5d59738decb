# SPDX-License-Identifier: GPL-3.0-or-later
"""The animated canvas (addon/scene/animated.py): a painted sequence's maps as image sequences that follow the frame.

tests/blender/animated_checks.py paints three frames of a tiny shot (96 x 64 px,
frames 11 to 14, a checkered ball crossing a striped background) with the painter's
``core.paint_sequence_files``, builds the canvas with the Build Canvas
operator and checks it in one subprocess (``bpy`` can be imported once per
process; BLENDER_USER_RESOURCES in a temporary folder); each test asserts on
one of its findings. The pure helpers of addon/values.py are tested without Blender.
"""

import json
from pathlib import Path

import pytest
from addon_values import values
from blender_run import need_bpy, run_checks
from blender_run import step as _step
from tiny_shot import HEIGHT, WIDTH, shot

from core.files import shot_files

REPO = Path(__file__).resolve().parent.parent
HELPER = REPO / "tests" / "blender" / "animated_checks.py"


# --- pure helpers -------------------------------------------------------------

def test_map_names_number_frames_as_the_painter_does():
    assert shot_files.numbered_name("color.exr", 1) == "color_0001.exr"
    assert shot_files.numbered_name("height.exr", 16) == "height_0016.exr"
    assert shot_files.numbered_name("opacity.exr", 12345) == "opacity_12345.exr"


def test_sequence_frames_reads_a_sequence_report_only(tmp_path):
    assert values.sequence_frames(tmp_path) is None  # no report
    (tmp_path / "report.json").write_text(json.dumps({"strokes": 10, "files": {}}))
    assert values.sequence_frames(tmp_path) is None  # a still painting's report
    (tmp_path / "report.json").write_text("{ not json")
    assert values.sequence_frames(tmp_path) is None
    (tmp_path / "report.json").write_text(json.dumps({"sequence": "abc", "frames": [3, 4, 5]}))
    assert values.sequence_frames(tmp_path) == [3, 4, 5]


# --- inside Blender ---------------------------------------------------------------

@pytest.fixture(scope="module")
def results(tmp_path_factory):
    need_bpy()
    work = tmp_path_factory.mktemp("animated")
    shot(work / "frames")
    return run_checks(HELPER, work, work)


@pytest.mark.blender
def test_build_canvas_on_a_sequence_makes_image_sequences(results):
    step = _step(results, "build")
    assert step["result"] == ["FINISHED"], step["error"]
    assert step["sequence"] == [11, 3]
    assert {label: node["file"] for label, node in step["nodes"].items()} == {
        "Colour": "color_0011.exr", "Height": "height_0011.exr", "Opacity": "opacity_0011.exr"}
    for reader in (*step["nodes"].values(), step["displace"]):
        # Scene frame N shows painted frame N: the file number is (N - start + 1) + offset.
        assert (reader["source"], reader["duration"], reader["start"], reader["offset"], reader["auto"]) == (
            "SEQUENCE", 3, 11, 10, True), reader
    assert step["displace"]["file"] == "height_0011.exr"
    assert step["frame_range"] == [1, 250], "the scene's frame range is left alone unless asked"
    assert step["dimensions"] == pytest.approx([0.40, 0.40 * HEIGHT / WIDTH], abs=1e-6)


@pytest.mark.blender
def test_evaluated_heights_follow_the_scenes_frame(results):
    step = _step(results, "heights_follow_the_frame")
    means = [step[str(frame)]["z_mean"] for frame in (11, 12, 13)]
    assert len(set(means)) == 3, means
    for frame in (11, 12, 13):
        correlation = step[str(frame)]["correlation"]
        # The vertices stand on the height map of the frame shown, not on another frame's.
        assert correlation[str(frame)] > 0.9, (frame, correlation)
        assert all(correlation[str(frame)] > value + 0.05 for key, value in correlation.items() if key != str(frame))
        assert step[str(frame)]["z_max"] <= 0.002 * 1.5 + 1e-6  # 2 mm per height unit
    assert step["17"] == step["13"], "after the sequence the canvas holds its last frame"
    assert step["10"]["z_max"] == 0.0, "before it there is no file to show, as for any image sequence"


@pytest.mark.blender
def test_frame_range_is_set_only_on_request(results):
    step = _step(results, "frame_range_on_request")
    assert step["result"] == ["FINISHED"], step["error"]
    assert step["frame_range"] == [11, 13]


@pytest.mark.blender
def test_rebuild_keeps_the_users_transform_modifier_and_nodes(results):
    step = _step(results, "rebuild_keeps_the_users_changes")
    assert step["result"] == ["FINISHED"], step["error"]
    assert step["after"]["matrix"] == pytest.approx(step["before"]["matrix"])
    assert step["before"]["matrix"][11] == pytest.approx(0.3)  # moved, so the check means something
    assert (step["after"]["objects"], step["after"]["materials"], step["after"]["images"]) == (
        step["before"]["objects"], step["before"]["materials"], step["before"]["images"])
    assert step["bevel_kept"] and step["user_node_kept"]
    assert step["colour_source"] == "SEQUENCE" and step["sequence"] == [11, 3]
    assert step["heights"]["correlation"]["12"] > 0.9


@pytest.mark.blender
def test_reload_maps_takes_the_frames_painted_since(results):
    step = _step(results, "reload_takes_frames_painted_since")
    assert step["result"] == ["FINISHED"], step["error"]
    assert step["sequence"] == [11, 4] and step["durations"] == [4]
    assert step["heights"]["correlation"]["14"] > 0.9
    assert step["heights"]["correlation"]["14"] > step["heights"]["correlation"]["13"] + 0.05


@pytest.mark.blender
def test_a_broken_sequence_is_refused_in_one_sentence(results):
    step = _step(results, "refusals")
    missing = step["missing_frame"]
    assert missing["result"] is None and "opacity_0012.exr" in missing["error"] and not missing["changed"]
    normals = step["no_normal_maps"]
    assert normals["result"] is None and "normal_0011.exr" in normals["error"] and not normals["changed"]
    for found in (missing, normals):
        assert "Traceback" not in found["error"] and len(found["error"].strip().splitlines()) == 1
    assert step["canvas_still_a_sequence"]


@pytest.mark.blender
def test_a_sequence_painted_with_normal_maps_makes_a_normal_map_canvas(results):
    step = _step(results, "normal_map_sequence")
    assert step["result"] == ["FINISHED"], step["error"]
    assert step["readers"] == [[name + "_0011.exr", "SEQUENCE", 2, 11]
                               for name in ("color", "height", "normal", "opacity")]
    assert step["modifiers"] == []  # a flat plane shaded by the normal maps


@pytest.mark.blender
def test_cycles_renders_each_frames_colour(results):
    errors = _step(results, "colour_renders_follow_the_frame")["mean_squared_error"]
    assert errors["11"]["11"] < 1e-3 and errors["14"]["14"] < 1e-3, errors
    assert errors["11"]["14"] > 4 * errors["11"]["11"] and errors["14"]["11"] > 4 * errors["14"]["14"], errors
