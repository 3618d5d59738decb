"""The catalogue of odd meshes and scenes: every case is painted or refused in one sentence naming the object,
image or file at fault, with nothing half-written (tests/blender/object_catalogue.py), and the sample script's
own cases (a file that is no .blend, a curve, an object outside the view layer, Ctrl-C)."""

import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from blender_run import need_bpy, run_checks, user_env
from blender_run import step as _step

HELPER = Path(__file__).resolve().parent / "blender" / "object_catalogue.py"
SCRIPT = Path(__file__).resolve().parents[1] / "sample_scenes" / "paint_object.py"
RELIEF = ["Paint Relief Normals", "Paint Relief Triangles", "Paint Relief Subdivision", "Paint Relief Displace"]
UNWRAP = "unwrap it (Smart UV Project in the Paint Object panel), then paint."

PAINTED = ("uvs_overlapping", "uvs_outside_the_unit_square", "uvs_partly_outside",
           "uvs_wholly_outside_the_unit_square", "unused_empty_material_slot", "zero_area_faces",
           "concave_ngons", "one_triangle", "mesh_of_100k_faces", "negative_scale", "non_uniform_scale",
           "packed_image", "generated_image", "png_of_16_bits", "float_exr", "transparent_png",
           "material_with_use_nodes_off", "material_with_no_nodes", "no_material_painted_from_a_file",
           "hidden_object", "hidden_object_baked", "subdivision_catmull_clark", "mirror_modifier", "array_modifier",
           "solidify_modifier", "users_own_displace_modifiers", "shape_keys_and_armature", "painted_twice",
           "painted_over_an_earlier_painting", "texture_of_8k_on_a_tiny_mesh")
"""The cases that paint."""

REFUSED = {
    "ctrl_c_while_the_sources_are_read": "Painting Interrupted was stopped: its maps were not written and the object "
                                         "is as it was.",
    "no_uv_map": "Object NoUVs has no UV map: press Smart UV Project in the Paint Object panel to unwrap it, then "
                 "paint.",
    "uvs_all_at_one_point": "Object Collapsed's UV map UVMap has no area: its faces lie on a point or a line in UV "
                            "space; " + UNWRAP,
    "only_zero_area_faces": "Object Flat's UV map UVMap has no area: its faces lie on a point or a line in UV "
                            "space; " + UNWRAP,
    "faces_collapsed_to_a_point": "Object Point's faces have no area to paint: they lie on a point or a line.",
    "loose_geometry_only": "Object Wires has no faces to paint.",
    "missing_image_file": "Image Lost's file {work}/nowhere/lost.png does not exist: find it (File > External Data > "
                          "Find Missing Files) or choose another image, then paint.",
    "no_material": "Object Naked has no material, so there is no colour to bake: give it a material or choose a "
                   "texture file.",
    "empty_material_slot": "Object EmptySlot has no material, so there is no colour to bake: give it a material or "
                           "choose a texture file.",
    "texture_file_missing": "Texture {work}/nowhere/picture.png does not exist.",
    "curve_object": "Object Bezier is a curve: Paint Object paints meshes; convert it to a mesh (Object > Convert > "
                    "Mesh) first.",
    "text_object": "Object Title is a text object: Paint Object paints meshes; convert it to a mesh (Object > "
                   "Convert > Mesh) first.",
    "empty_object": "Object Pivot is an empty, which has no surface to paint: Paint Object paints meshes.",
    "no_active_object": "There is no active object: click the mesh object to paint, then press Paint Object.",
    "collection_excluded_from_the_view_layer": "There is no active object: click the mesh object to paint, then "
                                               "press Paint Object.",
    "edit_mode": "Object Editing is in Edit Mode: switch to Object Mode, then paint.",
    "mesh_shared_by_two_objects": "Object First shares its mesh Cube with object Twin: make it a single user (Object "
                                  "> Relation > Make Single User > Object & Data) to paint it alone.",
    "output_path_is_a_file": "Cannot write to output folder {work}/cases/output_path_is_a_file/taken.txt: a file of "
                             "that name is in the way.",
}
"""The cases refused, and their one sentence."""


@pytest.fixture(scope="module")
def catalogue(tmp_path_factory):
    need_bpy()
    work = tmp_path_factory.mktemp("catalogue")
    started = time.perf_counter()
    found = run_checks(HELPER, work, work, timeout=900)
    found["_seconds"] = time.perf_counter() - started
    found["_work"] = str(work)
    return found


def test_the_catalogue_holds_forty_cases_and_each_is_painted_or_refused(catalogue):
    cases = {name for name in catalogue if not name.startswith("_")} - {"scenes_for_the_sample_script"}
    assert cases == set(PAINTED) | set(REFUSED) | {"cancelled_midway"}
    assert len(cases) + len(SCRIPT_CASES) >= 40
    print("catalogue: {} cases in {:.0f} s".format(len(cases), catalogue["_seconds"]))


