# SPDX-License-Identifier: GPL-3.0-or-later
"""Run Paint Animation inside Blender (the bpy module) and print what it did, for tests/test_paint_shot.py.

Run in its own process (``bpy`` can be imported once per process), with
``BLENDER_USER_RESOURCES`` pointing at a throw-away folder::

    BLENDER_USER_RESOURCES=/tmp/x python tests/blender/paint_shot_checks.py WORK_DIR

The repository is loaded as the package ``paint_relief`` and registered as
Blender would. The scene is tiny (64 x 48 px, 4 frames, Cycles at 2 samples):
a ball moving across a textured wall seen by a panning camera, with a user's
compositor nodes (an Invert), extra passes (Z, Normal, an AOV), a second view
layer and render settings unlike the ones Paint Animation renders with. Each
check stores its findings under its name (a check that raises stores its
traceback); ``seconds`` holds each check's wall time. The checks that paint
need the painter's libraries (SciPy, OpenImageIO) and record ``skipped``
without them, so the render checks also run on a Blender that has only its
own modules. The last line printed is ``RESULTS <json>``.
"""

import contextlib
import json
import math
import os
import shutil
import sys
import time

from recorder import RESULTS, check, load_extension

WIDTH, HEIGHT, FRAMES = 64, 48, 4
SECONDS = {}
# Pointers not followed by the settings snapshot: the evaluated state and the scene's contents, which
# rendering rebuilds and which are no setting.
_NOT_SETTINGS = {"rna_type", "depsgraph", "layer_collection", "objects", "active_layer_collection", "bl_rna",
                 "eevee", "id_data"}


def timed(function):
    """``check`` that also records the check's wall time in SECONDS."""
    def run():
        start = time.perf_counter()
        try:
            return function()
        finally:
            SECONDS[function.__name__] = round(time.perf_counter() - start, 2)
    run.__name__ = function.__name__
    return check(run)


def rna_values(struct, depth):
    """Every property of a Blender struct as JSON-ready values, nested structs ``depth`` levels deep
    (IDs by name)."""
    import bpy

    found = {}
    for prop in struct.bl_rna.properties:
        name = prop.identifier
        if name in _NOT_SETTINGS:
            continue
        try:
            value = getattr(struct, name)
        except (AttributeError, RuntimeError):
            continue
        if prop.type == "POINTER":
            if value is None or isinstance(value, bpy.types.ID):
                found[name] = None if value is None else "ID " + value.name
            elif depth > 0:
                found[name] = rna_values(value, depth - 1)
        elif prop.type == "COLLECTION":
            if depth > 0:
                found[name] = [rna_values(item, depth - 1) for item in value]
        elif isinstance(value, set):
            found[name] = sorted(value)
        elif isinstance(value, str | int | float | bool):
            found[name] = value
        else:
            found[name] = [round(v, 6) if isinstance(v, float) else v for v in value]
    return found


def compositor_tree(scene):
    """The scene's compositor node tree (Blender 5: the node group; 4.x: scene.node_tree), or None."""
    if hasattr(scene, "compositing_node_group"):
        return scene.compositing_node_group
    return scene.node_tree if scene.use_nodes else None


def node_values(node):
    """A compositor node's properties, its sockets by identifier, and the order of the sockets it shows.

    A Render Layers node keeps a socket for every pass and shows those of the
    passes that are on; Blender 5.0 may put a hidden socket elsewhere in
    that list when a pass is switched on and off, which no one sees.
    """
    found = rna_values(node, 0)
    for side in ("inputs", "outputs"):
        sockets = getattr(node, side)
        found[side] = {socket.identifier: rna_values(socket, 0) for socket in sockets}
        found[side + "_shown"] = [socket.identifier for socket in sockets if socket.enabled and not socket.hide]
    return found


