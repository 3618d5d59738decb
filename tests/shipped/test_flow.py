"""The headless flow from the installed zip: paint, canvas, lights, camera, a Cycles render, the comparison.

Runs in the environments `make test-shipped` builds (bpy of one Blender
version, its NumPy, pytest; no PyPI SciPy or OpenImageIO), so every library
the painter uses comes from Blender or from the zip's wheels.
"""

import pytest
from conftest import script_results
from conftest import step as _step


@pytest.fixture(scope="module")
def flow(package_zip, tmp_path_factory):
    return script_results("flow.py", package_zip, tmp_path_factory.mktemp("flow"))


def test_installs_without_importing_the_painter(flow):
    found = flow["install"]
    assert found["result"] == ["FINISHED"] and found["enabled"]
    assert found["imported_at_enable"] == []


def test_libraries_come_from_blender_or_the_zip(flow):
    found = _step(flow, "libraries")
    assert found["problem"] is None
    user = found["user_resources"]
    assert found["scipy_file"].startswith(user), "SciPy must come from the zip's wheel"
    # The SciPy wheel of this Python: 1.15.3 (NumPy 1.24 and later) on 3.11, 1.18.1 (NumPy 2) on 3.13.
    assert found["scipy"] == {(3, 11): "1.15.3", (3, 13): "1.18.1"}[tuple(found["python"])], found
    if tuple(flow["install"]["blender"]) >= (4, 4, 0):
        assert found["openimageio_source"] == "blender", found["openimageio"]
    else:
        assert found["openimageio_source"] == "wheel" and found["openimageio"].startswith(user)


def test_paint(flow):
    found = _step(flow, "paint")
    assert found["result"] == ["FINISHED"], found["error"]
    assert {"color.exr", "height.exr", "opacity.exr", "painting.png"} <= set(found["files"])


def test_panel_paint_leaves_the_process_as_it_found_it(flow):
    before, after = _step(flow, "paint")["process"]
    assert after["environ"] == before["environ"] and after["locale"] == before["locale"]
    if before["malloc"] is not None:  # glibc: its mmap threshold still adapts and was not lowered
        assert after["malloc"]["adapts"] == before["malloc"]["adapts"], (before["malloc"], after["malloc"])
        assert (after["malloc"]["threshold"] or 2 ** 27) >= (before["malloc"]["threshold"] or 2 ** 27)


def test_an_output_folder_inside_the_installed_extension_is_refused(flow):
    found = _step(flow, "output_inside_the_installed_extension")
    assert found["result"] is None and "inside the extension's folder" in found["error"], found
    assert not found["written"], found


def test_canvas_lights_camera(flow):
    found = _step(flow, "stage")
    assert all(result == ["FINISHED"] for result, _ in found["results"].values()), found["results"]
    assert found["canvas_dimensions"] == pytest.approx([0.40, 0.30], abs=0.002)


def test_cycles_render(flow):
    found = _step(flow, "cycles_render")
    assert found["exists"] and found["size"][0] > 0 and found["std"] > 0.01


def test_comparison_with_labels(flow):
    found = _step(flow, "comparison")
    assert found["result"] == ["FINISHED"], found["error"]
    assert {"comparison.png", "correlation.png", "comparison.md", "light_sweep.gif"} <= set(found["files"])
    assert found["label_pixels"] > 100, "the comparison sheet's labels are missing"
    assert found["chart_title_dark_pixels"] > 50, "the chart's title is missing"


# --- scene manners -------------------------------------------------------------------

def test_second_paint_is_refused_while_one_runs(flow):
    found = _step(flow, "second_paint_refused")
    assert found["refused"] is None and "already running" in found["error"]
    assert found["after"] == ["FINISHED"], found["after_error"]


def test_two_default_paintings_both_stay_on_disk(flow):
    found = _step(flow, "default_paintings_keep_their_folders")
    first, second = found["folders"]
    assert first != second and found["both_there"], found
    assert not first.startswith(found["user_resources"]), "paintings must not go to the extension's user folder"


def test_two_canvases_show_two_paintings(flow):
    found = _step(flow, "two_canvases")
    a, b = found["canvases"]
    # Three canvases in all: the one staged earlier from the first painting, and these two.
    assert found["count"] == 3 and a["name"] != b["name"] and a["material"] != b["material"]
    assert [a["colour_file"], b["colour_file"]] == found["folders"]
    assert a["in_art"] and b["in_art"], "new canvases go into the active collection"
    assert b["selected"] and not a["selected"] and found["active"] == b["name"]


def test_rebuild_keeps_transform_modifiers_and_user_nodes(flow):
    found = _step(flow, "rebuild_keeps_user_changes")
    assert found["result"] == ["FINISHED"], found["error"]
    assert found["after"]["matrix"] == pytest.approx(found["before"]["matrix"])
    assert found["before"]["matrix"][3] == pytest.approx(0.3)  # moved, so the check means something
    assert found["after"]["objects"] == found["before"]["objects"]
    assert found["after"]["materials"] == found["before"]["materials"]
    assert found["extra_node"] and found["base_colour_from"] == "My Hue"
    assert found["bevel_kept"] and found["modifiers"].index("Paint Relief Displace") < found["modifiers"].index("My Bevel")
    assert found["displace_strength"] == pytest.approx(0.003)


