# SPDX-License-Identifier: GPL-3.0-or-later
"""Run Paint Scene inside Blender (the bpy module) and print what it did, for tests/test_paint_scene.py.

    BLENDER_USER_RESOURCES=/tmp/x python tests/blender/scene_paint_checks.py WORK_DIR

What the camera sees: a camera at (0, -10, 0) looking along +y over frames
1-5; a box ahead of it, one far to its side, one behind it, one hidden from
renders and one that moves into the picture only in the last frame. The
size of a pixel of a perspective and of an orthographic camera, against the
sensor and lens arithmetic. Then a scene of the demo box, a second box with
a mesh of its own wearing the same photograph, a ball whose colour is a
noise texture (baked) and a plane without a UV map, painted at 128 texels:
every object but the plane is painted, the plane is named in its sentence,
the two boxes share one painting, and the stroke widths are the still's for
the render at the size of a pixel at the median depth. Painted again, every
texture is kept; the selection alone paints only what is selected.
"""

import json
import math
import os
import statistics
import sys

from recorder import REPO, RESULTS, check, load_extension

WORK = os.path.abspath(sys.argv[1])
bpy = load_extension(WORK)
sys.path.insert(0, os.path.join(REPO, "sample_scenes"))
import object_scene  # noqa: E402 (after bpy)
import paint_relief  # noqa: E402
from paint_relief.addon.objects import ops_scene_paint, scene_view  # noqa: E402


def cube(name, location):
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=location)
    obj = bpy.context.active_object
    obj.name = name
    return obj


def camera_at(location, rotation, kind="PERSP"):
    scene = bpy.context.scene
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(camera)
    camera.location, camera.rotation_euler = location, rotation
    camera.data.type = kind
    scene.camera = camera
    return camera


@check
def seen_over_the_frames():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 640, 360, 100
    scene.frame_start, scene.frame_end = 1, 5
    camera_at((0.0, -10.0, 0.0), (math.pi / 2, 0.0, 0.0))
    cube("Ahead", (0.0, 0.0, 0.0))
    cube("Aside", (60.0, 0.0, 0.0))
    cube("Behind", (0.0, -20.0, 0.0))
    cube("Hidden", (1.0, 0.0, 0.0)).hide_render = True
    late = cube("Late", (40.0, 0.0, 0.0))
    late.keyframe_insert("location", frame=4)
    late.location = (0.0, 0.0, 2.0)
    late.keyframe_insert("location", frame=5)
    scene.frame_set(2)
    depths = scene_view.seen_meshes(scene, bpy.context.view_layer, scene_view.scanned_frames(1, 5))
    return {"seen": list(depths), "ahead": depths.get("Ahead"), "late": depths.get("Late"),
            "frame_after": scene.frame_current, "scanned_long": len(scene_view.scanned_frames(1, 1000)),
            "scanned_ends": scene_view.scanned_frames(1, 1000)[::len(scene_view.scanned_frames(1, 1000)) - 1]}


@check
def pixel_size():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 640, 360, 50
    camera = camera_at((0.0, -10.0, 0.0), (math.pi / 2, 0.0, 0.0))
    camera.data.lens, camera.data.sensor_width, camera.data.sensor_fit = 50.0, 36.0, "AUTO"
    perspective = scene_view.pixel_mm(scene, 10.0)
    camera.data.type, camera.data.ortho_scale = "ORTHO", 6.0
    return {"perspective": perspective, "orthographic": scene_view.pixel_mm(scene, 10.0),
            "render": list(scene_view.render_size(scene))}


PHOTO_SCENE = os.path.join(WORK, "photo_scene.blend")


def photo_scene():
    """The demo box, a second box (a mesh of its own) wearing the same photograph, a ball of baked noise, a plane
    without a UV map, a sun and a camera; returns the scene. Built once and saved, then opened: Blender's
    primitives may list their faces in another order each time they are made, and the order of a mesh's
    triangles is part of what a painting is painted from."""
    if os.path.isfile(PHOTO_SCENE):
        bpy.ops.wm.open_mainfile(filepath=PHOTO_SCENE)
        bpy.context.scene.paint_relief.scene_output_dir = os.path.join(WORK, "scene")
        return bpy.context.scene
    bpy.ops.wm.read_factory_settings(use_empty=True)
    box = object_scene.build()
    scene = bpy.context.scene
    twin = box.copy()
    twin.data = box.data.copy()
    twin.name = "Box Twin"
    twin.location.x -= 1.0
    scene.collection.objects.link(twin)
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.3, location=(1.0, 0.0, 0.3), segments=24, ring_count=12)
    ball = bpy.context.active_object
    ball.name = "Ball"
    noise = bpy.data.materials.new("Noise")
    if noise.node_tree is None:
        noise.use_nodes = True
    tree = noise.node_tree
    texture = tree.nodes.new("ShaderNodeTexNoise")
    bsdf = next(node for node in tree.nodes if node.bl_idname == "ShaderNodeBsdfPrincipled")
    tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
    ball.data.materials.append(noise)
    bpy.ops.mesh.primitive_plane_add(size=1.0, location=(0.0, 1.0, 0.0))
    plane = bpy.context.active_object
    plane.name = "Plane Without UVs"
    plane.data.uv_layers.remove(plane.data.uv_layers[0])
    plane.data.materials.append(noise)
    camera_at((0.0, -6.0, 1.0), (math.radians(80), 0.0, 0.0))
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 640, 360, 100
    scene.frame_start, scene.frame_end = 1, 3
    settings = scene.paint_relief
    settings.object_texture_size = "1024"
    settings.scene_output_dir = os.path.join(WORK, "scene")
    settings.seed = 5
    bpy.ops.wm.save_as_mainfile(filepath=PHOTO_SCENE, copy=True)
    return scene