def settings_snapshot(scene):
    """Everything a render could change: the render settings (image format, its colour management, views),
    Cycles', colour management, every view layer (passes, AOVs, use), the frame, the compositor's nodes."""
    tree = compositor_tree(scene)
    nodes = links = None
    if tree is not None:
        nodes = {node.name: node_values(node) for node in tree.nodes}
        links = sorted([link.from_node.name, link.from_socket.identifier, link.to_node.name, link.to_socket.identifier]
                       for link in tree.links)
    return {"render": rna_values(scene.render, 3), "cycles": rna_values(scene.cycles, 1),
            "view_settings": rna_values(scene.view_settings, 2),
            "display_settings": rna_values(scene.display_settings, 1),
            "view_layers": [rna_values(layer, 2) for layer in scene.view_layers],
            "scene": {name: getattr(scene, name) for name in
                      ("frame_current", "frame_subframe", "frame_start", "frame_end", "frame_step")},
            "scene_use_nodes": getattr(scene, "use_nodes", None),
            "camera": scene.camera.name, "compositor": tree.name if tree is not None else None,
            "nodes": nodes, "links": links}


def differences(before, after, path=""):
    """The paths at which two snapshots differ, as "path: before -> after"."""
    if isinstance(before, dict) and isinstance(after, dict):
        found = []
        for key in sorted(set(before) | set(after)):
            found += differences(before.get(key), after.get(key), "{}.{}".format(path, key))
        return found
    if isinstance(before, list) and isinstance(after, list) and len(before) == len(after):
        found = []
        for i, (b, a) in enumerate(zip(before, after, strict=True)):
            found += differences(b, a, "{}[{}]".format(path, i))
        return found
    return [] if before == after else ["{}: {!r} -> {!r}".format(path, before, after)]


def material(bpy, name, texture, colours):
    made = bpy.data.materials.new(name)
    if made.node_tree is None:  # Blender 4.x: a new material has no nodes yet
        made.use_nodes = True
    tree = made.node_tree
    shader = tree.nodes["Principled BSDF"]
    pattern = tree.nodes.new(texture)
    pattern.inputs["Scale"].default_value = 6.0
    pattern.inputs["Color1"].default_value = colours[0]
    pattern.inputs["Color2"].default_value = colours[1]
    tree.links.new(pattern.outputs["Color"], shader.inputs["Base Color"])
    return made


def build_scene(bpy, work):
    """The tiny shot and a user's render set-up unlike Paint Animation's (module docstring)."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.name = "Shot"
    bpy.ops.mesh.primitive_plane_add(size=20.0, location=(0.0, 2.0, 0.0), rotation=(math.radians(90.0), 0.0, 0.0))
    bpy.context.object.data.materials.append(
        material(bpy, "Wall", "ShaderNodeTexBrick", ((0.7, 0.3, 0.1, 1.0), (0.3, 0.1, 0.05, 1.0))))
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.7, location=(-1.5, 0.0, 0.0))
    ball = bpy.context.object
    ball.data.materials.append(
        material(bpy, "Ball", "ShaderNodeTexChecker", ((0.9, 0.85, 0.2, 1.0), (0.1, 0.25, 0.7, 1.0))))
    bpy.ops.object.light_add(type="SUN", rotation=(math.radians(40.0), 0.0, math.radians(20.0)))
    bpy.context.object.data.energy = 3.0
    bpy.ops.object.camera_add(location=(0.0, -8.0, 0.0), rotation=(math.radians(90.0), 0.0, 0.0))
    camera = bpy.context.object
    scene.camera = camera
    for frame in range(1, FRAMES + 1):
        ball.location.x = -1.5 + 0.8 * (frame - 1)
        camera.location.x = 0.1 * (frame - 1)
        ball.keyframe_insert("location", frame=frame)
        camera.keyframe_insert("location", frame=frame)
    scene.frame_start, scene.frame_end, scene.frame_current = 1, FRAMES, 3

    render = scene.render
    render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 2
    scene.cycles.use_denoising = False
    render.resolution_x, render.resolution_y, render.resolution_percentage = WIDTH * 2, HEIGHT * 2, 50
    # The user's own output and effects, all unlike what Paint Animation renders with.
    render.filepath = "//user_frames/shot_"
    render.use_file_extension = False
    render.use_motion_blur = True
    render.use_compositing = True
    render.use_sequencer = True
    render.use_stamp = True
    render.image_settings.file_format = "PNG"
    render.image_settings.color_mode = "RGB"
    render.image_settings.color_depth = "16"
    render.image_settings.exr_codec = "DWAA"
    layer = scene.view_layers[0]
    layer.use_pass_z = True
    layer.use_pass_normal = True
    layer.use_pass_vector = False
    aov = layer.aovs.add()
    aov.name = "user_aov"
    scene.view_layers.new("Background").use_pass_mist = True

    if hasattr(scene, "compositing_node_group"):  # Blender 5: the compositor is a node group
        tree = bpy.data.node_groups.new("User Compositing", "CompositorNodeTree")
        scene.compositing_node_group = tree
        layers = tree.nodes.new("CompositorNodeRLayers")
        tree.interface.new_socket("Image", in_out="OUTPUT", socket_type="NodeSocketColor")
        output = tree.nodes.new("NodeGroupOutput")
        output_socket = output.inputs[0]
    else:
        scene.use_nodes = True
        tree = scene.node_tree
        layers = tree.nodes["Render Layers"]
        output_socket = tree.nodes["Composite"].inputs["Image"]
    invert = tree.nodes.new("CompositorNodeInvert")
    invert.name = "User Invert"
    invert.location = (200.0, 100.0)
    tree.links.new(layers.outputs["Image"], invert.inputs["Color"])
    tree.links.new(invert.outputs["Color"], output_socket)

    settings = scene.paint_relief
    settings.stroke_sizes = "24,12,6"
    settings.layers = 2
    settings.seed = 3
    return scene


def exr_parts(path):
    """The channel names of every part of an EXR file, or None without OpenImageIO's Python module."""
    try:
        import OpenImageIO as oiio
    except ImportError:
        return None
    inp = oiio.ImageInput.open(path)
    names = []
    subimage = 0
    while inp.seek_subimage(subimage, 0):
        names += list(inp.spec().channelnames)
        subimage += 1
    inp.close()
    return names


