"""sample_scenes/world_scene.py: the animated painted-world test set is built, saved and read back with its objects,
its photographs packed, one image shared, a procedural colour to bake, a moving camera and ball, and every object
in view."""

import json
import subprocess
import sys
from pathlib import Path

import pytest
from blender_run import need_bpy, run_script, user_env

SCRIPT = Path(__file__).resolve().parents[1] / "sample_scenes" / "world_scene.py"

CHECKS = r'''
import json, os, sys
import bpy
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Vector

bpy.ops.wm.open_mainfile(filepath=sys.argv[1])
scene = bpy.context.scene


def images(material):
    """The names of the images of ``material``'s Image Texture nodes, and whether each has pixels to read."""
    found = {}
    for node in material.node_tree.nodes:
        if node.bl_idname == "ShaderNodeTexImage" and node.image is not None:
            image = node.image
            path = bpy.path.abspath(image.filepath)
            found[image.name] = image.packed_file is not None or (bool(image.filepath) and os.path.isfile(path))
    return found


def base_color_source(material):
    """The kind of node linked to the Principled BSDF's Base Color, or None."""
    shader = next(n for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    links = shader.inputs["Base Color"].links
    return links[0].from_node.bl_idname if links else None


def view(frame):
    """Each mesh's bounding box corners and centre in the camera's view at ``frame``: (x, y, depth) each."""
    scene.frame_set(frame)
    seen = {}
    for thing in scene.objects:
        if thing.type == "MESH":
            corners = [thing.matrix_world @ Vector(c) for c in thing.bound_box]
            centre = sum(corners, Vector()) / 8.0
            seen[thing.name] = {"corners": [list(world_to_camera_view(scene, scene.camera, c)) for c in corners],
                                "centre": list(world_to_camera_view(scene, scene.camera, centre))}
    return seen


def matrices(frame):
    scene.frame_set(frame)
    return {thing.name: [round(v, 6) for row in thing.matrix_world for v in row] for thing in scene.objects}


meshes = {}
for thing in scene.objects:
    if thing.type != "MESH":
        continue
    materials = [slot.material for slot in thing.material_slots if slot.material is not None]
    meshes[thing.name] = {
        "uv_maps": len(thing.data.uv_layers),
        "materials": [m.name for m in materials],
        "images": {name: ok for m in materials for name, ok in images(m).items()},
        "base_color": [base_color_source(m) for m in materials],
        "smooth": any(p.use_smooth for p in thing.data.polygons),
    }
first, last = scene.frame_start, scene.frame_end
render = scene.render
results = {
    "meshes": meshes,
    "hidden": [t.name for t in scene.objects if t.hide_render or t.hide_get()],
    "camera": scene.camera.name if scene.camera else None,
    "lights": [t.data.type for t in scene.objects if t.type == "LIGHT"],
    "world": scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value if scene.world else None,
    "frames": [first, last], "fps": render.fps / render.fps_base,
    "engine": render.engine, "size": [render.resolution_x, render.resolution_y, render.resolution_percentage],
    "vector": bpy.context.view_layer.use_pass_vector, "motion_blur": render.use_motion_blur,
    "view_transform": scene.view_settings.view_transform,
    "first": matrices(first), "last": matrices(last), "middle": view((first + last) // 2),
    "every_frame": {f: matrices(f) for f in range(first, last + 1)},
}
print("RESULTS " + json.dumps(results))
'''


def build_and_read(work: Path, name: str, *options) -> dict:
    """Build the scene into ``work/name`` with ``options``, reopen it in a process of its own and return what
    it holds."""
    blend = work / name
    built = run_script(SCRIPT, ["-o", blend, *options], work, timeout=120)
    assert built.returncode == 0 and blend.is_file(), built.stdout[-2000:] + built.stderr[-2000:]
    read = subprocess.run([sys.executable, "-c", CHECKS, str(blend)], capture_output=True, text=True,
                          timeout=120, env=user_env(work), cwd=work)
    lines = [line for line in read.stdout.splitlines() if line.startswith("RESULTS ")]
    assert read.returncode == 0 and lines, read.stdout[-2000:] + read.stderr[-2000:]
    return json.loads(lines[-1][len("RESULTS "):])


@pytest.fixture(scope="module")
def world(tmp_path_factory):
    need_bpy()
    return build_and_read(tmp_path_factory.mktemp("world"), "scene.blend")


def test_four_or_more_unwrapped_meshes_with_materials_three_photographs_packed_one_shared_one_to_bake(world):
    meshes = world["meshes"]
    assert len(meshes) >= 4
    assert all(m["materials"] and m["uv_maps"] >= 1 for m in meshes.values())
    with_images = {name for name, m in meshes.items() if m["images"]}
    assert len(with_images) >= 3
    assert all(all(m["images"].values()) for m in meshes.values())        # packed, or a file that exists
    assert all(m["base_color"] == ["ShaderNodeTexImage"] for name, m in meshes.items() if name in with_images)
    baked = [m for m in meshes.values() if not m["images"]]
    assert baked and all(set(m["base_color"]) <= {"ShaderNodeTexVoronoi", "ShaderNodeTexNoise"} for m in baked)
    users = {}
    for name, m in meshes.items():
        for image in m["images"]:
            users.setdefault(image, set()).add(name)
    assert max(len(names) for names in users.values()) >= 2
    assert meshes["Ball"]["smooth"] and meshes["Column"]["smooth"] and not meshes["Crate"]["smooth"]
    assert {"Ground", "Wall", "Crate", "Column", "Ball"} <= set(meshes) and world["hidden"] == []


def test_the_camera_and_the_ball_move_and_nothing_else_does(world):
    moved = {name for name in world["first"] if world["first"][name] != world["last"][name]}
    assert moved == {world["camera"], "Ball"}


def test_every_object_is_in_view_at_the_middle_frame(world):
    for name, seen in world["middle"].items():
        x, y, depth = seen["centre"]
        assert 0.0 < x < 1.0 and 0.0 < y < 1.0 and depth > 0.0, name
        if name != "Ground":                                               # the ground runs out of the frame
            assert all(0.0 <= x <= 1.0 and 0.0 <= y <= 1.0 and depth > 0.0 for x, y, depth in seen["corners"]), name


def test_render_settings_cycles_640_by_360_at_24_fps_with_the_vector_pass_and_a_sun(world):
    assert world["engine"] == "CYCLES" and world["size"] == [640, 360, 100]
    assert world["frames"] == [1, 24] and world["fps"] == 24.0
    assert world["vector"] and not world["motion_blur"] and world["view_transform"] == "Standard"
    assert world["lights"] == ["SUN"] and 0.0 < world["world"] < 1.0


def test_the_same_command_builds_the_same_scene_and_frames_sets_its_length(world, tmp_path):
    need_bpy()
    again = build_and_read(tmp_path, "again.blend")
    assert again["every_frame"] == world["every_frame"] and again["meshes"] == world["meshes"]
    short = build_and_read(tmp_path, "short.blend", "--frames", "6")
    assert short["frames"] == [1, 6] and short["first"] == world["first"]
    assert short["last"]["Ball"] == world["last"]["Ball"]               # the same path, faster
