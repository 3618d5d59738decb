# SPDX-License-Identifier: GPL-3.0-or-later
"""Shading and glow of painted objects against their originals, for tests/test_model_paintings.py.

    python tests/blender/model_figures.py ORIGINAL.blend PAINTED.blend OBJECT[,OBJECT...] OUT [--views V] [--res PX]

Each .blend is opened, every object but OBJECTS is hidden, and OBJECTS are rendered by Cycles from V views around
them (a camera at 2.6 times their bounding radius, 20 degrees up, the lens 50 mm), twice:
- **shading**: 1 sample, a box pixel filter, the Normal pass (world space, the shading normal: normal maps and
  bumps included) and the alpha, with the paint's relief at 0 (every Displace modifier's strength and every
  Displacement node's scale 0), so only what the painted material does to the shading differs;
- **glow**: every light hidden and the world black, 16 samples: what reaches the camera is the light the objects
  emit (and what of it they bounce back).
The last line printed is ``RESULTS <json>``: the mean and 95th percentile angle in degrees between the original's
and the painting's shading normals over the pixels both cover, and the summed linear RGB of each glow render.
"""

import json
import math
import os
import sys

import bpy
import numpy as np
from mathutils import Vector


def opened(blend, names):
    """Open ``blend``; hide every object but ``names`` and return (scene, objects)."""
    bpy.ops.wm.open_mainfile(filepath=os.path.abspath(blend), load_ui=False)
    scene = bpy.context.scene
    objects = [bpy.data.objects[name] for name in names]
    for obj in scene.objects:
        if obj not in objects and obj.type != "CAMERA":
            obj.hide_render = True
    return scene, objects


def frame_views(scene, objects, views, res):
    """A camera of its own for ``scene``; yields for each of ``views`` views after placing it."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    corners = [obj.evaluated_get(depsgraph).matrix_world @ Vector(corner) for obj in objects
               for corner in obj.evaluated_get(depsgraph).bound_box]
    centre = sum(corners, Vector()) / len(corners)
    radius = max((corner - centre).length for corner in corners)
    data = bpy.data.cameras.new("figures")
    data.lens = 50
    camera = bpy.data.objects.new("figures", data)
    scene.collection.objects.link(camera)
    scene.camera = camera
    scene.render.resolution_x = scene.render.resolution_y = res
    scene.render.resolution_percentage = 100
    distance = 2.6 * radius / math.tan(data.angle / 2) * 0.5
    for view in range(views):
        angle = 2 * math.pi * view / views
        camera.location = centre + Vector((math.cos(angle) * math.cos(0.35), math.sin(angle) * math.cos(0.35),
                                           math.sin(0.35))) * distance
        camera.rotation_euler = (centre - camera.location).to_track_quat("-Z", "Y").to_euler()
        yield view


def render(scene, path):
    """Render ``scene`` into the multilayer EXR ``path``; {channel name without its layer: (H, W) array}."""
    import OpenImageIO as oiio

    settings = scene.render.image_settings
    if hasattr(settings, "media_type"):
        settings.media_type = "MULTI_LAYER_IMAGE"
    settings.file_format = "OPEN_EXR_MULTILAYER"
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    found = {}
    for part in range(max(oiio.ImageBuf(path).nsubimages, 1)):      # Blender 5 writes a part per pass
        buffer = oiio.ImageBuf(path, part, 0)
        pixels = buffer.get_pixels(oiio.FLOAT)
        for index, name in enumerate(buffer.spec().channelnames):
            found[".".join(name.split(".")[-2:])] = pixels[..., index]
    return found


def cycles(scene, samples):
    """Cycles on the CPU at ``samples`` samples, no denoising, the render's own passes written (no compositor)."""
    scene.render.use_compositing = False
    scene.render.engine = "CYCLES"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False
    scene.cycles.device = "CPU"


def normals(blend, names, views, res, out, tag):
    """[(normal (H, W, 3), alpha (H, W))] of each view, the relief at 0."""
    scene, objects = opened(blend, names)
    for obj in objects:
        for modifier in obj.modifiers:
            if modifier.type == "DISPLACE":
                modifier.strength = 0.0
        for slot in obj.material_slots:
            if slot.material is not None and slot.material.node_tree is not None:
                for node in slot.material.node_tree.nodes:
                    if node.bl_idname == "ShaderNodeDisplacement":
                        node.inputs["Scale"].default_value = 0.0
    cycles(scene, 1)
    scene.cycles.pixel_filter_type = "BOX"
    scene.render.film_transparent = True
    for layer in scene.view_layers:
        layer.use_pass_normal = True
    found = []
    for view in frame_views(scene, objects, views, res):
        channels = render(scene, os.path.join(out, "{}_normal_{}.exr".format(tag, view)))
        found.append((np.stack([channels["Normal.X"], channels["Normal.Y"], channels["Normal.Z"]], -1),
                      channels["Combined.A"]))
    return found


def glow(blend, names, views, res, out, tag):
    """The summed linear RGB the objects send to the camera over every view with no light but their own."""
    scene, objects = opened(blend, names)
    for obj in scene.objects:
        if obj.type == "LIGHT":
            obj.hide_render = True
    world = bpy.data.worlds.new("black")
    scene.world = world
    world.color = (0.0, 0.0, 0.0)
    if world.node_tree is not None:
        world.node_tree.nodes.clear()
    cycles(scene, 16)
    total = 0.0
    for view in frame_views(scene, objects, views, res):
        channels = render(scene, os.path.join(out, "{}_glow_{}.exr".format(tag, view)))
        total += float(sum(channels["Combined." + channel].sum() for channel in "RGB"))
    return total


def angles(original, painted):
    """Degrees between the shading normals of two lists of (normal, alpha) views over the pixels both cover."""
    found = []
    for (normal_a, alpha_a), (normal_b, alpha_b) in zip(original, painted, strict=True):
        both = (alpha_a > 0.99) & (alpha_b > 0.99)
        a, b = normal_a[both], normal_b[both]
        a = a / np.maximum(np.linalg.norm(a, axis=1, keepdims=True), 1e-9)
        b = b / np.maximum(np.linalg.norm(b, axis=1, keepdims=True), 1e-9)
        found.append(np.degrees(np.arccos(np.clip((a * b).sum(1), -1.0, 1.0))))
    return np.concatenate(found)


def main(argv):
    original, painted, names, out = argv[:4]
    views = int(argv[argv.index("--views") + 1]) if "--views" in argv else 2
    res = int(argv[argv.index("--res") + 1]) if "--res" in argv else 96
    names = names.split(",")
    os.makedirs(out, exist_ok=True)
    degrees = angles(normals(original, names, views, res, out, "original"),
                     normals(painted, names, views, res, out, "painted"))
    seen = degrees.size > 0
    results = {"shading_mean": float(degrees.mean()) if seen else None,
               "shading_p95": float(np.percentile(degrees, 95)) if seen else None, "pixels": int(degrees.size),
               "glow_original": glow(original, names, views, res, out, "original"),
               "glow_painted": glow(painted, names, views, res, out, "painted")}
    print("RESULTS " + json.dumps(results))


if __name__ == "__main__":
    main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:])
