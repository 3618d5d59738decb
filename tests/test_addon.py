# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's operators inside Blender: paint, build the canvas, light it, frame it, render it.

tests/blender/addon_checks.py runs every step in one subprocess (``bpy`` can
be imported once per process; BLENDER_USER_RESOURCES points at a temporary
folder) and prints its findings as JSON; each test here asserts on one step.
The pure helpers of addon/values.py are tested without Blender.
"""

import math
import os
from pathlib import Path

import numpy as np
import pytest
from addon_values import values
from blender_run import need_bpy, run_checks
from blender_run import step as _step

REPO = Path(__file__).resolve().parent.parent
HELPER = REPO / "tests" / "blender" / "addon_checks.py"


# --- pure helpers -------------------------------------------------------------

def test_parse_sizes():
    assert values.parse_sizes("64,32,16,8,4") == (64, 32, 16, 8, 4)
    assert values.parse_sizes(" 12  6, 3 ") == (12, 6, 3)
    for bad, word in (("", "empty"), ("64,x", "'x'"), ("8,-2", "-2"), ("8,0", "0")):
        with pytest.raises(ValueError, match=word):
            values.parse_sizes(bad)


def test_canvas_size_keeps_the_aspect():
    assert values.canvas_size(640, 480, 40.0) == pytest.approx((0.40, 0.30))
    assert values.canvas_size(480, 640, 30.0) == pytest.approx((0.30, 0.40))


def test_grid_resolution_and_cap():
    assert values.grid_resolution(64, 48) == (33, 25)
    nx, ny = values.grid_resolution(4000, 3000, max_vertices=300_000)
    assert nx * ny <= 300_000 and abs(nx / ny - 4 / 3) < 0.01


def test_grid_arrays():
    co, loops, starts, uv = values.grid_arrays(3, 2, 2.0, 1.0)
    co = co.reshape(-1, 3)
    assert co[:, 0].min() == -1.0 and co[:, 0].max() == 1.0 and co[:, 1].min() == -0.5 and co[:, 1].max() == 0.5
    assert len(loops) == 2 * 4 and list(starts) == [0, 4]
    uv = uv.reshape(-1, 2)
    # Each loop's UV is its vertex's position mapped to [0, 1]^2.
    assert np.allclose(uv, co[loops, :2] / [2.0, 1.0] + 0.5)
    # Quads run counter-clockwise seen from +z: positive signed area.
    quad = co[loops[:4], :2]
    area = 0.5 * sum(quad[i - 1, 0] * quad[i, 1] - quad[i, 0] * quad[i - 1, 1] for i in range(4))
    assert area > 0


def test_light_direction_convention():
    assert values.light_direction(0.0, 0.0) == pytest.approx((1.0, 0.0, 0.0))
    # 90 degrees is the image's bottom edge, which lies along -y in Blender.
    assert values.light_direction(math.pi / 2, 0.0) == pytest.approx((0.0, -1.0, 0.0), abs=1e-12)
    assert values.light_direction(0.3, math.pi / 2) == pytest.approx((0.0, 0.0, 1.0), abs=1e-12)


def test_wave_scale_for_period():
    """Blender's Wave Texture (bands, sine profile) at scale s is 0.5 + 0.5 sin(20 s x - pi/2) along its axis:
    one band every 2 pi / (20 s) units, so a band every millimetre is s = 2 pi / 0.02 = 100 pi."""
    assert values.wave_scale_for_period(0.001) == pytest.approx(100 * math.pi, rel=1e-12)
    assert values.wave_scale_for_period(0.0008) == pytest.approx(125 * math.pi, rel=1e-12)
    scale = values.wave_scale_for_period(0.002)
    bands = [0.5 + 0.5 * math.sin(20 * scale * x - math.pi / 2) for x in (0.0, 0.0005, 0.001, 0.002, 0.003)]
    assert bands == pytest.approx([0.0, 0.5, 1.0, 0.0, 1.0], abs=1e-9)  # trough, rising, crest, trough, crest


# --- inside Blender ---------------------------------------------------------------

@pytest.fixture(scope="module")
def results(tmp_path_factory):
    need_bpy()
    work = tmp_path_factory.mktemp("addon")
    found = run_checks(HELPER, work, work, "--render")
    found["work"] = str(work)
    return found


@pytest.mark.blender
def test_settings_match_the_painter_and_buttons_wait(results):
    step = _step(results, "settings_defaults")
    for name, (setting, default) in step["params"].items():
        assert setting == pytest.approx(default), name  # Blender stores floats in single precision
    assert step["canvas_width_cm"] == 40.0 and step["thickness_mm"] == 2.0
    assert not step["poll_paint_without_image"]
    assert not step["poll_canvas_without_painting"]
    assert not step["poll_camera_without_canvas"]


@pytest.mark.blender
def test_paint_writes_the_maps(results):
    step = _step(results, "paint")
    assert step["result"] == ["FINISHED"], step["error"]
    for name in ("color.exr", "height.exr", "opacity.exr", "report.json"):
        assert name in step["files"]
    assert os.path.samefile(step["painting_dir"], os.path.join(results["work"], "painted"))


@pytest.mark.blender
def test_missing_photo_is_reported_and_changes_nothing(results):
    step = _step(results, "missing_photo")
    assert step["result"] is None
    assert "no_such_photo.png" in step["error"] and "does not exist" in step["error"]
    assert "Traceback" not in step["error"]
    assert step["before"] == step["after"] and step["painting_dir"] == ""


@pytest.mark.blender
def test_unreadable_or_missing_map_is_reported_and_changes_nothing(results):
    step = _step(results, "unreadable_map")
    assert step["result"] is None and step["broken_file"] in step["error"], step["error"]
    assert step["missing_result"] is None and step["missing_file"] in step["missing_error"]
    for text in (step["error"], step["missing_error"]):
        assert "Traceback" not in text
    assert step["before"] == step["after"]


EXPECTED_LINKS = {
    ("ShaderNodeTexImage", "Color", "ShaderNodeBsdfPrincipled", "Base Color"),
    ("ShaderNodeBsdfPrincipled", "BSDF", "ShaderNodeOutputMaterial", "Surface"),
    ("ShaderNodeTexImage", "Color", "ShaderNodeDisplacement", "Height"),
    ("ShaderNodeBump", "Normal", "ShaderNodeBsdfPrincipled", "Normal"),
    ("ShaderNodeMapRange", "Result", "ShaderNodeBsdfPrincipled", "Roughness"),
    ("ShaderNodeTexImage", "Color", "ShaderNodeMapRange", "Value"),
    ("ShaderNodeTexCoord", "UV", "ShaderNodeTexImage", "Vector"),
}
DISPLACEMENT_LINK = ("ShaderNodeDisplacement", "Displacement", "ShaderNodeOutputMaterial", "Displacement")


@pytest.mark.blender
def test_mesh_canvas_size_material_and_relief(results):
    step = _step(results, "canvas_mesh")
    assert step["result"] == ["FINISHED"], step["error"]
    assert step["dimensions"] == pytest.approx([0.40, 0.30], abs=1e-5)
    links = {tuple(link) for link in step["links"]}
    assert EXPECTED_LINKS <= links, EXPECTED_LINKS - links
    # MESH: the modifier displaces; the material output's Displacement stays free (no double relief).
    assert DISPLACEMENT_LINK not in links and step["displacement_method"] == "BUMP"
    images = {v["file"]: v for v in step["images"].values()}
    assert images["color.exr"]["colorspace"] in ("Linear Rec.709", "Linear")
    assert images["height.exr"]["is_data"] and images["opacity.exr"]["is_data"]
    assert images["height.exr"]["interpolation"] == "Cubic"
    assert all(v["extension"] == "EXTEND" for v in images.values())
    assert step["displacement_inputs"] == pytest.approx({"midlevel": 0.0, "scale": 0.002})
    assert step["modifiers"] == [["DISPLACE", pytest.approx(0.002), 0.0, "UV"]]
    # the mesh samples the map at its vertices: compare the 1st-99th percentile spans (the thinnest
    # ridges fall between vertices)
    z_extent = step["z_percentiles"][1] - step["z_percentiles"][0]
    height_extent = 0.002 * (step["height_percentiles"][1] - step["height_percentiles"][0])
    assert height_extent > 0
    assert z_extent == pytest.approx(height_extent, rel=0.10)
    assert step["z_range"][1] - step["z_range"][0] <= 0.002 * (step["height_range"][1] - step["height_range"][0]) * 1.02


@pytest.mark.blender
def test_building_again_updates_the_same_canvas(results):
    step = _step(results, "canvas_again_adaptive")
    assert step["result"] == ["FINISHED"], step["error"]
    assert len(step["canvases"]) == 1 and step["before"] == step["after"]
    assert DISPLACEMENT_LINK in {tuple(link) for link in step["links"]}
    assert step["displacement_method"] in ("DISPLACEMENT", "BOTH")
    assert step["modifiers"] == ["SUBSURF"] and step["adaptive"] is True and step["engine"] == "CYCLES"
    assert step["back_to_mesh"] == ["FINISHED"] and step["modifiers_after"] == ["DISPLACE"]


@pytest.mark.blender
def test_a_normal_map_canvas_makes_its_normal_map_from_the_height_map(results):
    step = _step(results, "canvas_normal_map")
    assert not step["had_normals"]                       # the painter writes normal.exr only when asked
    assert step["result"] == ["FINISHED"], step["error"]
    assert step["normal_shape"][:2] == [48, 64] and step["normal_z_min"] > 0.5   # encoded n.z = 0.5 + 0.5 z > 0.5
    assert ("ShaderNodeNormalMap", "Normal", "ShaderNodeBump", "Normal") in {tuple(link) for link in step["links"]}
    assert step["reload"] == ["FINISHED"], step["reload_error"]
    assert step["reloaded_normals_match"]                 # made again for the repainted height map
    assert step["back_to_mesh"] == ["FINISHED"]


@pytest.mark.blender
def test_lights_are_updated_not_duplicated(results):
    step = _step(results, "lights")
    assert step["results"] == [["FINISHED"]] * 3
    assert step["first"] == step["second"] and step["first"]["lights"] == 2
    assert step["no_fill"]["lights"] == 1
    az, el = step["azimuth"], step["elevation"]
    towards = [math.cos(el) * math.cos(az), -math.cos(el) * math.sin(az), math.sin(el)]
    assert step["key_towards_light"] == pytest.approx(towards, abs=1e-5)
    assert step["world"] == "Paint Relief World"


@pytest.mark.blender
def test_camera_frames_the_canvas(results):
    step = _step(results, "camera")
    assert step["result"] == ["FINISHED"] and step["again"] == ["FINISHED"]
    assert step["first"] == step["second"] and step["first"]["cameras"] == 1
    assert step["type"] == "ORTHO" and step["ortho_scale"] == pytest.approx(0.40)
    assert step["sensor_fit"] == "HORIZONTAL" and step["resolution"] == [64, 48]
    assert step["view"] == ["Standard", "None", 0.0, 1.0]


@pytest.mark.blender
def test_render_reproduces_the_colour_map(results):
    step = _step(results, "colour_render")
    assert step["size"] == [128, 96]
    assert step["psnr"] >= 30.0, step
    assert step["psnr_upside_down"] < 20.0  # the check can tell a flipped canvas


@pytest.mark.blender
def test_unregister_removes_everything(results):
    assert results["unregistered"] == {"scene_property": False, "operator": False, "panel": False}
