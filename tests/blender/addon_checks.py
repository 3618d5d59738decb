# SPDX-License-Identifier: GPL-3.0-or-later
"""Run the Paint Relief operators inside Blender (the bpy module) and print what they did.

Run in its own process (``bpy`` can be imported once per process), with
``BLENDER_USER_RESOURCES`` pointing at a throw-away folder::

    BLENDER_USER_RESOURCES=/tmp/x python tests/blender/addon_checks.py WORK_DIR [--render]

The repository is loaded as the package ``paint_relief`` (through a symbolic
link in WORK_DIR), registered as Blender would, and driven with ``bpy.ops``
in background mode. Each check stores its findings (numbers, names, error
text) under its name; the last line printed is ``RESULTS <json>``, which
tests/test_addon.py asserts on. A check that raises records its traceback
instead, so the others still run.
"""

import json
import os
import sys

from recorder import RESULTS, check, load_extension, shade_colour_map

MAP_W, MAP_H = 64, 48



def counts(bpy):
    """How many objects, materials, meshes, images, lights and cameras the file holds."""
    data = bpy.data
    return {"objects": len(data.objects), "materials": len(data.materials), "meshes": len(data.meshes),
            "images": len(data.images), "lights": len(data.lights), "cameras": len(data.cameras)}


def run_op(op, **kwargs):
    """Call an operator; return (result set or None, error text)."""
    try:
        return sorted(op(**kwargs)), ""
    except RuntimeError as error:  # an operator's ERROR report raises in background mode
        return None, str(error)


def read_exr(path, channels=None):
    """An EXR file as float32 (H, W, C) through OpenImageIO, optionally only the named channels."""
    import numpy as np
    import OpenImageIO as oiio

    inp = oiio.ImageInput.open(path)
    spec = inp.spec()
    pixels = np.asarray(inp.read_image(0, 0, 0, spec.nchannels, "float"), dtype=np.float32)
    inp.close()
    pixels = pixels.reshape(spec.height, spec.width, spec.nchannels)
    if channels is None:
        return pixels
    names = list(spec.channelnames)
    return pixels[..., [names.index(c) for c in channels]]


def bilinear_resample(image, width, height):
    """Resample (H, W, C) to (height, width, C) as a bilinear texture lookup with clamped edges."""
    import numpy as np

    h, w = image.shape[:2]
    x = (np.arange(width) + 0.5) / width * w - 0.5
    y = (np.arange(height) + 0.5) / height * h - 0.5
    x0 = np.clip(np.floor(x).astype(int), 0, w - 1)
    y0 = np.clip(np.floor(y).astype(int), 0, h - 1)
    x1, y1 = np.clip(x0 + 1, 0, w - 1), np.clip(y0 + 1, 0, h - 1)
    fx = np.clip(x - np.floor(x), 0, 1)[None, :, None]
    fy = np.clip(y - np.floor(y), 0, 1)[:, None, None]
    top = image[y0][:, x0] * (1 - fx) + image[y0][:, x1] * fx
    bottom = image[y1][:, x0] * (1 - fx) + image[y1][:, x1] * fx
    return top * (1 - fy) + bottom * fy


