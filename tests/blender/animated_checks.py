# SPDX-License-Identifier: GPL-3.0-or-later
"""The animated canvas inside Blender (the bpy module): build it on a painted sequence and print what it does.

    BLENDER_USER_RESOURCES=/tmp/x python tests/blender/animated_checks.py WORK_DIR

WORK_DIR/frames holds a tiny shot (frame_0011.png to frame_0014.png). Its first three
frames are painted here into WORK_DIR/sequence with the package's
``core.paint_sequence_files``; the Build Canvas operator builds the animated
canvas, and the checks read the evaluated mesh at several frames, the image
sequences' settings, a rebuild after the user moved the canvas, Reload Maps
after the fourth frame is painted, refusals, and two Cycles renders of the
colour map. The last line printed is ``RESULTS <json>`` for
tests/test_animated_canvas.py.
"""

import json
import os
import shutil
import sys

from recorder import RESULTS, check, load_extension

THICKNESS_MM = 2.0


def evaluated_heights(bpy, obj):
    """(z, u, v) of the canvas's evaluated vertices: float64 arrays, z in metres, u and v in [0, 1]."""
    import numpy as np

    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float64)
    mesh.vertices.foreach_get("co", co)
    evaluated.to_mesh_clear()
    x, y, z = co.reshape(-1, 3).T  # the grid spans its width and height about the object's origin
    return z, (x - x.min()) / (x.max() - x.min()), (y - y.min()) / (y.max() - y.min())


def sampled(height_map, u, v):
    """The height map (H, W), row 0 at the top, at UV (u, v) (v up): bilinear between pixel centres, edges
    clamped, as a texture lookup."""
    import numpy as np

    h, w = height_map.shape
    x = np.clip(u * w - 0.5, 0, w - 1)
    y = np.clip((1.0 - v) * h - 0.5, 0, h - 1)
    x0, y0 = np.minimum(np.floor(x).astype(int), w - 2), np.minimum(np.floor(y).astype(int), h - 2)
    fx, fy = x - x0, y - y0
    top = height_map[y0, x0] * (1 - fx) + height_map[y0, x0 + 1] * fx
    bottom = height_map[y0 + 1, x0] * (1 - fx) + height_map[y0 + 1, x0 + 1] * fx
    return top * (1 - fy) + bottom * fy


def correlation(a, b):
    import numpy as np

    return float(np.corrcoef(a, b)[0, 1])


def run_op(op, **kwargs):
    """Call an operator; return (sorted result or None, error text)."""
    try:
        return sorted(op(**kwargs)), ""
    except RuntimeError as error:  # an operator's ERROR report raises in background mode
        return None, str(error)