@pytest.mark.parametrize("name", PAINTED)
def test_a_case_that_paints_writes_the_maps_and_the_object_wears_the_painting(catalogue, name):
    found = _step(catalogue, name)
    assert found["result"] == ["FINISHED"], found["error"]
    assert found["maps"] and found["wears_painting"] and found["leftovers"] == []
    assert found["painted_material"].startswith("Paint Relief ")
    if name != "painted_twice":
        assert found["originals"] == found["originals_before"]          # the original materials are kept
    relief = [modifier.removesuffix(".001") for modifier in found["relief"]]   # beside a user's of that name
    assert relief == RELIEF and found["modifiers"][-4:] == found["relief"]


@pytest.mark.parametrize("name", sorted(REFUSED))
def test_a_refused_case_is_one_sentence_naming_what_is_at_fault_and_writes_nothing(catalogue, name):
    found = _step(catalogue, name)
    expected = REFUSED[name].format(work=catalogue["_work"])
    assert found["result"] is None and found["one_sentence"], found["error"]
    assert found["sentence"] == expected
    assert found["look_kept"] and found["leftovers"] == []
    if name == "output_path_is_a_file":
        assert found["file_kept"]
        return
    assert found["folder_absent"]                                      # no folder of its own left behind
    assert found["again"] is None and found["same_sentence"]           # into an earlier painting's folder:
    assert found["earlier_kept"] and found["look_kept_again"]          # every byte of it and the user's file kept
    assert found["leftovers_again"] == []


def test_uvs_outside_the_square_are_clipped_to_it_and_the_texture_is_covered(catalogue):
    found = _step(catalogue, "uvs_outside_the_unit_square")
    assert found["opacity_covered"] == 1.0                              # the square's texels all painted


def test_modifiers_are_painted_as_the_surface_they_make_and_stay_first(catalogue):
    for name, factor in (("subdivision_catmull_clark", 16), ("mirror_modifier", 2), ("array_modifier", 3),
                         ("solidify_modifier", 2)):
        found = _step(catalogue, name)
        assert found["user_modifiers_first"], name
        assert found["seen_triangles"] >= factor * found["base_triangles"], name


def test_the_users_own_displace_modifiers_are_never_taken_for_the_relief(catalogue):
    found = _step(catalogue, "users_own_displace_modifiers")
    assert found["modifiers"][:2] == ["Displace", "Paint Relief Displace"]
    assert found["relief"][-1] == "Paint Relief Displace.001"
    assert found["user_strengths"] == pytest.approx([0.05, 0.01])
    assert found["toggled"] and found["user_shown"] == [True, True] and found["relief_hidden"] == [False] * 4


def test_the_relief_follows_the_armature_and_the_shape_key(catalogue):
    poses = _step(catalogue, "shape_keys_and_armature")["poses"]
    assert poses[1]["top_y"] > poses[0]["top_y"] + 0.05                 # the bone turned the column
    assert poses[1]["radius"] > poses[0]["radius"]                      # the shape key swelled it
    for pose in poses:
        assert 1.0 < pose["relief_mm"] <= 50.0 * 1.1                    # and the relief rides on it


def test_a_second_painting_is_painted_from_the_original_source(catalogue):
    found = _step(catalogue, "painted_twice")
    assert found["first"]["result"] == ["FINISHED"]
    assert found["input"] == found["first"]["input"] and found["input"].endswith("coffee.png")
    assert found["originals"] == ["Coffee"] == found["first"]["originals"]


def test_esc_midway_writes_nothing_and_leaves_the_object_as_it_was(catalogue):
    found = _step(catalogue, "cancelled_midway")
    assert found["outcome"] == ["CANCELLED"] and not found["running"]
    assert found["folder_absent"] and found["look_kept"] and found["leftovers"] == []
    assert found["reports"] == [["WARNING", "Painting Cancelled was stopped: its maps were not written and the "
                                            "object is as it was."]]


def test_a_hidden_object_is_painted_and_stays_hidden(catalogue):
    assert _step(catalogue, "hidden_object_baked")["still_hidden"]


def test_a_painting_over_an_earlier_one_keeps_the_users_file(catalogue):
    assert _step(catalogue, "painted_over_an_earlier_painting")["notes_kept"]


