"""Paint Object inside Blender: a textured sphere painted with displacement and back to its own material, a mesh
without UVs refused, unwrapped and painted from a bake with a normal map (tests/blender/object_checks.py)."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from addon_values import values
from blender_run import need_bpy, run_checks
from blender_run import step as _step

HELPER = Path(__file__).resolve().parent / "blender" / "object_checks.py"
RELIEF = [["Paint Relief Normals", "WEIGHTED_NORMAL"], ["Paint Relief Triangles", "TRIANGULATE"],
          ["Paint Relief Subdivision", "SUBSURF"], ["Paint Relief Displace", "DISPLACE"]]
MAPS = {"color.exr", "height.exr", "opacity.exr", "orientation.exr", "painting.png", "report.json", "strokes.json"}


@pytest.fixture(scope="module")
def found(tmp_path_factory):
    need_bpy()
    work = tmp_path_factory.mktemp("objects")
    return run_checks(HELPER, work, work)


def test_a_sphere_is_painted_from_its_base_color_image_and_displaced_by_its_relief(found):
    sphere = _step(found, "sphere_painted")
    assert sphere["result"] == ["FINISHED"], sphere["error"]
    assert MAPS <= set(sphere["files"]) and sphere["input"].endswith("chelsea.png")
    assert sphere["width"] == 1024 and sphere["islands"] == 1
    assert sphere["slots"] == ["Paint Relief Sphere"]
    assert sphere["modifiers"] == RELIEF
    assert sphere["displace_uv"] == "UVMap" and sphere["strength"] == pytest.approx(0.002)
    assert sphere["render_levels"] == values.relief_levels(32 * 16, 1024)


def test_the_original_material_comes_back_with_one_toggle_and_the_painting_with_another(found):
    toggled = _step(found, "original_material_back")
    assert toggled["back"] == ["FINISHED"] and toggled["original"] == ["Photo"]
    assert toggled["relief_shown"] == [False] * len(RELIEF)
    assert toggled["again"] == ["FINISHED"] and toggled["painted"] == ["Paint Relief Sphere"]
    assert toggled["relief_again"] == [True] * len(RELIEF)
    assert toggled["thicker"] == pytest.approx([0.004, 0.004])      # the panel's thickness reaches the object


def test_the_relief_can_be_cycles_material_displacement_over_an_adaptive_subdivision_and_back(found):
    sphere = _step(found, "sphere_with_cycles_displacement")
    assert sphere["modifiers"] == [["Paint Relief Subdivision", "SUBSURF"]] and sphere["adaptive"]
    assert sphere["method"] == "DISPLACEMENT" and sphere["displacement_linked"] == ["ShaderNodeDisplacement"]
    assert sphere["then_modifiers"] == RELIEF
    assert sphere["then_linked"] == [] and sphere["then_method"] == "BUMP"


def test_painting_keeps_the_shape_and_the_smooth_or_flat_shading_and_only_the_paint_adds_relief(found):
    kept = _step(found, "shape_and_shading_kept")
    relief = [name for name, _ in RELIEF]
    monkey, cube = kept["monkey"], kept["cube"]
    assert monkey["modifiers"] == ["Twist"] + relief and kept["twist_angle"] == pytest.approx(0.3)
    # Relief 0: at each face's centre the painted Suzanne shades as the original's interpolated smooth normals
    # (a simple subdivision shading each low-poly face flat gave 18.3 degrees on average, 45.7 at the 95th percentile)
    assert monkey["faces"] > 4000 and monkey["mean"] < 1.0 and monkey["p95"] < 3.0
    assert cube["modifiers"] == relief and cube["mean"] < 0.1 and cube["p95"] < 0.1
    assert cube["axis_stray"] < 0.1 and cube["off_surface"] < 1e-5        # still a cube, its faces flat
    assert monkey["moved_mm"] > 1.0 and cube["moved_mm"] > 1.0             # the paint's relief moves the surface
    assert kept["custom"]["modifiers"] == relief[1:] and kept["custom"]["lowest_up"] > 0.999   # the user's normals


def test_paint_object_with_hertzmann_1998_is_one_sentence_and_writes_nothing_and_the_panel_says_so(found):
    refused = _step(found, "sphere_with_hertzmann_1998")
    assert refused["refused"] is None and not refused["output_exists"]
    assert refused["error"].strip() == ("Error: Objects are painted with the paper's method (Huang 2011, huang11); "
                                        "Hertzmann 1998 (hertzmann98) paints still images only.")
    assert "Objects are painted with the paper's method: choose Huang 2011 in Paint" in refused["labels"]["HERTZMANN98"]
    assert "The Paint panel's painter settings apply" in refused["labels"]["HUANG11"]


def test_a_mesh_without_a_uv_map_is_one_sentence_offering_smart_uv_project_which_unwraps_it(found):
    monkey = _step(found, "monkey_without_uvs")
    assert monkey["refused"] is None
    assert monkey["error"].strip() == ("Error: Object Suzanne has no UV map: press Smart UV Project in the Paint "
                                       "Object panel to unwrap it, then paint.")
    assert monkey["unwrapped"] == ["FINISHED"] and monkey["uv_maps"] == ["UVMap"]


def test_a_mesh_whose_colour_is_no_image_is_painted_from_a_bake_and_shaded_by_a_normal_map(found):
    monkey = _step(found, "monkey_baked_with_a_normal_map")
    assert monkey["result"] == ["FINISHED"], monkey["error"]
    assert MAPS | {"normal.exr", "source.png"} <= set(monkey["files"]) and monkey["input_is_the_kept_source"]
    assert monkey["bake_share_orange"] > 0.3                   # its UV islands hold its Base Color
    assert monkey["engine_kept"] and monkey["images_left"] == []
    assert monkey["modifiers"] == [] and monkey["normal_map_uv"] == ["UVMap"]


def test_a_second_painting_is_painted_from_the_original_source_never_from_the_first_painting(found):
    again = _step(found, "painted_again_from_the_original")
    sphere, monkey = again["sphere"], again["monkey"]
    assert sphere["result"] == ["FINISHED"], sphere["error"]
    assert sphere["input"].endswith("chelsea.png") and sphere["same_colours"]      # same seed: the same colours
    assert sphere["slots"] == ["Paint Relief Sphere"] and sphere["relief_shown"] == [True] * len(RELIEF)
    assert monkey["result"] == ["FINISHED"], monkey["error"]
    assert monkey["input"].endswith("monkey_again/source.png") and monkey["same_colours"]
    assert monkey["bake_share_orange"] > 0.3 and again["images_left"] == []   # a bake of the orange original
    assert monkey["slots"] == ["Paint Relief Suzanne"]


def test_a_refused_run_changes_nothing_in_the_scene_or_the_folder_and_leaves_no_new_folder(found):
    refused = _step(found, "refused_changes_nothing")
    assert refused["painted"] == ["FINISHED"], refused["error"]
    assert refused["refused"] is None and refused["refusal"].strip() == (
        "Error: Object Cube has no material, so there is no colour to bake: give it a material or choose a "
        "texture file.")
    assert MAPS | {"notes.txt"} <= set(refused["files"]) and refused["folder_kept"]   # bytes and names alike
    assert refused["look_kept"] and refused["slots"] == ["Paint Relief Cube"]
    assert refused["refused_new"] is None and not refused["new_folder_exists"]


def test_the_original_material_and_the_painting_survive_save_and_reopen_and_a_disabled_extension(found):
    kept = _step(found, "saved_and_reopened")
    assert {"Photo", "Paint Relief Sphere"} <= set(kept["materials"]) and kept["shows_painting"]
    assert kept["back"] == ["FINISHED"] and kept["original"] == ["Photo"]
    assert kept["tree_after"] == kept["tree_before"] and kept["tree_after"]["image"] == "chelsea.png"
    assert kept["relief_shown"] == [False] * len(RELIEF)
    assert kept["painted_kept"] == "Paint Relief Sphere"                  # saved while the original showed
    assert kept["again"] == ["FINISHED"] and kept["painted"] == ["Paint Relief Sphere"]
    assert kept["relief_again"] == [True] * len(RELIEF)
    assert kept["disabled_kept"] == ["Photo", "Paint Relief Sphere"]
    assert kept["duplicate_original"] == ["Photo"]
    assert kept["legacy_original"] == ["Photo"] and kept["legacy_adopted"] == [False, "Photo", True]


def test_each_material_slot_and_udim_tile_is_painted_from_its_own_source_and_worn_by_its_slot(found):
    both = _step(found, "texture_set_of_two_materials_and_udim_tiles")
    ball, cube = both["set_ball"], both["set_cube"]
    assert ball["result"] == ["FINISHED"], ball["error"]
    assert {"color.s0.exr", "color.s1.exr", "height.s1.exr", "opacity.s0.exr"} <= set(ball["files"])
    assert ball["slots"] == ["Paint Relief Sphere", "Paint Relief Sphere 2"] and ball["colour_sources"] == ["FILE"]
    assert min(ball["r"].values()) >= 0.7, ball["r"]                  # each slot from its own photograph
    assert cube["result"] == ["FINISHED"], cube["error"]
    assert {"color.s0.1001.exr", "color.s0.1002.exr", "height.s0.1002.exr"} <= set(cube["files"])
    assert cube["slots"] == ["Paint Relief Cube"] and cube["colour_sources"] == ["TILED"]
    assert cube["r"]["0"] >= 0.7, cube["r"]                            # both tiles, each from its own
    for found in (ball, cube):                                         # the relief reads the atlas
        assert found["uv_maps"] == ["UVMap", "Paint Relief Atlas"] and found["render_uv"] == "UVMap"
        assert found["displace_uv"] == "Paint Relief Atlas" and found["back"] == ["FINISHED"]
    assert ball["original"] == ["Lower", "Upper"] and cube["original"] == ["Tiles"]
    assert both["reopened"] == {"Sphere": ["Paint Relief Sphere", "Paint Relief Sphere 2"],
                                "Cube": ["Paint Relief Cube"]}
    assert {"Lower", "Upper", "Tiles"} <= set(both["materials"])      # the originals kept through save


def test_relief_levels_give_about_a_vertex_for_every_four_by_four_texels():
    assert values.relief_levels(1024, 1024) == 3               # 1024 x 4^3 = 65536 faces for 256^2 texels
    assert values.relief_levels(6, 2048) == 6                  # a cube: at most 6 levels
    assert values.relief_levels(10 ** 6, 1024) == 0
    assert values.parse_widths(" 32, 16 8") == (32.0, 16.0, 8.0) and values.parse_widths("") is None
    with pytest.raises(ValueError, match="'x' is not a number of millimetres"):
        values.parse_widths("8,x")
    with pytest.raises(ValueError, match="-2 must be a positive number"):
        values.parse_widths("8,-2")


def test_the_headless_script_paints_the_demo_box_films_it_three_ways_and_measures_the_films(tmp_path):
    """sample_scenes/paint_object.py on its demo scene: the maps, three turntable films and side by side, the
    islands' texels 4x apart, and the warping error of each film from view to view by the Vector pass. A refused
    run leaves no folder it made, and the folder of an earlier painting (with the user's own files) as it was."""
    need_bpy()
    script = Path(__file__).resolve().parents[1] / "sample_scenes" / "paint_object.py"
    run = subprocess.run([sys.executable, str(script), "-o", str(tmp_path / "out"), "--views", "3", "--samples", "2",
                          "--resolution", "48", "--texture-size", "1024", "--relief", "CYCLES_ADAPTIVE"],
                         capture_output=True, text=True,
                         timeout=600, cwd=tmp_path, env=dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "user")))
    assert run.returncode == 0, run.stderr[-3000:]
    out = tmp_path / "out"
    summary = json.loads((out / "object.json").read_text())
    assert summary["relief"] == "CYCLES_ADAPTIVE"
    spans = sorted(island["texel_mm"] for island in summary["islands"])
    assert len(spans) == 6 and spans[-1] / spans[0] == pytest.approx(4.0, rel=0.01)
    for film in ("relit", "paper", "original", "side_by_side"):
        assert sorted(p.name for p in (out / "turntable" / film).iterdir()) == ["0001.png", "0002.png", "0003.png"]
    for film in ("relit", "paper", "original"):
        errors = summary["warping_error"][film]
        assert len(errors) == 2 and all(0 <= error < 0.1 for error in errors), (film, errors)
    assert summary["relit_over_original"] == pytest.approx(summary["mean_warping_error"]["relit"]
                                                           / summary["mean_warping_error"]["original"])
    for film in ("relit", "paper", "original"):                 # the box's islands are its faces: all seams
        steps = summary["render_seam_steps"][film]
        assert steps["samples"]["seam"] > 0 and steps["samples"]["inner"] == 0 and 0 < steps["seam"] < 1
    texture = summary["texture_seam_steps"]                     # its faces' two triangles share a diagonal each
    assert texture["edges"] == {"seam": 12, "inner": 6}
    source, painted = texture["source"], texture["painted"]     # each face shows its own part of the photograph
    assert source["seam"] > 3 * source["inner"] and painted["seam"] == pytest.approx(source["seam"], rel=0.25)
    assert (out / "scene.blend").is_file() and (out / "maps" / "color.exr").is_file()
    refused = subprocess.run([sys.executable, str(script), str(tmp_path / "none.blend"), "-o", str(tmp_path / "x")],
                             capture_output=True, text=True, timeout=600, cwd=tmp_path,
                             env=dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "user")))
    assert refused.returncode == 1 and refused.stderr.strip().endswith(f"The scene {tmp_path / 'none.blend'} does "
                                                                       f"not exist.")
    assert not (tmp_path / "x").exists()                        # a refused run leaves no folder it made
    (out / "maps" / "normal.exr").mkdir()                       # the user's folder where the painter must write
    (out / "maps" / "normal.exr" / "mine.txt").write_text("the user's own file")
    before = {path: path.read_bytes() for path in out.rglob("*") if path.is_file()}
    refused = subprocess.run([sys.executable, str(script), "-o", str(out), "--views", "2", "--texture-size", "1024",
                              "--relief", "NORMAL_MAP"], capture_output=True, text=True, timeout=600, cwd=tmp_path,
                             env=dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "user")))
    assert refused.returncode == 1 and refused.stderr.strip().endswith(
        f"Cannot write {out / 'maps' / 'normal.exr'}: a folder of that name is in the way."), refused.stderr[-3000:]
    assert {path: path.read_bytes() for path in out.rglob("*") if path.is_file()} == before   # the earlier painting