def folder_files(folder):
    """Every file under ``folder`` with its size, relative names, hidden ones included."""
    found = {}
    for root, _, names in os.walk(folder):
        for name in names:
            path = os.path.join(root, name)
            found[os.path.relpath(path, folder)] = os.path.getsize(path)
    return found


def run_op(op, **kwargs):
    try:
        return sorted(op(**kwargs)), ""
    except RuntimeError as error:
        return None, str(error)


def main(work):
    bpy = load_extension(work)
    from paint_relief.addon import dependencies
    from paint_relief.addon.painting import jobs, ops_paint_shot, scene_render, shot_source

    ops = bpy.ops.paint_relief
    try:
        missing = dependencies.problem()
    except ValueError as error:  # a checkout holding ./wheels/, on a Python without SciPy: no extension folder
        missing = str(error)
    painter = missing is None
    RESULTS["painter"] = painter
    RESULTS["blender_version"] = list(bpy.app.version)

    @timed
    def render_frames_restore_the_scene():
        """The scene's frames rendered as Paint Animation renders them (no painter needed)."""
        scene = build_scene(bpy, work)
        before = settings_snapshot(scene)
        folder = os.path.join(work, "render_only", scene_render.RENDER_FOLDER)
        frames = scene_render.RenderedFrames(scene, bpy.context.view_layer, folder)
        rendered = 0
        try:
            while frames.render_next():
                rendered += 1
                between = settings_snapshot(scene)  # the user's settings are back between frames
                between["scene"]["frame_current"] = before["scene"]["frame_current"]
                assert not differences(before, between), differences(before, between)
        finally:
            frames.close()
        names = sorted(os.listdir(folder))
        return {"differences": differences(before, settings_snapshot(scene)), "rendered": rendered,
                "files": names, "channels": exr_parts(os.path.join(folder, names[0])),
                "frame_current": scene.frame_current, "user_frames": os.path.exists(os.path.join(work, "user_frames"))}

    @timed
    def other_output_formats():
        """The scene's own output a video (FFmpeg, MPEG-4 H.264) or a single-layer half-float DWAA EXR: one
        frame rendered, every setting back."""
        found = {}
        for file_format in ("FFMPEG", "OPEN_EXR"):
            scene = build_scene(bpy, work)
            image_settings = scene.render.image_settings
            if hasattr(image_settings, "media_type"):
                image_settings.media_type = "VIDEO" if file_format == "FFMPEG" else "IMAGE"
            image_settings.file_format = file_format
            if file_format == "FFMPEG":
                scene.render.ffmpeg.format, scene.render.ffmpeg.codec = "MPEG4", "H264"
            else:
                image_settings.exr_codec, image_settings.color_depth = "DWAA", "16"
            before = settings_snapshot(scene)
            frames = scene_render.RenderedFrames(scene, bpy.context.view_layer,
                                                 os.path.join(work, "formats", file_format))
            try:
                frames.render_next()
            finally:
                frames.close()
            found[file_format] = {"differences": differences(before, settings_snapshot(scene)),
                                  "files": sorted(os.listdir(frames.folder))}
        return found

    @timed
    def paint_the_scene():
        if not painter:
            return {"skipped": missing}
        scene = build_scene(bpy, work)
        out = os.path.join(work, "scene_painted")
        scene.paint_relief.animation_source = "SCENE"
        scene.paint_relief.animation_output_dir = out
        before = settings_snapshot(scene)
        result, error = run_op(ops.paint_animation)
        report = json.load(open(os.path.join(out, "report.json"))) if os.path.isfile(os.path.join(out, "report.json")) else {}
        return {"result": result, "error": error, "differences": differences(before, settings_snapshot(scene)),
                "files": sorted(os.listdir(out)) if os.path.isdir(out) else [], "motion": report.get("motion"),
                "complete": report.get("complete"), "frames": report.get("frames"), "inputs": report.get("input"),
                "painting_dir": scene.paint_relief.painting_dir, "animation_key": scene.paint_relief.animation_key}

    @timed
    def cancel_and_resume():
        """The interactive operator's own steps (``ModalDriver``): Esc between rendered frames, Paint Animation
        again and Esc while painting frame 3, Paint Animation again to the end; against a run never stopped."""
        if not painter:
            return {"skipped": missing}
        scene = build_scene(bpy, work)
        settings = scene.paint_relief
        settings.animation_source = "SCENE"
        settings.animation_output_dir = ""  # the folder the operator picks: beside the saved .blend file
        bpy.ops.wm.save_as_mainfile(filepath=os.path.join(work, "shot.blend"))
        before = settings_snapshot(scene)

        first = ModalDriver(bpy, ops_paint_shot)
        first.run(stop_when=lambda: first.rendered_frames() == 2)
        folder = settings.animation_dir
        after_render_stop = {"outcome": first.outcome, "reports": first.reports, "texts": first.shown(),
                             "progress": first.progress, "differences": differences(before, settings_snapshot(scene)),
                             "files": folder_files(folder), "running": jobs.is_running(scene)}

        second = ModalDriver(bpy, ops_paint_shot)
        with painter_waiting_for_esc("Frame 3 (3/4)"):
            second.run(stop_when=lambda: any(text and "Frame 3 (3/4)" in text for text in second.texts))
        report = json.load(open(os.path.join(folder, "report.json")))
        after_paint_stop = {"outcome": second.outcome, "reports": second.reports, "folder": settings.animation_dir,
                            "files": folder_files(folder), "frames": report["frames"],
                            "first_frame": report["per_frame"][0], "texts": second.shown(),
                            "running": jobs.is_running(scene)}

        third = ModalDriver(bpy, ops_paint_shot)
        third.run()
        folder_again = settings.animation_dir
        resumed = json.load(open(os.path.join(folder, "report.json")))
        reference = os.path.join(work, "never_stopped")
        settings.animation_output_dir = reference
        reference_result, reference_error = run_op(ops.paint_animation)
        return {"parent": os.path.join(work, "paint_relief"), "folder": folder,
                "after_render_stop": after_render_stop, "after_paint_stop": after_paint_stop,
                "outcome": third.outcome, "reports": third.reports, "folder_again": folder_again,
                "resumed_frames": resumed["frames"], "resumed_first_frame": resumed["per_frame"][0],
                "complete": resumed["complete"], "resumed_files": folder_files(folder),
                "differences": differences(before, settings_snapshot(scene)),
                "reference_result": reference_result, "reference_error": reference_error,
                "differing": differing_files(folder, reference)}

    @timed
    def sources():
        """Which files each kind of image sequence source names: a datablock (with and without a user that sets
        its frames), a folder holding other files too, a pattern beside other numbered files."""
        scene = build_scene(bpy, work)
        settings = scene.paint_relief
        frames = os.path.join(work, "frames")
        for number in range(3, 9):
            write_frame(bpy, os.path.join(frames, "shot_{:04d}.png".format(number)), number)
        write_frame(bpy, os.path.join(frames, ".preview_0001.png"), 1)  # hidden: not a frame
        with open(os.path.join(frames, "notes.txt"), "w") as stream:
            stream.write("not a frame\n")
        takes = os.path.join(work, "takes")
        for number in (1, 2, 3):
            write_frame(bpy, os.path.join(takes, "take_{:03d}.png".format(number)), number)
        write_frame(bpy, os.path.join(takes, "other_001.png"), 9)
        write_frame(bpy, os.path.join(takes, "take_001_mask.png"), 9)
        sequence = bpy.data.images.load(os.path.join(frames, "shot_0005.png"))
        sequence.source = "SEQUENCE"
        found = {"no_user": [os.path.basename(p) for p in shot_source.image_sequence_files(sequence)]}
        node_tree = bpy.data.materials["Wall"].node_tree
        texture = node_tree.nodes.new("ShaderNodeTexImage")
        texture.image = sequence
        texture.image_user.frame_offset = 3   # files 4 .. 7
        texture.image_user.frame_duration = 4
        found["user_4_to_7"] = [os.path.basename(p) for p in shot_source.image_sequence_files(sequence)]
        texture.image_user.frame_offset = 2   # files 3 .. 102: the sequence ends with its last file, 8
        texture.image_user.frame_duration = 100
        found["user_3_to_102"] = [os.path.basename(p) for p in shot_source.image_sequence_files(sequence)]
        texture.image_user.frame_offset = 40  # no file 41: the image's own file starts the sequence
        texture.image_user.frame_duration = 2
        found["user_41_to_42"] = [os.path.basename(p) for p in shot_source.image_sequence_files(sequence)]
        node_tree.nodes.remove(texture)
        if not painter:
            return found
        runs = (("IMAGE", "animation_image", sequence), ("FOLDER", "animation_folder", frames),
                ("PATTERN", "animation_pattern", os.path.join(takes, "take_###.png")))
        for source, name, value in runs:
            settings.animation_source = source
            setattr(settings, name, value)
            settings.animation_output_dir = os.path.join(work, "painted_" + source.lower())
            result, error = run_op(ops.paint_animation)
            report_path = os.path.join(settings.animation_output_dir, "report.json")
            report = json.load(open(report_path)) if os.path.isfile(report_path) else {}
            found[source] = {"result": result, "error": error, "frames": report.get("frames"),
                             "inputs": [os.path.basename(p) for p in report.get("input", [])]}
        return found

    @timed
    def bad_sources():
        """Each wrong source is refused by the operator with one sentence and writes nothing."""
        if not painter:
            return {"skipped": missing}
        scene = build_scene(bpy, work)
        settings = scene.paint_relief
        os.makedirs(os.path.join(work, "no_frames_here"), exist_ok=True)
        write_frame(bpy, os.path.join(work, "mixed_sizes", "m_0001.png"), 1)
        write_frame(bpy, os.path.join(work, "mixed_sizes", "m_0002.png"), 2, size=(20, 12))
        write_frame(bpy, os.path.join(work, "gap", "g_0001.png"), 1)
        write_frame(bpy, os.path.join(work, "gap", "g_0003.png"), 3)
        write_frame(bpy, os.path.join(work, "still.png"), 1)
        still = bpy.data.images.load(os.path.join(work, "still.png"))
        still.source = "SEQUENCE"  # chosen as a sequence, then made a single image again
        settings.animation_image = still
        still.source = "FILE"
        cases = {
            "image_not_a_sequence": ("IMAGE", None, None),
            "missing_folder": ("FOLDER", "animation_folder", os.path.join(work, "no_such_folder")),
            "folder_without_frames": ("FOLDER", "animation_folder", os.path.join(work, "no_frames_here")),
            "frames_of_two_sizes": ("FOLDER", "animation_folder", os.path.join(work, "mixed_sizes")),
            "missing_frame": ("FOLDER", "animation_folder", os.path.join(work, "gap")),
            "pattern_without_hash": ("PATTERN", "animation_pattern", os.path.join(work, "frames", "shot.png")),
            "pattern_matching_nothing": ("PATTERN", "animation_pattern", os.path.join(work, "frames", "x_####.png")),
            "no_camera": ("SCENE", None, None),
        }
        # An output folder inside an installed extension's own folder: here the checkout the package links to,
        # installed as far as Blender knows by an extension repository whose folder holds it (removed below).
        package = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(ops_paint_shot.__file__))))
        inside = os.path.join(package, "painted_inside_the_extension")
        repositories = bpy.context.preferences.extensions.repos
        holding = repositories.new(name="Holding The Checkout", module="holding_the_checkout",
                                   custom_directory=os.path.dirname(os.path.realpath(package)))
        cases["output_inside_the_extension"] = ("FOLDER", "animation_folder", os.path.join(work, "frames"))
        # Output folders holding something else (their report.json says what): a still painting, the scene
        # painted to the end, the frames of another footage stopped halfway.
        reports = {"into_a_still": {"strokes": 3},
                   "into_a_finished_animation": {"sequence": "k", "complete": True,
                                                 "input": [os.path.join(work, "x", "scene_render", "frame_0001.exr")]},
                   "into_other_footage": {"sequence": "k", "complete": False,
                                          "input": [os.path.join(work, "frames", "shot_0003.png")]}}
        for case, report in reports.items():
            os.makedirs(os.path.join(work, "bad_" + case))
            with open(os.path.join(work, "bad_" + case, "report.json"), "w") as stream:
                json.dump(report, stream)
            cases[case] = ("SCENE", None, None)
        found = {}
        for case, (source, name, value) in cases.items():
            settings.animation_source = source
            if name is not None:
                setattr(settings, name, value)
            scene.camera = None if case == "no_camera" else bpy.data.objects["Camera"]
            out = inside if case == "output_inside_the_extension" else os.path.join(work, "bad_" + case)
            settings.animation_output_dir = out
            result, error = run_op(ops.paint_animation)
            found[case] = {"result": result, "error": error,
                           "output_exists": os.path.exists(out) and sorted(os.listdir(out)) != ["report.json"]}
        # The still painting keeps to the same rule.
        settings.image_path = os.path.join(work, "still.png")
        settings.output_dir = inside
        result, error = run_op(ops.paint)
        found["still_inside_the_extension"] = {"result": result, "error": error, "output_exists": os.path.exists(inside)}
        shutil.rmtree(inside, ignore_errors=True)
        repositories.remove(holding)
        return found

    @timed
    def scene_jobs_end():
        """Paint's and Paint Object's interactive path (``ModalDriver``; their end is jobs.SceneJob's) run to its
        end, and ended by Blender while it paints (``cancel``, as when the file closes): either way the scene may
        paint again, the timer and the progress bar are gone, the status text is cleared, and Paint Object's
        scratch folder is removed."""
        if not painter:
            return {"skipped": missing}
        from paint_relief.addon.objects import ops_object
        from paint_relief.addon.painting import ops_paint

        scene = build_scene(bpy, work)
        settings = scene.paint_relief
        photo = os.path.join(work, "modal", "photo.png")
        write_frame(bpy, photo, 1)
        settings.image_path = settings.object_texture_path = photo
        settings.object_texture_size = "1024"
        ball = bpy.data.objects["Sphere"]
        ball.data.materials.clear()  # no Base Color image: the texture comes from object_texture_path
        bpy.context.view_layer.objects.active = ball
        found = {}
        for name, operator in (("paint", ops_paint.PAINT_RELIEF_OT_paint),
                               ("paint_object", ops_object.PAINT_RELIEF_OT_paint_object)):
            for how in ("finished", "cancelled"):
                settings.output_dir = settings.object_output_dir = os.path.join(work, "modal", name + "_" + how)
                driver = ModalDriver(bpy, ops_paint_shot, operator)
                if how == "finished":
                    driver.run()
                else:
                    driver.outcome = sorted(driver.operator.begin_modal(driver.context))
                    driver.operator.cancel(driver.context)
                job = getattr(driver.operator, "_job", None)
                found["{} {}".format(name, how)] = {
                    "outcome": driver.outcome, "running": jobs.is_running(scene), "progress": driver.progress[-2:],
                    "status": driver.texts[-1] if driver.texts else "never set", "reports": driver.reports,
                    "scratch_left": job is not None and os.path.exists(job.scratch)}
        return found

    @timed
    def extension_folder_guard():
        """The output folder rule as the operators apply it (settings/properties.check_output_folder): a folder in
        the checkout the package links to is refused while an extension repository holds the checkout, and free
        (its out/, as `make demo` writes) when none does, the checkout loaded by path."""
        from paint_relief.addon.settings import properties

        package = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(ops_paint_shot.__file__))))
        demo = os.path.join(package, "out", "object", "maps")

        def error():
            try:
                properties.check_output_folder(demo)
            except ValueError as refused:
                return str(refused)
            return ""

        repositories = bpy.context.preferences.extensions.repos
        found = {"repositories": properties.extension_repositories(), "checkout": error()}
        holding = repositories.new(name="Holding The Checkout", module="holding_the_checkout",
                                   custom_directory=os.path.dirname(os.path.realpath(package)))
        found["installed"] = error()
        repositories.remove(holding)
        found["checkout_again"] = error()
        return found

    @timed
    def panel_draws():
        """The Paint Animation panel drawn for every source and state into a layout that records what it shows
        (a property that does not exist fails)."""
        from paint_relief.addon import panels

        scene = build_scene(bpy, work)
        settings = scene.paint_relief
        shown = {}
        states = [("SCENE", ""), ("SCENE", "stopped"), ("SCENE", "no camera"), ("IMAGE", ""), ("FOLDER", ""),
                  ("PATTERN", ""), ("FOLDER", "output")]
        for source, state in states:
            settings.animation_source = source
            settings.animation_output_dir = os.path.join(work, "out") if state == "output" else ""
            settings.animation_key, settings.animation_dir = ("k", os.path.join(work, "Shot_001")) if state else ("", "")
            scene.camera = None if state == "no camera" else bpy.data.objects["Camera"]
            layout = _Layout()
            panel = type("Panel", (), {"layout": layout, "_layout": lambda self: self.layout})()
            panels.VIEW3D_PT_paint_relief_animation.draw(panel, bpy.context)
            shown["{} {}".format(source, state).strip()] = layout.shown
        return shown

    RESULTS["seconds"] = SECONDS
    print("RESULTS " + json.dumps(RESULTS), flush=True)


