# SPDX-License-Identifier: GPL-3.0-or-later
"""Open a saved .blend holding an animated Paint Relief canvas (the bpy module) and print what it holds.

    BLENDER_USER_RESOURCES=/tmp/x python tests/blender/blend_checks.py SCENE.blend

Prints ``RESULTS <json>``: the scene's frame range, its render settings, and
for the canvas (the object whose ``paint_relief_role`` is "canvas") the
source of each of its material's images and its evaluated vertex heights at
the first and the last frame of the range.
"""

import json
import sys


def main(path):
    import bpy
    import numpy as np

    bpy.ops.wm.open_mainfile(filepath=path)
    scene = bpy.context.scene
    canvas = next(obj for obj in scene.objects if obj.get("paint_relief_role") == "canvas")

    def heights(frame):
        scene.frame_set(frame)
        evaluated = canvas.evaluated_get(bpy.context.evaluated_depsgraph_get())
        mesh = evaluated.to_mesh()
        co = np.empty(len(mesh.vertices) * 3, dtype=np.float64)
        mesh.vertices.foreach_get("co", co)
        evaluated.to_mesh_clear()
        return co[2::3]

    first, last = heights(scene.frame_start), heights(scene.frame_end)
    images = {node.label: node.image.source for node in canvas.active_material.node_tree.nodes
              if node.bl_idname == "ShaderNodeTexImage"}
    render = scene.render
    print("RESULTS " + json.dumps({
        "frame_range": [scene.frame_start, scene.frame_end], "images": images,
        "heights_first": [float(first.min()), float(first.max()), float(first.mean())],
        "heights_last": [float(last.min()), float(last.max()), float(last.mean())],
        "heights_differ": float(np.abs(first - last).max()),
        "render": {"engine": render.engine, "filepath": render.filepath, "format": render.image_settings.file_format,
                   "size": [render.resolution_x, render.resolution_y], "samples": scene.cycles.samples},
        "key_lights": [obj.name for obj in scene.objects if obj.get("paint_relief_role") == "key_light"],
        "camera": scene.camera.name if scene.camera else None}), flush=True)


if __name__ == "__main__":
    main(sys.argv[1])