def run_paint_scene(**options):
    try:
        return sorted(bpy.ops.paint_relief.paint_scene(texture_size=128, **options)), ""
    except RuntimeError as error:
        return None, str(error)


def report():
    with open(os.path.join(WORK, "scene", ops_scene_paint.REPORT_FILE)) as file:
        return json.load(file)


def mtimes():
    root = os.path.join(WORK, "scene")
    return {os.path.relpath(os.path.join(folder, name), root): os.stat(os.path.join(folder, name)).st_mtime_ns
            for folder, _, names in os.walk(root) for name in names if name != ops_scene_paint.REPORT_FILE}


@check
def scene_painted():
    scene = photo_scene()
    result, error = run_paint_scene()
    found = report()
    scene.frame_set(1)
    depths = scene_view.seen_meshes(scene, bpy.context.view_layer, [1, 2, 3])
    centre_depths = [d for name in ("Ball", "Box", "Box Twin") for d in depths[name]]
    params = ops_scene_paint.object_params(scene.paint_relief)
    return {"result": result, "error": error, "painted": found["painted"], "refused": found["refused"],
            "paintings": {k: v["objects"] for k, v in found["paintings"].items()},
            "stroke_mm": found["stroke_mm"], "how": found["stroke_mm_from"],
            "expected_depth": statistics.median(centre_depths),
            "expected_mm": list(paint_relief.core.screen_stroke_mm(
                params, 640, 360, scene_view.pixel_mm(scene, statistics.median(centre_depths)))),
            "materials": {name: [slot.material.name for slot in scene.objects[name].material_slots]
                          for name in ("Box", "Box Twin", "Ball", "Plane Without UVs")},
            "files": sorted(os.listdir(os.path.join(WORK, "scene")))}


@check
def painted_again_keeps_every_texture():
    before = mtimes()
    result, error = run_paint_scene()
    found = report()
    return {"result": result, "error": error, "kept": {k: v["kept"] for k, v in found["paintings"].items()},
            "unchanged": mtimes() == before, "painted": sorted(found["painted"])}


MAP_FILES = ("color.exr", "height.exr", "opacity.exr", "painting.png", "strokes.json", "lit_paper.png")


@check
def stopped_and_painted_again():
    """Stop the painting once one texture is committed; paint again: that texture is kept, the other painted, and
    every map has the bytes of the run never stopped (``scene_painted``'s)."""
    scene = photo_scene()
    stopped = os.path.join(WORK, "stopped")
    scene.paint_relief.scene_output_dir = stopped
    context = bpy.context
    names, depths = ops_scene_paint.scene_targets(context, False)
    run = ops_scene_paint.ScenePaint(context, names, depths, False, 128)
    while run.gather_next(context):
        pass
    run.begin_painting()

    def done():
        return [folder for folder in ("Ball", "Box") if os.path.isfile(os.path.join(stopped, folder, "report.json"))]

    try:
        run.work(None, lambda: bool(done()))
        outcome = "finished"
    except paint_relief.core.Cancelled as error:
        outcome = str(error)
    finally:
        run.clean()
    first = done()
    result, error = run_paint_scene()
    with open(os.path.join(stopped, ops_scene_paint.REPORT_FILE)) as file:
        found = json.load(file)

    def same(folder, name):
        paths = [os.path.join(root, folder, name) for root in (stopped, os.path.join(WORK, "scene"))]
        with open(paths[0], "rb") as one, open(paths[1], "rb") as other:
            return one.read() == other.read()

    return {"outcome": outcome, "done_when_stopped": first, "result": result, "error": error,
            "kept": {k: v["kept"] for k, v in found["paintings"].items()},
            "same_bytes": {folder: all(same(folder, name) for name in MAP_FILES) for folder in ("Ball", "Box")},
            "differ": [f"{folder}/{name}" for folder in ("Ball", "Box") for name in MAP_FILES if not same(folder, name)]}


@check
def selection_alone():
    scene = bpy.context.scene
    for obj in scene.objects:
        obj.select_set(obj.name == "Ball")
    scene.paint_relief.scene_output_dir = os.path.join(WORK, "selection")
    try:
        result = sorted(bpy.ops.paint_relief.paint_scene(texture_size=128, selected_only=True))
    except RuntimeError as error:
        return {"error": str(error)}
    with open(os.path.join(WORK, "selection", ops_scene_paint.REPORT_FILE)) as file:
        found = json.load(file)
    return {"result": result, "painted": sorted(found["painted"]), "folders": sorted(
        name for name in os.listdir(os.path.join(WORK, "selection")) if name != ops_scene_paint.REPORT_FILE)}


print("RESULTS " + json.dumps(RESULTS))