class _Layout:
    """A panel layout that records the properties, labels and operators it is asked to show."""

    def __init__(self, shown=None):
        self.shown = [] if shown is None else shown

    def prop(self, data, name, **options):
        if name not in data.bl_rna.properties:
            raise AttributeError("{} has no property {}".format(data, name))
        self.shown.append("prop " + name)

    def label(self, text="", **options):
        self.shown.append("label " + text)

    def operator(self, name, **options):
        self.shown.append("operator " + name)

    def row(self, **options):
        return _Layout(self.shown)

    column = row


class _WindowManager:
    """What the operator asks of the window manager: a timer, the progress bar and a modal handler."""

    def __init__(self, progress):
        self.progress = progress

    def event_timer_add(self, interval, window=None):
        return "timer"

    def event_timer_remove(self, timer):
        self.progress.append("timer removed")

    def progress_begin(self, low, high):
        self.progress.append("begin")

    def progress_update(self, value):
        self.progress.append(value)

    def progress_end(self):
        self.progress.append("end")

    def modal_handler_add(self, operator):
        pass


class _Workspace:
    def __init__(self, texts):
        self.texts = texts

    def status_text_set(self, text):
        self.texts.append(text)


class ModalDriver:
    """A long operator's interactive path without a window (Paint Animation's unless ``operator``, the class, is
    given): the operator's own ``begin_modal`` and ``modal`` methods, called with the events a window sends (a
    timer event every few milliseconds, Esc when ``stop_when()`` first turns True) and a window manager and
    workspace that record the progress bar and the status text."""

    def __init__(self, bpy, ops_paint_shot, operator=None):
        operator = operator or ops_paint_shot.PAINT_RELIEF_OT_paint_animation
        own = {name: value for name, value in vars(operator).items() if not name.startswith(("__", "bl_"))}
        self.operator = type("Operator", tuple(base for base in operator.__bases__ if base is not bpy.types.Operator),
                             own)()
        self.reports, self.texts, self.progress = [], [], []
        self.operator.report = lambda level, text: self.reports.append([sorted(level)[0], text])
        self.context = type("Context", (), {})()
        self.context.scene, self.context.view_layer = bpy.context.scene, bpy.context.view_layer
        self.context.blend_data, self.context.preferences = bpy.data, bpy.context.preferences
        self.context.window = None
        self.context.active_object, self.context.mode = bpy.context.active_object, bpy.context.mode
        self.context.window_manager = _WindowManager(self.progress)
        self.context.workspace = _Workspace(self.texts)
        self.outcome = None

    def shown(self):
        """The status texts in the order shown, each once in a row."""
        return [text for i, text in enumerate(self.texts) if i == 0 or text != self.texts[i - 1]]

    def rendered_frames(self):
        frames = getattr(getattr(self.operator, "_job", None), "frames", None)
        return frames.done if frames is not None else 0

    def run(self, stop_when=lambda: False, seconds=300):
        timer, escape = type("Event", (), {"type": "TIMER", "value": "NOTHING"}), None
        result = self.operator.begin_modal(self.context)
        stopped = False
        deadline = time.monotonic() + seconds
        while result == {"RUNNING_MODAL"} and time.monotonic() < deadline:
            if not stopped and stop_when():
                stopped = True
                escape = type("Event", (), {"type": "ESC", "value": "PRESS"})
                self.operator.modal(self.context, escape)
            time.sleep(0.005)
            result = self.operator.modal(self.context, timer)
        self.outcome = sorted(result)


