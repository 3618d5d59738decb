"""Paint Object reads UVs as Blender does (tests/blender/uv_rule_checks.py): a plane beyond the UV square 0..1 under
an image set to Repeat paints the bytes of the plane inside it, under Clip or Extend it is one sentence, and an image
read through a second UV map is painted in that map."""

from pathlib import Path

import pytest
from blender_run import need_bpy, run_checks
from blender_run import step as _step

HELPER = Path(__file__).resolve().parent / "blender" / "uv_rule_checks.py"
pytestmark = pytest.mark.blender

REFUSAL = ("No face of the mesh covers a texel of the texture: its UV map is empty, or lies outside the square 0..1 "
           "where its image does not repeat (Clip or Extend).")


@pytest.fixture(scope="module")
def found(tmp_path_factory):
    need_bpy()
    work = tmp_path_factory.mktemp("uv_rules")
    return run_checks(HELPER, work, work)


def test_a_plane_at_u_1_to_2_under_repeat_paints_the_bytes_of_the_plane_at_0_to_1(found):
    planes = _step(found, "plane_beyond_the_square")
    home, far = planes["Home"], planes["Far"]
    assert home["result"] == far["result"] == ["FINISHED"], (home["error"], far["error"])
    assert far["extensions"] == ["REPEAT"] and far["uv_maps"] == [None]
    assert far["digests"] == home["digests"] and len(far["digests"]) == 3
    assert [cell["extension"] for cell in far["cells"]] == ["REPEAT"]
    assert far["slots"] == ["Paint Relief Far"]


@pytest.mark.parametrize("name, rule", [("Clipped", "CLIP"), ("Extended", "EXTEND")])
def test_a_plane_at_u_1_to_2_under_clip_or_extend_is_one_sentence_and_writes_nothing(found, name, rule):
    plane = _step(found, "plane_beyond_the_square")[name]
    assert plane["extensions"] == [rule]
    assert plane["result"] is None and not plane["exists"]
    assert plane["error"].strip() == "Error: " + REFUSAL
    assert plane["slots"] == [name]                         # the object keeps its own material


def test_an_image_read_through_a_second_uv_map_is_painted_in_that_map(found):
    grid = _step(found, "second_uv_map")
    assert grid["result"] == ["FINISHED"], grid["error"]
    assert grid["uv_maps"] == ["UVMap.001"] and grid["slot_uv_maps"] == ["UVMap.001"]
    assert grid["extensions"] == ["REPEAT"] and grid["render_map"] == "UVMap"
    assert grid["triangles_in_second"] and grid["differs_from_render_map"]
    assert grid["r_second"] > 0.7                            # the painting follows the picture through UVMap.001
    assert grid["opacity_second"] > 0 and grid["opacity_first"] == 0     # and the rendered map's texels are bare
    assert grid["missing"].strip() == ("Error: Material Second's Base Color image blocks.png is read through UV map "
                                       "Missing, which object Grid does not have: choose one of its UV maps in the UV "
                                       "Map node, then paint.")


def test_an_image_read_through_nodes_is_painted_where_those_nodes_read_it(found):
    chains = _step(found, "vector_chains")
    points = [[0.0, 0.0], [0.5, 0.25], [1.5, 0.75], [2.25, -0.5]]
    flat = [value for point in chains["mapped"] for value in point]
    assert flat == pytest.approx([value for u, v in points for value in (2 * u + 0.25, 3 * v)])  # scale, then move
    assert chains["mapped_map"] == "UVMap" and chains["mapped_feed"][1] == "Vector"
    flat = [value for point in chains["mirrored"] for value in point]
    assert flat == pytest.approx([0.0, 0.0, 0.5, 0.25, 0.5, 0.75, 0.25, -0.5])
    assert chains["noisy"] and chains["plain"]             # a Noise texture is not followed: that source is baked