def main(work, render):
    import numpy as np

    bpy = load_extension(work)
    import paint_relief
    from paint_relief.core.files import reading, writing

    ops = bpy.ops.paint_relief
    scene = bpy.context.scene
    settings = scene.paint_relief
    photo = os.path.join(work, "photo.png")
    y, x = np.mgrid[0:MAP_H, 0:MAP_W]
    stripes = 0.5 + 0.4 * np.sin(x / 3.0) * np.cos(y / 5.0)
    writing.write_png(photo, np.stack([x / MAP_W, y / MAP_H, stripes], axis=-1).astype(np.float32))
    out = os.path.join(work, "painted")

    @check
    def settings_defaults():
        from paint_relief.core import Params

        defaults = Params()
        return {"params": {"detail": [settings.detail, defaults.detail],
                           "stroke_sizes": [list(paint_relief.addon.values.parse_sizes(settings.stroke_sizes)),
                                            list(defaults.stroke_sizes)],
                           "layers": [settings.layers, defaults.layers],
                           "seed": [settings.seed, defaults.seed],
                           "brush": [settings.brush.lower(), defaults.brush],
                           "height_mode": [settings.height_mode.lower(), defaults.height_mode]},
                "canvas_width_cm": settings.canvas_width_cm, "thickness_mm": settings.thickness_mm,
                "poll_paint_without_image": ops.paint.poll(),
                "poll_canvas_without_painting": ops.build_canvas.poll(),
                "poll_camera_without_canvas": ops.add_camera.poll()}

    @check
    def missing_photo():
        settings.image_path = os.path.join(work, "no_such_photo.png")
        before = counts(bpy)
        result, error = run_op(ops.paint)
        return {"result": result, "error": error, "before": before, "after": counts(bpy),
                "painting_dir": settings.painting_dir}

    @check
    def paint():
        settings.image_path = photo
        settings.output_dir = out
        # Strokes wide enough for a 64 x 48 photograph that the mesh grid (a vertex
        # every 2 px) samples the height map's whole range.
        settings.stroke_sizes = "400,200"
        result, error = run_op(ops.paint)
        return {"result": result, "error": error, "painting_dir": settings.painting_dir,
                "files": sorted(os.listdir(out)) if os.path.isdir(out) else []}

    @check
    def unreadable_map():
        broken = os.path.join(work, "broken")
        os.makedirs(broken, exist_ok=True)
        for name in ("height.exr", "opacity.exr"):
            with open(os.path.join(out, name), "rb") as src, open(os.path.join(broken, name), "wb") as dst:
                dst.write(src.read())
        with open(os.path.join(broken, "color.exr"), "wb") as dst:
            dst.write(b"this is not an EXR file\n" * 10)
        settings.painting_dir = broken
        before = counts(bpy)
        result, error = run_op(ops.build_canvas)
        missing_dir = os.path.join(work, "empty")
        os.makedirs(missing_dir, exist_ok=True)
        settings.painting_dir = missing_dir
        missing_result, missing_error = run_op(ops.build_canvas)
        return {"result": result, "error": error, "before": before, "after": counts(bpy),
                "missing_result": missing_result, "missing_error": missing_error,
                "broken_file": os.path.join(broken, "color.exr"), "missing_file": os.path.join(missing_dir, "color.exr")}

    @check
    def canvas_mesh():
        settings.painting_dir = out
        settings.canvas_width_cm = 40.0
        settings.thickness_mm = 2.0
        settings.displacement_method = "MESH"
        result, error = run_op(ops.build_canvas)
        from paint_relief.addon.scene import canvas_plane

        obj = canvas_plane.find_role(scene, "canvas")
        material = obj.active_material
        links = sorted({(l.from_node.bl_idname, l.from_socket.identifier, l.to_node.bl_idname, l.to_socket.identifier)
                        for l in material.node_tree.links})
        images = {n.image.name: {"colorspace": n.image.colorspace_settings.name, "is_data": n.image.colorspace_settings.is_data,
                                 "interpolation": n.interpolation, "extension": n.extension,
                                 "file": os.path.basename(n.image.filepath)}
                  for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeTexImage"}
        depsgraph = bpy.context.evaluated_depsgraph_get()
        evaluated = obj.evaluated_get(depsgraph)
        mesh = evaluated.to_mesh()
        co = np.empty(len(mesh.vertices) * 3, dtype=np.float64)
        mesh.vertices.foreach_get("co", co)
        z = co.reshape(-1, 3)[:, 2]
        evaluated.to_mesh_clear()
        height = read_exr(os.path.join(out, "height.exr"))[..., 0]
        displacement = next(n for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeDisplacement")
        bump = next(n for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeBump")
        return {"result": result, "error": error, "dimensions": list(obj.dimensions[:2]),
                "links": links, "images": images, "vertices": len(obj.data.vertices),
                "z_range": [float(z.min()), float(z.max())],
                "height_range": [float(height.min()), float(height.max())],
                "z_percentiles": [float(v) for v in np.percentile(z, [1, 99])],
                "height_percentiles": [float(v) for v in np.percentile(height, [1, 99])],
                "displacement_inputs": {"midlevel": displacement.inputs["Midlevel"].default_value,
                                        "scale": displacement.inputs["Scale"].default_value},
                "bump_distance": bump.inputs["Distance"].default_value,
                "modifiers": [(m.type, getattr(m, "strength", None), getattr(m, "mid_level", None),
                               getattr(m, "texture_coords", None)) for m in obj.modifiers],
                "displacement_method": getattr(material, "displacement_method", None)
                or getattr(getattr(material, "cycles", None), "displacement_method", None)}

    @check
    def canvas_again_adaptive():
        before = counts(bpy)
        settings.displacement_method = "CYCLES_ADAPTIVE"
        result, error = run_op(ops.build_canvas)
        from paint_relief.addon.scene import canvas_plane

        canvases = [o.name for o in scene.objects if o.get(canvas_plane.ROLE_KEY) == "canvas"]
        obj = bpy.data.objects[canvases[0]]
        material = obj.active_material
        links = sorted({(l.from_node.bl_idname, l.from_socket.identifier, l.to_node.bl_idname, l.to_socket.identifier)
                        for l in material.node_tree.links})
        subsurf = [m for m in obj.modifiers if m.type == "SUBSURF"]
        adaptive = (getattr(subsurf[0], "use_adaptive_subdivision", None) if subsurf else None)
        if adaptive is None and hasattr(obj, "cycles"):
            adaptive = getattr(obj.cycles, "use_adaptive_subdivision", None)
        method = getattr(material, "displacement_method", None) or material.cycles.displacement_method
        modifiers = [m.type for m in obj.modifiers]
        settings.displacement_method = "MESH"
        back, back_error = run_op(ops.build_canvas)
        return {"result": result, "error": error, "canvases": canvases, "before": before, "after": counts(bpy),
                "links": links, "modifiers": modifiers, "adaptive": adaptive,
                "displacement_method": method, "engine": scene.render.engine,
                "back_to_mesh": back, "back_error": back_error,
                "modifiers_after": [m.type for m in obj.modifiers]}

    @check
    def canvas_normal_map():
        had_normals = os.path.exists(os.path.join(out, "normal.exr"))
        settings.displacement_method = "NORMAL_MAP"
        result, error = run_op(ops.build_canvas)
        from paint_relief.addon.scene import canvas_plane

        material = canvas_plane.find_role(scene, "canvas").active_material
        links = sorted({(l.from_node.bl_idname, l.from_socket.identifier, l.to_node.bl_idname, l.to_socket.identifier)
                        for l in material.node_tree.links})
        normals = read_exr(os.path.join(out, "normal.exr")) if os.path.exists(os.path.join(out, "normal.exr")) else None
        # painted again (here: the height map turned upside down): Reload Maps makes the normal map again
        from paint_relief.core.files.export import HEIGHT_DIGEST_ATTR, file_digest, painting_attributes

        height_path = os.path.join(out, "height.exr")
        original = open(height_path, "rb").read()
        height, _, attributes = reading.read_exr(height_path)
        kept = painting_attributes(attributes)
        writing.write_exr(height_path, height[::-1].copy(), channels=("Y",), half=True, attributes=kept)
        reload_result, reload_error = run_op(ops.reload_maps)
        recorded = reading.read_attributes(os.path.join(out, "normal.exr")).get(HEIGHT_DIGEST_ATTR)
        matches = recorded == file_digest(height_path)["sha256"]
        with open(height_path, "wb") as f:
            f.write(original)
        settings.displacement_method = "MESH"
        back, back_error = run_op(ops.build_canvas)
        return {"result": result, "error": error, "had_normals": had_normals, "links": links,
                "normal_shape": None if normals is None else list(normals.shape),
                "normal_z_min": None if normals is None else float(normals[..., 2].min()),
                "reload": reload_result, "reload_error": reload_error, "reloaded_normals_match": matches,
                "back_to_mesh": back, "back_error": back_error}

    @check
    def lights():
        results = [run_op(ops.add_lights)[0]]
        first = counts(bpy)
        results.append(run_op(ops.add_lights)[0])
        second = counts(bpy)
        from paint_relief.addon.scene import canvas_plane

        key = canvas_plane.find_role(scene, "key_light")
        direction = key.matrix_world.to_3x3() @ __import__("mathutils").Vector((0.0, 0.0, 1.0))
        settings.fill_light = False
        results.append(run_op(ops.add_lights)[0])
        third = counts(bpy)
        settings.fill_light = True
        return {"results": results, "first": first, "second": second, "no_fill": third,
                "key_towards_light": list(direction), "azimuth": settings.light_azimuth,
                "elevation": settings.light_elevation, "world": scene.world.name if scene.world else None}

    @check
    def camera():
        settings.camera_match_resolution = True
        settings.camera_standard_view = True
        result, error = run_op(ops.add_camera)
        first = counts(bpy)
        again, _ = run_op(ops.add_camera)
        cam = scene.camera
        return {"result": result, "again": again, "error": error, "first": first, "second": counts(bpy),
                "type": cam.data.type, "ortho_scale": cam.data.ortho_scale, "sensor_fit": cam.data.sensor_fit,
                "resolution": [scene.render.resolution_x, scene.render.resolution_y],
                "view": [scene.view_settings.view_transform, scene.view_settings.look,
                         scene.view_settings.exposure, scene.view_settings.gamma]}

    if render:
        @check
        def colour_render():
            # Calibration: the canvas material's colour map drives an Emission shader of
            # strength 1 in a black world, so the render's scene-linear pixels are the
            # colour map's own values: it shows framing, orientation and the EXR colour
            # space. (Blender 5.0's bpy module writes no extra passes such as DiffCol into
            # a multilayer EXR here, so the Combined pass of an Emission shader is used.)
            from paint_relief.addon.scene import canvas_plane

            material = canvas_plane.find_role(scene, "canvas").active_material
            emission = shade_colour_map(material, "ShaderNodeEmission", "Color", "Emission")
            emission.inputs["Strength"].default_value = 1.0
            for obj in scene.objects:
                if obj.type == "LIGHT":
                    obj.hide_render = True
            world = bpy.data.worlds.new("black")
            scene.world = world
            world.color = (0.0, 0.0, 0.0)
            if world.node_tree is not None:
                for node in world.node_tree.nodes:
                    if node.type == "BACKGROUND":
                        node.inputs["Strength"].default_value = 0.0

            scene.render.engine = "CYCLES"
            scene.cycles.device = "CPU"
            scene.cycles.samples = 16
            if hasattr(scene.cycles, "use_adaptive_sampling"):
                scene.cycles.use_adaptive_sampling = False
            scene.cycles.use_denoising = False
            scene.cycles.filter_width = 0.01
            scene.render.resolution_percentage = 200  # 64 x 48 map -> 128 x 96 render
            path = os.path.join(work, "render.exr")
            image_settings = scene.render.image_settings
            if hasattr(image_settings, "media_type"):  # Blender 5.0: a media type first
                image_settings.media_type = "IMAGE"
            image_settings.file_format = "OPEN_EXR"
            image_settings.color_depth = "32"
            scene.render.filepath = path
            bpy.ops.render.render(write_still=True)

            rendered = read_exr(path)[..., :3]
            expected = bilinear_resample(read_exr(os.path.join(out, "color.exr"))[..., :3],
                                         rendered.shape[1], rendered.shape[0])
            mse = float(np.mean((rendered - expected) ** 2))
            peak = float(expected.max())
            flipped = float(np.mean((rendered[::-1] - expected) ** 2))
            return {"size": [rendered.shape[1], rendered.shape[0]],
                    "psnr": 10 * np.log10(peak * peak / max(mse, 1e-12)),
                    "psnr_upside_down": 10 * np.log10(peak * peak / max(flipped, 1e-12)),
                    "mean_rendered": rendered.mean(axis=(0, 1)).tolist(),
                    "mean_expected": expected.mean(axis=(0, 1)).tolist()}

    paint_relief.unregister()
    RESULTS["unregistered"] = {"scene_property": "paint_relief" in bpy.types.Scene.bl_rna.properties,
                               "operator": hasattr(bpy.types, "PAINT_RELIEF_OT_paint"),
                               "panel": hasattr(bpy.types, "VIEW3D_PT_paint_relief")}
    RESULTS["blender_version"] = list(bpy.app.version)
    print("RESULTS " + json.dumps(RESULTS), flush=True)


if __name__ == "__main__":
    if not os.environ.get("BLENDER_USER_RESOURCES"):
        sys.exit("BLENDER_USER_RESOURCES is not set: refusing to touch a real user profile")
    main(sys.argv[1], "--render" in sys.argv[2:])
