# SPDX-License-Identifier: GPL-3.0-or-later
"""The extension as an artist gets it: installed from the built zip, driven headless step by step.

Run in its own process with BLENDER_USER_RESOURCES set to a throw-away folder::

    BLENDER_USER_RESOURCES=/tmp/u python tests/shipped/flow.py PACKAGE.zip WORK_DIR

Blender installs the zip (and the wheels it declares) with
``package_install_files``, exactly as *Install from Disk* does; nothing of
the checkout is imported. Each step records its findings under its name (a
step that raises records its traceback); the last line printed is
``RESULTS <json>``, which test_flow.py asserts on.
"""

import ctypes
import ctypes.util
import json
import os
import sys

from steps import MODULE, REPO, RESULTS, run_op, step  # tests/shipped/steps.py, beside this script


class _MallocInfo(ctypes.Structure):
    _fields_ = [(name, ctypes.c_size_t) for name in (
        "arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks", "fsmblks", "uordblks", "fordblks", "keepcost")]


def malloc_state():
    """glibc's mmap threshold as behaviour shows it: {"threshold": bytes, "adapts": bool}, or None (not glibc).

    glibc has no call that reports its malloc parameters, so they are read
    from what it does. ``threshold`` is the smallest power of two from 128 KiB
    to 64 MiB that a malloc maps instead of taking from the heap; ``adapts``
    is whether freeing that block raised the threshold, as glibc's dynamic
    threshold does until ``mallopt`` fixes it for the rest of the process.
    The reading itself raises a dynamic threshold, never lowers it.
    """
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        libc.mallinfo2.restype = _MallocInfo
    except (OSError, AttributeError):
        return None
    libc.malloc.restype = ctypes.c_void_p
    libc.malloc.argtypes = [ctypes.c_size_t]
    libc.free.argtypes = [ctypes.c_void_p]

    def mapped(size):
        before = libc.mallinfo2().hblks
        block = libc.malloc(size)
        found = libc.mallinfo2().hblks > before
        libc.free(block)
        return found

    threshold = next((2 ** k for k in range(17, 27) if mapped(2 ** k)), None)
    return {"threshold": threshold, "adapts": threshold is not None and not mapped(threshold)}


def process_settings():
    """What a panel Paint must leave as it found it: environment, locale, glibc's malloc thresholds."""
    import locale

    return {"environ": dict(os.environ), "locale": locale.setlocale(locale.LC_ALL), "malloc": malloc_state()}