def main(work):
    import numpy as np

    bpy = load_extension(work)
    import paint_relief
    from paint_relief import core
    from paint_relief.addon.scene import animated, canvas_plane
    from paint_relief.core.files import reading

    frames_dir = os.path.join(work, "frames")
    sequence = os.path.join(work, "sequence")
    params = core.Params(seed=3)
    core.paint_sequence_files([frames_dir], sequence, params, frame_range="11-13")
    ops = bpy.ops.paint_relief
    scene = bpy.context.scene
    settings = scene.paint_relief
    scene.frame_start, scene.frame_end = 1, 250

    def height_map(number):
        return reading.read_exr(os.path.join(sequence, "height_{:04d}.exr".format(number)))[0][..., 0]

    def heights_at(obj, frame, numbers):
        scene.frame_set(frame)
        z, u, v = evaluated_heights(bpy, obj)
        return {"z_mean": float(z.mean()), "z_max": float(z.max()),
                "correlation": {str(n): correlation(z, sampled(height_map(n), u, v)) for n in numbers}}

    @check
    def build():
        settings.painting_dir = sequence
        settings.canvas_width_cm = 40.0
        settings.thickness_mm = THICKNESS_MM
        settings.displacement_method = "MESH"
        result, error = run_op(ops.build_canvas)
        obj = canvas_plane.find_role(scene, "canvas")
        material = obj.active_material
        nodes = {node.label: {"file": os.path.basename(node.image.filepath), "source": node.image.source,
                              "duration": node.image_user.frame_duration, "start": node.image_user.frame_start,
                              "offset": node.image_user.frame_offset, "auto": node.image_user.use_auto_refresh}
                 for node in material.node_tree.nodes if node.bl_idname == "ShaderNodeTexImage"}
        texture = obj.modifiers[canvas_plane.DISPLACE_MODIFIER].texture
        return {"result": result, "error": error, "nodes": nodes, "sequence": list(obj[animated.SEQUENCE_KEY]),
                "displace": {"file": os.path.basename(texture.image.filepath), "source": texture.image.source,
                             "duration": texture.image_user.frame_duration,
                             "start": texture.image_user.frame_start, "offset": texture.image_user.frame_offset,
                             "auto": texture.image_user.use_auto_refresh},
                "frame_range": [scene.frame_start, scene.frame_end], "dimensions": list(obj.dimensions[:2])}

    @check
    def heights_follow_the_frame():
        obj = canvas_plane.find_role(scene, "canvas")
        return {str(frame): heights_at(obj, frame, (11, 12, 13)) for frame in (10, 11, 12, 13, 17)}

    @check
    def frame_range_on_request():
        result, error = run_op(ops.build_canvas, frame_range=True)
        return {"result": result, "error": error, "frame_range": [scene.frame_start, scene.frame_end]}

    @check
    def rebuild_keeps_the_users_changes():
        obj = canvas_plane.find_role(scene, "canvas")
        obj.location = (0.1, -0.2, 0.3)
        obj.rotation_euler = (0.2, 0.0, 0.5)
        obj.scale = (1.5, 1.5, 1.5)
        bevel = obj.modifiers.new("My Bevel", "BEVEL")
        tree = obj.active_material.node_tree
        hue = tree.nodes.new("ShaderNodeHueSaturation")
        hue.name = "My Hue"
        before = {"matrix": [value for row in obj.matrix_basis for value in row], "objects": len(bpy.data.objects),
                  "materials": len(bpy.data.materials), "images": len(bpy.data.images)}
        result, error = run_op(ops.build_canvas)
        obj = canvas_plane.find_role(scene, "canvas")
        after = {"matrix": [value for row in obj.matrix_basis for value in row], "objects": len(bpy.data.objects),
                 "materials": len(bpy.data.materials), "images": len(bpy.data.images)}
        colour = next(node for node in obj.active_material.node_tree.nodes if node.label == "Colour")
        return {"result": result, "error": error, "before": before, "after": after,
                "bevel_kept": obj.modifiers.get(bevel.name) is not None,
                "user_node_kept": "My Hue" in obj.active_material.node_tree.nodes,
                "colour_source": colour.image.source, "sequence": list(obj[animated.SEQUENCE_KEY]),
                "heights": heights_at(obj, 12, (11, 12, 13))}

    @check
    def reload_takes_frames_painted_since():
        core.paint_sequence_files([frames_dir], sequence, params)  # goes on with frame 4
        result, error = run_op(ops.reload_maps)
        obj = canvas_plane.find_role(scene, "canvas")
        return {"result": result, "error": error, "sequence": list(obj[animated.SEQUENCE_KEY]),
                "durations": sorted({user.frame_duration for user in animated.image_users(obj)}),
                "heights": heights_at(obj, 14, (13, 14))}

    @check
    def refusals():
        found = {}
        broken = os.path.join(work, "broken")
        shutil.copytree(sequence, broken)
        os.remove(os.path.join(broken, "opacity_0012.exr"))
        for name, folder, method in (("missing_frame", broken, "MESH"), ("no_normal_maps", sequence, "NORMAL_MAP")):
            settings.painting_dir = folder
            settings.displacement_method = method
            before = (len(bpy.data.objects), len(bpy.data.images), len(bpy.data.meshes))
            result, error = run_op(ops.build_canvas)
            after = (len(bpy.data.objects), len(bpy.data.images), len(bpy.data.meshes))
            found[name] = {"result": result, "error": error, "changed": before != after}
        settings.painting_dir = sequence
        settings.displacement_method = "MESH"
        obj = canvas_plane.find_role(scene, "canvas")
        found["canvas_still_a_sequence"] = all(user.frame_duration == 4 for user in animated.image_users(obj))
        return found

    @check
    def normal_map_sequence():
        normals = os.path.join(work, "sequence_normals")
        core.paint_sequence_files([frames_dir], normals, params, core.SequenceSettings(normal_map=True),
                                  frame_range="11-12")
        settings.painting_dir = normals
        settings.displacement_method = "NORMAL_MAP"
        result, error = run_op(ops.build_canvas)
        obj = canvas_plane.find_role(scene, "canvas")
        readers = sorted((os.path.basename(image.filepath), image.source, user.frame_duration, user.frame_start)
                         for image, user in animated.image_readers(obj))
        modifiers = [m.type for m in obj.modifiers]
        bpy.data.objects.remove(obj)
        settings.painting_dir = sequence
        settings.displacement_method = "MESH"
        return {"result": result, "error": error, "readers": readers, "modifiers": modifiers}

    @check
    def colour_renders_follow_the_frame():
        # The colour map drives an Emission shader of strength 1 in a black world, so the render's scene-linear
        # pixels are the colour map's values at the frame rendered.
        obj = canvas_plane.find_role(scene, "canvas")
        obj.location, obj.rotation_euler, obj.scale = (0, 0, 0), (0, 0, 0), (1, 1, 1)
        obj.modifiers.remove(obj.modifiers["My Bevel"])
        settings.camera_match_resolution = True
        settings.camera_standard_view = True
        ops.add_camera()
        tree = obj.active_material.node_tree
        colour = next(node for node in tree.nodes if node.label == "Colour")
        output = next(node for node in tree.nodes if node.bl_idname == "ShaderNodeOutputMaterial")
        emission = tree.nodes.new("ShaderNodeEmission")
        tree.links.new(colour.outputs["Color"], emission.inputs["Color"])
        tree.links.new(emission.outputs["Emission"], output.inputs["Surface"])
        world = bpy.data.worlds.new("black")
        world.color = (0.0, 0.0, 0.0)
        scene.world = world
        scene.render.engine = "CYCLES"
        scene.cycles.device = "CPU"
        scene.cycles.samples = 4
        scene.cycles.use_denoising = False
        scene.cycles.filter_width = 0.01
        image_settings = scene.render.image_settings
        if hasattr(image_settings, "media_type"):
            image_settings.media_type = "IMAGE"
        image_settings.file_format = "OPEN_EXR"
        image_settings.color_depth = "32"
        errors = {}
        for frame in (11, 14):
            scene.frame_set(frame)
            path = os.path.join(work, "render_{}.exr".format(frame))
            scene.render.filepath = path
            bpy.ops.render.render(write_still=True)
            rendered = reading.read_exr(path)[0][..., :3]
            errors[str(frame)] = {str(n): float(np.mean(np.square(
                rendered - reading.read_exr(os.path.join(sequence, "color_{:04d}.exr".format(n)))[0][..., :3])))
                for n in (11, 14)}
        return {"mean_squared_error": errors}

    RESULTS["blender_version"] = list(bpy.app.version)
    paint_relief.unregister()
    print("RESULTS " + json.dumps(RESULTS), flush=True)


if __name__ == "__main__":
    if not os.environ.get("BLENDER_USER_RESOURCES"):
        sys.exit("BLENDER_USER_RESOURCES is not set: refusing to touch a real user profile")
    main(sys.argv[1])