def test_the_100k_face_mesh_and_the_8k_photograph_paint_in_bounded_time(catalogue):
    mesh = _step(catalogue, "mesh_of_100k_faces")
    assert mesh["faces"] > 100_000 and mesh["seconds"] < 60
    photo = _step(catalogue, "texture_of_8k_on_a_tiny_mesh")
    assert photo["default_size"] == 2048 and photo["width"] == 2048 and photo["seconds"] < 150
    print("100k faces: {:.1f} s at 128 texels; 8K photograph: {:.1f} s at 2048".format(mesh["seconds"],
                                                                                      photo["seconds"]))


def test_no_traceback_reached_the_output(catalogue):
    assert all("Traceback" not in found.get("error", "") for found in catalogue.values() if isinstance(found, dict))


def test_a_material_without_an_image_is_baked_and_its_nodes_are_left_as_they_were(catalogue):
    for name in ("material_with_use_nodes_off", "material_with_no_nodes", "hidden_object_baked"):
        found = _step(catalogue, name)
        assert found["input"].endswith("source.png") and "source.png" in found["files"], name
    assert _step(catalogue, "material_with_use_nodes_off")["nodes_kept"]
    assert _step(catalogue, "material_with_no_nodes")["nodes_left"] == []


# --- the sample script ------------------------------------------------------------------------------------------

SCRIPT_CASES = ("not_a_blend", "curve", "excluded", "ctrl_c_new_folder", "ctrl_c_earlier_painting")


def script(args, work, **options):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True, text=True,
                          timeout=600, cwd=work, env=user_env(work), **options)


def refused_in_one_sentence(run, sentence, code=1):
    assert run.returncode == code, run.stderr[-3000:]
    assert "Traceback" not in run.stderr and "Traceback" not in run.stdout
    assert run.stderr.strip().splitlines()[-1] == sentence


def test_the_sample_script_refuses_a_file_that_is_no_blend_in_one_sentence(tmp_path):
    need_bpy()
    fake = tmp_path / "notes.blend"
    fake.write_text("not a Blender file")
    run = script([fake, "-o", tmp_path / "out"], tmp_path)
    assert run.returncode == 1 and "Traceback" not in run.stderr + run.stdout, run.stderr[-3000:]
    last = run.stderr.strip().splitlines()[-1]
    assert last.startswith("Blender ") and last.endswith(f" cannot open the scene {fake}: it is not a .blend file, "
                                                         f"or one this Blender cannot read.")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("scene, name, sentence", [
    ("curve.blend", "Box", "Object Box is a curve: Paint Object paints meshes; convert it to a mesh (Object > "
                           "Convert > Mesh) first."),
    ("excluded.blend", "Excluded", "Object Excluded is not in view layer ViewLayer: include its collection, then "
                                   "paint.")])
def test_the_sample_script_names_an_object_it_cannot_paint(catalogue, tmp_path, scene, name, sentence):
    run = script([Path(catalogue["_work"]) / "scenes" / scene, "--object", name, "-o", tmp_path / "out",
                  "--texture-size", "1024"], tmp_path)
    refused_in_one_sentence(run, sentence)
    assert not (tmp_path / "out").exists()


def interrupted(args, work):
    """Run the sample script; send it SIGINT a moment after it starts painting; return (process, stdout, stderr)."""
    process = subprocess.Popen([sys.executable, str(SCRIPT), *map(str, args)], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True, cwd=work, env=user_env(work))
    lines = []
    for line in process.stdout:
        lines.append(line)
        if line.startswith("[paint]"):
            time.sleep(1.5)
            process.send_signal(signal.SIGINT)
            break
    out, err = process.communicate(timeout=600)
    return process, "".join(lines) + out, err


@pytest.mark.parametrize("earlier", [False, True], ids=["new_folder", "earlier_painting"])
def test_ctrl_c_in_the_sample_script_is_one_sentence_and_nothing_half_written(catalogue, tmp_path, earlier):
    out = tmp_path / "out"
    if earlier:
        shutil.copytree(Path(catalogue["_work"]) / "earlier", out / "maps")
    before = {path: path.read_bytes() for path in out.rglob("*") if path.is_file()}
    # 2048 texels: the demo box paints for many seconds, so the signal 1.5 s in lands while it paints
    process, stdout, stderr = interrupted(["-o", out, "--texture-size", "2048", "--views", "2"], tmp_path)
    assert process.returncode != 0 and "Traceback" not in stderr + stdout, stderr[-3000:]
    last = stderr.strip().splitlines()[-1]
    assert last in ("Painting Box was stopped: its maps were not written and the object is as it was.",
                    f"Interrupted (Ctrl-C) in the paint step: the folder {out} it made was removed.",
                    f"Interrupted (Ctrl-C) in the paint step: {out} is as it was."), stderr[-3000:]
    if earlier:
        assert {path: path.read_bytes() for path in out.rglob("*") if path.is_file()} == before
    else:
        assert not out.exists()