def test_thickness_and_relief_change_only_the_extensions_nodes(flow):
    found = _step(flow, "user_nodes_keep_their_values")
    for state in ("thicker", "flat", "relief"):
        assert found[state]["My Bump"] == [0.77, 0.05] and found[state]["My Displacement"] == [0.2], found
    assert found["thicker"]["Paint Relief Bump"][1] == pytest.approx(0.002)
    assert found["thicker"]["Paint Relief Displacement"] == [pytest.approx(0.002)]
    assert found["flat"]["Paint Relief Bump"][0] == 0 and found["flat"]["Paint Relief Displacement"] == [0]
    assert found["relief"] == found["thicker"]


def test_agx_stays_agx(flow):
    found = _step(flow, "agx_stays_agx")
    assert found["result"] == ["FINISHED"], found["error"]
    assert found["kept"] == {"view": "AgX", "resolution": [1920, 1080]}
    assert found["changed"] == {"view": "Standard", "resolution": found["map_size"]}


def test_sideways_jpeg_paints_upright(flow):
    found = _step(flow, "exif_sideways_jpeg_paints_upright")
    assert found["result"] == ["FINISHED"], found["error"]
    assert found["shape"] == [48, 24, 3]
    top, bottom = found["top_mean"], found["bottom_mean"]
    assert top[0] > top[2] + 0.3 and bottom[2] > bottom[0] + 0.3, (top, bottom)


def test_command_line_compare(flow):
    found = _step(flow, "command_line")
    assert found["registered"]
    assert (found["bad_input"], found["usage"], found["compare"]) == (1, 2, 0)
    assert {"comparison.png", "correlation.png", "comparison.md", "scene.blend"} <= set(found["files"])


def test_user_world_survives_add_lights_and_a_reload(flow):
    found = _step(flow, "user_world_survives_add_lights_and_reload")
    assert found["result"] == ["FINISHED"], found["error"]
    assert found["before"] == "My World" and found["after_reload"] == "My World"
    assert len(found["lights"]) >= 1


def test_paint_object_paints_a_sphere_from_its_base_color_and_gives_back_its_material(flow):
    found = _step(flow, "paint_object_from_its_base_color")
    assert found["result"] == ["FINISHED"], found["error"]
    assert {"color.exr", "height.exr", "opacity.exr", "report.json", "source.png"} <= set(found["files"])
    assert found["slots"] == ["Paint Relief Sphere"]
    # the Triangulate modifier only where it keeps custom normals exactly (Blender 5.x), addon/objects/relief.py
    assert found["modifiers"] in (["WEIGHTED_NORMAL", "TRIANGULATE", "SUBSURF", "DISPLACE"],
                                  ["WEIGHTED_NORMAL", "SUBSURF", "DISPLACE"])
    assert found["back"] == ["FINISHED"] and found["original"] == ["Generated colour"]


def test_paint_object_offers_smart_uv_project_then_paints_a_bake_with_a_normal_map(flow):
    found = _step(flow, "paint_object_without_uvs_from_a_bake")
    assert found["refused"] is None and "has no UV map: press Smart UV Project" in found["refusal"]
    assert found["unwrapped"] == ["FINISHED"]
    assert found["result"] == ["FINISHED"], found["error"]
    assert {"normal.exr", "source.png"} <= set(found["files"]) and found["modifiers"] == []


def test_paint_object_paints_udim_tiles_and_a_baked_slot_each_from_its_own_source(flow):
    found = _step(flow, "paint_object_of_udim_tiles_and_a_baked_slot")
    assert found["result"] == ["FINISHED"], found["error"]
    assert {"color.s0.1001.exr", "color.s0.1002.exr", "color.s1.exr", "height.s1.exr"} <= set(found["files"])
    assert found["slots"] == ["Paint Relief Tiled box", "Paint Relief Tiled box 2"]
    assert found["tiled"] == ["FILE", "TILED"] and found["displace_uv"] == "Paint Relief Atlas"
    assert found["back"] == ["FINISHED"] and found["original"] == ["Tiles", "Plain"]


def test_paint_scene_paints_the_selection_side_by_side_from_the_zip(flow):
    found = _step(flow, "paint_scene_of_the_selection")
    assert found["result"] == ["FINISHED"], found["error"]
    assert found["painted"] == ["Scene Ball", "Scene Box"] and found["refused"] == {}
    assert found["folders"] == ["Scene Ball", "Scene Box", "paint_scene.json"]
    assert found["slots"] == ["Paint Relief Scene Ball", "Paint Relief Scene Box"]
