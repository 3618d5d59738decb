# SPDX-License-Identifier: GPL-3.0-or-later
"""The shot flow from the installed zip: the scene's animation painted, its animated canvas, two Cycles frames,
and the ``animate`` command.

Run in its own process with BLENDER_USER_RESOURCES set to a throw-away folder::

    BLENDER_USER_RESOURCES=/tmp/u python tests/shipped/shot.py PACKAGE.zip WORK_DIR

Blender installs the zip as *Install from Disk* does; nothing of the checkout
is imported. A tiny animated scene (frames 11 to 14: a checkered ball
rolling past a brick wall, the camera panning) is painted by Paint Animation
from the scene's own renders; Build Canvas makes the animated canvas; the
evaluated relief is read at two frames; frames 11 and 14 are rendered with
Cycles through the extension's film renderer; ``cli_command.execute(["animate",
...])`` runs the whole film on a tiny shot of PNG frames.
The last line printed is ``RESULTS <json>``, which test_shot.py asserts on.
"""

import json
import os
import sys

from steps import MODULE, REPO, RESULTS, run_op, step  # tests/shipped/steps.py, beside this script

FIRST, FRAMES, WIDTH, HEIGHT = 11, 4, 64, 48


def write_shot(writing, folder):
    """FRAMES PNG frames numbered from FIRST: a checkered ball moving 8 px a frame to the right over stripes."""
    import numpy as np

    os.makedirs(folder, exist_ok=True)
    y, x = np.mgrid[0:HEIGHT, 0:WIDTH].astype(np.float32)
    background = np.stack([0.3 + 0.3 * x / WIDTH, 0.4 + 0.2 * np.sin(y / 4.0), 0.6 - 0.3 * y / HEIGHT], axis=-1)
    for number in range(FIRST, FIRST + FRAMES):
        cx, cy = WIDTH / 4 + 8 * (number - FIRST), HEIGHT / 2
        disc = ((x - cx) ** 2 + (y - cy) ** 2 < (HEIGHT / 4.5) ** 2)[..., None]
        ball = np.stack([0.9 + 0 * x, 0.8 * (((x - cx) // 5 + (y - cy) // 5) % 2), 0.1 + 0 * x], axis=-1)
        writing.write_png(os.path.join(folder, "frame_{:04d}.png".format(number)), np.where(disc, ball, background))
    return folder


def textured(bpy, name, texture, colours):
    """A material whose base colour is a ``texture`` node ('ShaderNodeTexBrick' or 'ShaderNodeTexChecker')."""
    material = bpy.data.materials.new(name)
    if material.node_tree is None:  # Blender 4.2 makes the tree only with use_nodes
        material.use_nodes = True
    tree = material.node_tree
    node = tree.nodes.new(texture)
    node.inputs["Color1"].default_value, node.inputs["Color2"].default_value = colours
    node.inputs["Scale"].default_value = 4.0
    bsdf = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    tree.links.new(node.outputs["Color"], bsdf.inputs["Base Color"])
    return material


def animated_scene(bpy):
    """The scene's animation, frames FIRST to FIRST + FRAMES - 1: a ball rolling past a wall, the camera panning."""
    import math

    scene = bpy.context.scene
    bpy.ops.mesh.primitive_plane_add(size=20.0, location=(0.0, 2.0, 0.0), rotation=(math.radians(90.0), 0.0, 0.0))
    bpy.context.object.data.materials.append(
        textured(bpy, "Wall", "ShaderNodeTexBrick", ((0.7, 0.3, 0.1, 1.0), (0.3, 0.1, 0.05, 1.0))))
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.8, location=(-1.5, 0.0, 0.0))
    ball = bpy.context.object
    ball.data.materials.append(
        textured(bpy, "Ball", "ShaderNodeTexChecker", ((0.9, 0.85, 0.2, 1.0), (0.1, 0.25, 0.7, 1.0))))
    bpy.ops.object.light_add(type="SUN", rotation=(math.radians(40.0), 0.0, math.radians(20.0)))
    bpy.context.object.data.energy = 3.0
    bpy.ops.object.camera_add(location=(0.0, -8.0, 0.0), rotation=(math.radians(90.0), 0.0, 0.0))
    camera = bpy.context.object
    scene.camera = camera
    for index in range(FRAMES):
        ball.location.x = -1.5 + 0.8 * index
        camera.location.x = 0.1 * index
        ball.keyframe_insert("location", frame=FIRST + index)
        camera.keyframe_insert("location", frame=FIRST + index)
    scene.frame_start, scene.frame_end = FIRST, FIRST + FRAMES - 1
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 2
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = WIDTH, HEIGHT, 100
    return scene


def main(zip_path, work):
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    result = bpy.ops.extensions.package_install_files(filepath=os.path.abspath(zip_path), repo=REPO,
                                                      enable_on_install=True)
    RESULTS["install"] = {"result": sorted(result), "enabled": MODULE in bpy.context.preferences.addons,
                          "blender": list(bpy.app.version)}
    from importlib import import_module

    import numpy as np

    # The painter's libraries as the extension finds them (Blender's own OpenImageIO, the zip's SciPy wheels).
    RESULTS["libraries"] = {"problem": sys.modules[MODULE + ".addon.dependencies"].problem()}
    writing = import_module(MODULE + ".core.files.writing")
    reading = import_module(MODULE + ".core.files.reading")
    animated = import_module(MODULE + ".addon.scene.animated")
    film = import_module(MODULE + ".addon.film.relit")
    compare = import_module(MODULE + ".addon.comparison.compare")
    cli_command = import_module(MODULE + ".addon.cli_command")
    ops = bpy.ops.paint_relief
    scene = bpy.context.scene
    settings = scene.paint_relief
    frames_dir = write_shot(writing, os.path.join(work, "frames"))
    sequence = os.path.join(work, "scene_painted")

    @step
    def paint_the_scenes_animation():
        animated_scene(bpy)
        settings.animation_source = "SCENE"
        settings.animation_output_dir = sequence
        settings.stroke_sizes = "24,12,6"
        settings.layers = 2
        result, error = run_op(ops.paint_animation)
        report = {}
        if os.path.isfile(os.path.join(sequence, "report.json")):
            with open(os.path.join(sequence, "report.json")) as file:
                report = json.load(file)
        return {"result": result, "error": error, "frames": report.get("frames"), "motion": report.get("motion"),
                "painting_dir": settings.painting_dir,
                "files": sorted(name for name in os.listdir(sequence) if name.startswith("height_"))
                if os.path.isdir(sequence) else []}

    def canvas_object():
        return next(obj for obj in scene.objects if obj.get("paint_relief_role") == "canvas")

    def hide_the_shot():
        """The animated scene's own objects out of the renders: the camera frames the canvas alone."""
        for obj in scene.objects:
            if obj.get("paint_relief_role") is None:
                obj.hide_render = obj.hide_viewport = True

    def heights(frame):
        scene.frame_set(frame)
        evaluated = canvas_object().evaluated_get(bpy.context.evaluated_depsgraph_get())
        mesh = evaluated.to_mesh()
        co = np.empty(len(mesh.vertices) * 3, dtype=np.float64)
        mesh.vertices.foreach_get("co", co)
        evaluated.to_mesh_clear()
        return co[2::3]

    @step
    def animated_canvas():
        hide_the_shot()
        settings.painting_dir = sequence
        settings.displacement_method = "MESH"
        scene.frame_start, scene.frame_end = 1, 250
        result, error = run_op(ops.build_canvas, frame_range=True)
        obj = canvas_object()
        readers = [{"file": os.path.basename(image.filepath), "source": image.source,
                    "duration": user.frame_duration, "start": user.frame_start, "offset": user.frame_offset,
                    "auto": user.use_auto_refresh} for image, user in animated.image_readers(obj)]
        first, last = heights(FIRST), heights(FIRST + FRAMES - 1)
        return {"result": result, "error": error, "readers": readers,
                "frame_range": [scene.frame_start, scene.frame_end],
                "heights_differ": float(np.abs(first - last).max()), "height_max": float(first.max()),
                "same_frame_again": float(np.abs(first - heights(FIRST)).max())}

    @step
    def two_cycles_frames():
        settings.fill_light = False
        settings.camera_match_resolution = True
        settings.camera_standard_view = True
        results = [run_op(ops.add_lights), run_op(ops.add_camera)]
        previous = film.configure_film(scene, 2, False, (WIDTH, HEIGHT))
        rendered = {}
        try:
            for frame in (FIRST, FIRST + FRAMES - 1):
                scene.frame_set(frame)
                path = os.path.join(work, "relit_{}.png".format(frame))
                compare.render_still(scene, path, film.FilmError)
                rendered[frame] = reading.read_image(path)
        finally:
            film.restore(previous)
        a, b = rendered[FIRST], rendered[FIRST + FRAMES - 1]
        return {"results": results, "shape": list(a.shape), "std": [float(a.std()), float(b.std())],
                "difference": float(np.abs(a - b).mean()), "engine_restored": scene.render.engine}

    @step
    def animate_command():
        out = os.path.join(work, "animate")
        code = cli_command.execute(["animate", frames_dir, "-o", out, "--samples", "1", "--size", "48", "--seed", "1",
                                    "--quiet"])
        bad = cli_command.execute(["animate", os.path.join(work, "no_such_frames"), "-o", out, "--quiet"])
        return {"code": code, "bad": bad, "movie_available": film.movie_available(),
                "relit": sorted(os.listdir(os.path.join(out, "relit"))) if os.path.isdir(out) else [],
                "paper": sorted(os.listdir(os.path.join(out, "paper"))) if os.path.isdir(out) else [],
                "files": sorted(name for name in os.listdir(out) if not os.path.isdir(os.path.join(out, name)))
                if os.path.isdir(out) else []}

    print("RESULTS " + json.dumps(RESULTS), flush=True)


if __name__ == "__main__":
    if not os.environ.get("BLENDER_USER_RESOURCES"):
        sys.exit("BLENDER_USER_RESOURCES is not set: refusing to touch a real user profile")
    main(sys.argv[1], sys.argv[2])