def main(zip_path, work):
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    result = bpy.ops.extensions.package_install_files(filepath=os.path.abspath(zip_path), repo=REPO,
                                                      enable_on_install=True)
    RESULTS["install"] = {"result": sorted(result), "enabled": MODULE in bpy.context.preferences.addons,
                          "imported_at_enable": [m for m in ("scipy", "OpenImageIO") if m in sys.modules],
                          "blender": list(bpy.app.version)}
    dependencies = sys.modules[MODULE + ".addon.dependencies"]
    ops = bpy.ops.paint_relief
    scene = bpy.context.scene
    settings = scene.paint_relief

    @step
    def libraries():
        problem = dependencies.problem()
        import numpy
        import OpenImageIO
        import scipy

        user = os.environ["BLENDER_USER_RESOURCES"]
        installed = sorted(os.path.relpath(os.path.join(root, name), user) for root, dirs, _ in os.walk(user)
                           for name in dirs if name.endswith(".dist-info"))
        return {"problem": problem, "openimageio": OpenImageIO.__file__, "installed": installed,
                "python": list(sys.version_info[:2]),
                "openimageio_source": dependencies.openimageio_source(OpenImageIO),
                "openimageio_version": OpenImageIO.VERSION_STRING, "numpy": numpy.__version__,
                "scipy": scipy.__version__, "scipy_file": scipy.__file__,
                "user_resources": os.environ["BLENDER_USER_RESOURCES"]}

    from importlib import import_module

    import_module(MODULE + ".core")
    reading = import_module(MODULE + ".core.files.reading")
    writing = import_module(MODULE + ".core.files.writing")
    import numpy as np

    photo = os.path.join(work, "photo.png")
    y, x = np.mgrid[0:48, 0:64]
    writing.write_png(photo, np.stack([x / 64, y / 48, 0.5 + 0.4 * np.sin(x / 3.0) * np.cos(y / 5.0)], -1)
                 .astype(np.float32))

    @step
    def paint():
        settings.image_path = photo
        settings.output_dir = os.path.join(work, "painted")
        settings.stroke_sizes = "400,200"
        before = process_settings()
        result, error = run_op(ops.paint)
        after = process_settings()
        folder = settings.painting_dir
        return {"result": result, "error": error, "painting_dir": folder, "process": [before, after],
                "files": sorted(os.listdir(folder)) if folder and os.path.isdir(folder) else []}

    @step
    def output_inside_the_installed_extension():
        """Paint refuses an output folder inside the installed package's folder, which Blender deletes on update or
        removal (the checkout's own out/ is free: tests/test_paint_shot.py)."""
        package = os.path.dirname(sys.modules[MODULE].__file__)
        inside = os.path.join(package, "out", "painting")
        settings.output_dir = inside
        result, error = run_op(ops.paint)
        settings.output_dir = os.path.join(work, "painted")
        return {"result": result, "error": error, "package": package, "written": os.path.exists(inside)}

    @step
    def stage():
        results = {name: run_op(getattr(ops, name)) for name in ("build_canvas", "add_lights", "add_camera")}
        canvas = [o for o in scene.objects if o.get("paint_relief_role") == "canvas"]
        return {"results": results, "canvas_dimensions": list(canvas[0].dimensions[:2]) if canvas else None,
                "resolution": [scene.render.resolution_x, scene.render.resolution_y]}

    @step
    def cycles_render():
        scene.render.engine = "CYCLES"
        scene.cycles.device = "CPU"
        scene.cycles.samples = 4
        scene.cycles.use_denoising = False
        settings_image = scene.render.image_settings
        if hasattr(settings_image, "media_type"):
            settings_image.media_type = "IMAGE"
        settings_image.file_format = "PNG"
        path = os.path.join(work, "render.png")
        scene.render.filepath = path
        bpy.ops.render.render(write_still=True)
        pixels = reading.read_image(path)
        return {"exists": os.path.isfile(path), "size": list(pixels.shape[:2]), "mean": float(pixels.mean()),
                "std": float(pixels.std())}

    @step
    def comparison():
        settings.compare_azimuths = 2
        settings.compare_samples = 2
        settings.compare_output_dir = os.path.join(work, "comparison")
        result, error = run_op(ops.render_comparison)
        folder = settings.compare_output_dir
        sheet_path = os.path.join(folder, "comparison.png")
        found = {"result": result, "error": error, "files": sorted(os.listdir(folder)) if os.path.isdir(folder) else []}
        if os.path.isfile(sheet_path):
            sheet_module = import_module(MODULE + ".core.figures.sheet")
            sheet = reading.read_image(sheet_path)
            # The first row of labels: the strip between the top gap and the first pictures.
            strip = sheet[6:6 + 24, 6:200]
            found["label_pixels"] = int((np.abs(strip - np.asarray(sheet_module.BACKGROUND)).max(axis=2) > 0.3).sum())
            chart = reading.read_image(os.path.join(folder, "correlation.png"))
            found["chart_title_dark_pixels"] = int((chart[5:30, 70:400].max(axis=2) < 0.5).sum())
        return found

    canvas_mod = import_module(MODULE + ".addon.scene.canvas_plane")
    jobs = import_module(MODULE + ".addon.painting.jobs")
    cli_command = import_module(MODULE + ".addon.cli_command")

    @step
    def second_paint_refused():
        jobs.begin(scene)  # what the interactive Paint does while its worker runs
        try:
            refused, error = run_op(ops.paint)
        finally:
            jobs.end(scene)
        again, again_error = run_op(ops.paint)
        return {"refused": refused, "error": error, "after": again, "after_error": again_error}

    @step
    def default_paintings_keep_their_folders():
        bpy.context.preferences.addons[MODULE].preferences.output_dir = os.path.join(work, "defaults")
        settings.output_dir = ""
        folders = []
        for _ in range(2):
            result, error = run_op(ops.paint)
            folders.append(settings.painting_dir)
        return {"folders": folders, "error": error,
                "both_there": all(os.path.isfile(os.path.join(f, "color.exr")) for f in folders),
                "user_resources": os.environ["BLENDER_USER_RESOURCES"]}

    @step
    def two_canvases():
        first, second = RESULTS["default_paintings_keep_their_folders"]["folders"]
        art = bpy.data.collections.new("Art")
        scene.collection.children.link(art)
        layer = bpy.context.view_layer
        layer.active_layer_collection = layer.layer_collection.children["Art"]
        made = []
        for folder in (first, second):
            settings.painting_dir = folder
            run_op(ops.build_canvas)
            made.append(layer.objects.active)
        found = []
        for obj in made:
            material = obj.active_material
            colour = next(n.image for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeTexImage"
                          and n.label == "Colour")
            found.append({"name": obj.name, "material": material.name,
                          "colour_file": os.path.dirname(bpy.path.abspath(colour.filepath)),
                          "in_art": obj.name in art.objects, "selected": obj.select_get()})
        return {"canvases": found, "folders": [first, second], "count": len(canvas_mod.canvases(scene)),
                "active": layer.objects.active.name}

    @step
    def rebuild_keeps_user_changes():
        obj = canvas_mod.canvases(scene)[0]
        layer = bpy.context.view_layer
        layer.objects.active = obj
        obj.location = (0.3, -0.2, 0.1)
        obj.rotation_euler = (0.2, 0.1, 0.5)
        obj.scale = (1.5, 1.5, 1.5)
        tree = obj.active_material.node_tree
        extra = tree.nodes.new("ShaderNodeHueSaturation")
        extra.name = "My Hue"
        colour = tree.nodes["Paint Relief Colour"]
        bsdf = tree.nodes["Paint Relief BSDF"]
        tree.links.new(colour.outputs["Color"], extra.inputs["Color"])
        tree.links.new(extra.outputs["Color"], bsdf.inputs["Base Color"])
        bevel = obj.modifiers.new("My Bevel", "BEVEL")
        layer.update()
        before = {"matrix": [v for r in obj.matrix_world for v in r], "objects": len(bpy.data.objects),
                  "materials": len(bpy.data.materials)}
        settings.painting_dir = obj["paint_relief_painting_dir"]
        settings.thickness_mm = 3.0
        result, error = run_op(ops.build_canvas)
        tree = obj.active_material.node_tree
        base = tree.nodes["Paint Relief BSDF"].inputs["Base Color"]
        layer.update()
        return {"result": result, "error": error, "before": before,
                "after": {"matrix": [v for r in obj.matrix_world for v in r], "objects": len(bpy.data.objects),
                          "materials": len(bpy.data.materials)},
                "extra_node": "My Hue" in tree.nodes,
                "base_colour_from": base.links[0].from_node.name if base.links else None,
                "modifiers": [m.name for m in obj.modifiers], "bevel_kept": bevel.name in obj.modifiers,
                "displace_strength": obj.modifiers["Paint Relief Displace"].strength}

    @step
    def user_nodes_keep_their_values():
        obj = canvas_mod.canvases(scene)[0]
        tree = obj.active_material.node_tree
        bump = tree.nodes.new("ShaderNodeBump")
        bump.name = "My Bump"
        bump.inputs["Strength"].default_value = 0.77
        bump.inputs["Distance"].default_value = 0.05
        displacement = tree.nodes.new("ShaderNodeDisplacement")
        displacement.name = "My Displacement"
        displacement.inputs["Scale"].default_value = 0.2

        def values():
            return {name: [round(tree.nodes[name].inputs[key].default_value, 6) for key in keys] for name, keys in (
                ("My Bump", ("Strength", "Distance")), ("My Displacement", ("Scale",)),
                ("Paint Relief Bump", ("Strength", "Distance")), ("Paint Relief Displacement", ("Scale",)))}

        settings.thickness_mm = 2.0           # the panel's thickness: a live update of every canvas
        thicker = values()
        canvas_mod.set_relief(obj, False)     # the comparison's flat renders
        flat = values()
        canvas_mod.set_relief(obj, True)
        return {"thicker": thicker, "flat": flat, "relief": values()}

    @step
    def agx_stays_agx():
        scene.view_settings.view_transform = "AgX"
        scene.render.resolution_x, scene.render.resolution_y = 1920, 1080
        result, error = run_op(ops.add_camera)
        kept = {"view": scene.view_settings.view_transform,
                "resolution": [scene.render.resolution_x, scene.render.resolution_y]}
        settings.camera_match_resolution = True
        settings.camera_standard_view = True
        asked, _ = run_op(ops.add_camera)
        changed = {"view": scene.view_settings.view_transform,
                   "resolution": [scene.render.resolution_x, scene.render.resolution_y]}
        return {"result": result, "error": error, "kept": kept, "asked": asked, "changed": changed,
                "map_size": list(canvas_mod.find_role(scene, "canvas")["paint_relief_map_size"])}

    @step
    def exif_sideways_jpeg_paints_upright():
        import OpenImageIO as oiio

        stored = np.zeros((24, 48, 3), np.uint8)
        stored[:, :24] = (230, 20, 20)
        stored[:, 24:] = (20, 20, 230)
        path = os.path.join(work, "sideways.jpg")
        spec = oiio.ImageSpec(48, 24, 3, "uint8")
        spec.attribute("Orientation", 6)
        out = oiio.ImageOutput.create(path)
        out.open(path, spec)
        out.write_image(stored)
        out.close()
        settings.source = "FILE"
        settings.image_path = path
        settings.output_dir = os.path.join(work, "sideways")
        result, error = run_op(ops.paint)
        painted = reading.read_image(os.path.join(settings.painting_dir, "painting.png"))
        return {"result": result, "error": error, "shape": list(painted.shape),
                "top_mean": painted[:20].mean(axis=(0, 1)).tolist(),
                "bottom_mean": painted[-20:].mean(axis=(0, 1)).tolist()}

    @step
    def command_line():
        registered = cli_command._handle is not None
        bad = cli_command.execute(["compare", os.path.join(work, "no_such_photo.png"), "-o", os.path.join(work, "x")])
        usage = cli_command.execute(["frobnicate"])
        out = os.path.join(work, "cli_compare")
        code = cli_command.execute(["compare", photo, "-o", out, "--azimuths", "1", "--samples", "1", "--size", "48",
                                    "--quiet"])
        return {"registered": registered, "bad_input": bad, "usage": usage, "compare": code,
                "files": sorted(os.listdir(out)) if os.path.isdir(out) else []}

    @step
    def paint_object_from_its_base_color():
        bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, segments=16, ring_count=8, location=(3.0, 0.0, 0.0))
        sphere = bpy.context.active_object
        image = bpy.data.images.new("Generated", 64, 32)
        u, v = np.mgrid[0:32, 0:64][::-1]
        image.pixels.foreach_set(np.dstack([u / 64, v / 32, 0.5 + 0 * u, 1 + 0 * u]).astype(np.float32).ravel())
        material = bpy.data.materials.new("Generated colour")
        if material.node_tree is None:
            material.use_nodes = True
        texture = material.node_tree.nodes.new("ShaderNodeTexImage")
        texture.image = image
        bsdf = next(n for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
        material.node_tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
        sphere.data.materials.append(material)
        settings.object_texture_size = "1024"
        settings.object_output_dir = os.path.join(work, "sphere")
        result, error = run_op(ops.paint_object)
        folder = settings.object_output_dir
        files = sorted(os.listdir(folder)) if os.path.isdir(folder) else []
        back, _ = run_op(ops.object_painting, show=False)
        original = [slot.material.name for slot in sphere.material_slots]
        run_op(ops.object_painting, show=True)
        return {"result": result, "error": error, "files": files,
                "slots": [slot.material.name for slot in sphere.material_slots], "back": back, "original": original,
                "modifiers": [m.type for m in sphere.modifiers]}

    @step
    def paint_object_without_uvs_from_a_bake():
        bpy.ops.object.select_all(action="DESELECT")
        bpy.ops.mesh.primitive_cube_add(size=0.5, location=(-3.0, 0.0, 0.0))
        cube = bpy.context.active_object
        while cube.data.uv_layers:
            cube.data.uv_layers.remove(cube.data.uv_layers[0])
        material = bpy.data.materials.new("Plain colour")
        if material.node_tree is None:
            material.use_nodes = True
        cube.data.materials.append(material)
        refused, refusal = run_op(ops.paint_object)
        unwrapped, _ = run_op(ops.smart_uv_project)
        settings.object_output_dir = os.path.join(work, "cube")
        settings.object_relief = "NORMAL_MAP"
        result, error = run_op(ops.paint_object)
        folder = settings.object_output_dir
        return {"refused": refused, "refusal": refusal, "unwrapped": unwrapped, "result": result, "error": error,
                "files": sorted(os.listdir(folder)) if os.path.isdir(folder) else [],
                "modifiers": [m.type for m in cube.modifiers], "engine": scene.render.engine}

    @step
    def paint_object_of_udim_tiles_and_a_baked_slot():
        """A cube of two slots: a UDIM image of two tiles on disk, and a plain material, which is baked."""
        bpy.ops.object.select_all(action="DESELECT")
        bpy.ops.mesh.primitive_cube_add(size=0.5, location=(0.0, 3.0, 0.0))
        cube = bpy.context.active_object
        cube.name = "Tiled box"
        y, x = np.mgrid[0:32, 0:32]
        for tile, phase in ((1001, 0.0), (1002, 2.0)):
            writing.write_png(os.path.join(work, "tiles.{}.png".format(tile)),
                              np.stack([0.5 + 0.4 * np.sin(x / 4.0 + phase), y / 32, 0.5 + 0 * x], -1)
                              .astype(np.float32))
        tiles = bpy.data.materials.new("Tiles")
        plain = bpy.data.materials.new("Plain")
        for material in (tiles, plain):
            if material.node_tree is None:
                material.use_nodes = True
        texture = tiles.node_tree.nodes.new("ShaderNodeTexImage")
        texture.image = bpy.data.images.load(os.path.join(work, "tiles.1001.png"))
        texture.image.source = "TILED"
        bsdf = next(n for n in tiles.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
        tiles.node_tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
        cube.data.materials.append(tiles)
        cube.data.materials.append(plain)
        uv = cube.data.uv_layers.active.data
        for polygon in cube.data.polygons:
            polygon.material_index = int(polygon.normal.z < -0.5)
            if polygon.normal.x > 0.5:
                for loop in polygon.loop_indices:
                    uv[loop].uv = (uv[loop].uv[0] + 1.0, uv[loop].uv[1])
        settings.object_output_dir = os.path.join(work, "tiles")
        settings.object_relief = "DISPLACE"
        result, error = run_op(ops.paint_object, texture_size=128)       # three cells of 128 texels
        folder = settings.object_output_dir
        displace = cube.modifiers.get("Paint Relief Displace")
        back, _ = run_op(ops.object_painting, show=False)
        original = [slot.material.name for slot in cube.material_slots]
        run_op(ops.object_painting, show=True)
        return {"result": result, "error": error,
                "files": sorted(os.listdir(folder)) if os.path.isdir(folder) else [],
                "slots": [slot.material.name for slot in cube.material_slots],
                "tiled": sorted({node.image.source for slot in cube.material_slots
                                 for node in slot.material.node_tree.nodes
                                 if node.bl_idname == "ShaderNodeTexImage" and node.image}),
                "displace_uv": displace.uv_layer if displace else None, "back": back, "original": original}

    @step
    def paint_scene_of_the_selection():
        """Two objects, a ball of the generated image and a baked box, painted by Paint Scene side by side."""
        bpy.ops.object.select_all(action="DESELECT")
        bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, segments=16, ring_count=8, location=(6.0, 0.0, 0.0))
        ball = bpy.context.active_object
        ball.name = "Scene Ball"
        ball.data.materials.append(bpy.data.materials["Generated colour"])
        bpy.ops.mesh.primitive_cube_add(size=0.5, location=(6.0, 2.0, 0.0))
        box = bpy.context.active_object
        box.name = "Scene Box"
        box.data.materials.append(bpy.data.materials["Plain colour"])
        ball.select_set(True)
        settings.scene_output_dir = os.path.join(work, "scene")
        settings.object_stroke_mm = "40,20,10"
        result, error = run_op(ops.paint_scene, texture_size=64, selected_only=True)
        settings.object_stroke_mm = ""
        path = os.path.join(work, "scene", "paint_scene.json")
        found = json.load(open(path)) if os.path.isfile(path) else {}
        return {"result": result, "error": error, "painted": sorted(found.get("painted", {})),
                "refused": found.get("refused"), "folders": sorted(os.listdir(settings.scene_output_dir)),
                "slots": [slot.material.name for obj in (ball, box) for slot in obj.material_slots]}

    @step
    def user_world_survives_add_lights_and_reload():
        world = bpy.data.worlds.new("My World")
        scene.world = world
        result, error = run_op(ops.add_lights)
        before = scene.world.name
        path = os.path.join(work, "world.blend")
        bpy.ops.wm.save_as_mainfile(filepath=path)
        bpy.ops.wm.open_mainfile(filepath=path)
        return {"result": result, "error": error, "before": before,
                "after_reload": bpy.context.scene.world.name if bpy.context.scene.world else None,
                "lights": sorted(o.name for o in bpy.context.scene.objects if o.type == "LIGHT")}

    print("RESULTS " + json.dumps(RESULTS), flush=True)


if __name__ == "__main__":
    if not os.environ.get("BLENDER_USER_RESOURCES"):
        sys.exit("BLENDER_USER_RESOURCES is not set: refusing to touch a real user profile")
    main(sys.argv[1], sys.argv[2])