@contextlib.contextmanager
def painter_waiting_for_esc(words, seconds=600):
    """Within the body, a painter's thread (``modal_job.Worker``) whose progress message first holds ``words`` waits
    there until it is asked to stop (Esc): the window's timer events see that message and press Esc while that
    part is painted, however the two threads are scheduled. ``seconds`` only guards against a hang."""
    from paint_relief.addon import modal_job

    progress = modal_job.Worker.progress

    def waiting(worker, fraction, message):
        progress(worker, fraction, message)
        if words in message:
            worker.cancel.wait(seconds)

    modal_job.Worker.progress = waiting
    try:
        yield
    finally:
        modal_job.Worker.progress = progress


def write_frame(bpy, path, number, size=(WIDTH, HEIGHT)):
    """Write a PNG frame whose gradient moves 3 px a frame."""
    import numpy as np

    os.makedirs(os.path.dirname(path), exist_ok=True)
    width, height = size
    y, x = np.mgrid[0:height, 0:width]
    pixels = np.stack([(x + 3 * number) % width / width, y / height, np.full(x.shape, 0.5), np.ones(x.shape)], -1)
    image = bpy.data.images.new("frame", width, height)
    image.pixels.foreach_set(pixels[::-1].astype(np.float32).ravel())
    image.filepath_raw = path
    image.file_format = "PNG"
    image.save()
    bpy.data.images.remove(image)


def differing_files(folder, reference):
    """The painted frame files (not report.json, which holds seconds) whose bytes differ between two folders,
    or that only one holds."""
    names = sorted(set(os.listdir(folder)) | set(os.listdir(reference)))
    differing = []
    for name in names:
        if name == "report.json":
            continue
        first, second = os.path.join(folder, name), os.path.join(reference, name)
        if not (os.path.isfile(first) and os.path.isfile(second)):
            differing.append(name)
        elif open(first, "rb").read() != open(second, "rb").read():
            differing.append(name)
    return differing


if __name__ == "__main__":
    if not os.environ.get("BLENDER_USER_RESOURCES"):
        sys.exit("BLENDER_USER_RESOURCES is not set: refusing to touch a real user profile")
    work_dir = os.path.abspath(sys.argv[1])
    shutil.rmtree(work_dir, ignore_errors=True)
    os.makedirs(work_dir)
    main(work_dir)
