"""Paint an object's texture in its UV space, then film it on a turntable: relit as impasto, lit by the paper's
2-D model, and with its original material.

    blender -b --python-exit-code 1 --python sample_scenes/paint_object.py -- [MODEL] [--object NAME] \\
        -o OUTDIR [--texture-size N] [--views V] [--samples S] [--resolution PX] [--seed N] \\
        [--relief DISPLACE|CYCLES_ADAPTIVE|NORMAL_MAP]
    .venv/bin/python sample_scenes/paint_object.py [MODEL] [--object NAME] -o OUTDIR [options]

MODEL is a .blend scene, opened, or a model file, .glb, .gltf, .obj or .fbx,
imported into an empty scene by Blender's own importer for its extension
(``model_files.py``), as a user would. With ``--object NAME`` that object is
painted. Without it, every mesh object that has a material is painted, each
with Paint Object, one after another in name order; an object Paint Object
refuses (a mesh shared with another object, say) has its sentence on stderr
and the others are painted: the run succeeds when at least one object was
painted. With no MODEL, the demo scene of ``sample_scenes/object_scene.py``
is built (a box whose UV islands differ 4x in texel density) and its
``Box`` painted. Steps, each printed with its time:

1. the scene is opened, imported (or built) and saved as it is, before any
   painting, as ``OUTDIR/original.blend``, and the extension loaded;
2. Paint Object paints each object's texture into ``OUTDIR/maps`` (painted
   without ``--object``: ``OUTDIR/maps/<object>``) and gives the object its
   painted material and displaced relief;
3. a camera circles the painted objects (all of them framed) in V views under
   one raking sun, rendered by
   Cycles with the Vector pass three times: the painted object
   (``OUTDIR/turntable/relit/NNNN.png``), the object showing the paper's
   Eq. 6-7 applied in texture space (``lit_paper.png`` of the maps, as
   emission, without relief: ``turntable/paper/``) and the object with its
   original material (``turntable/original/``); ``turntable/side_by_side/``
   holds relit and paper next to each other;
4. ``OUTDIR/object.json``: the report's per-island figures and, for each
   film, the warping error from each view to the next by the render's own
   Vector pass, their means and the relit film's over the original's; and
   the colour step across the mesh's UV seams against the step across as
   many edges inside islands in the renders (``render_seam_steps``), and in
   the texture, source and painted (``texture_seam_steps``, the report's
   "seam_steps"). Painted without ``--object``, "objects" names the objects
   painted, "refused" gives each refused one's sentence, "per_object" holds
   each one's maps folder, stroke widths, islands and texture seam steps, and
   "islands" all the islands, each with its object; the films' figures cover
   all painted objects together;
5. ``OUTDIR/scene.blend``, the painted scene.

The maps are written as the painter commits them: all together or not at
all, over an earlier painting's in ``OUTDIR/maps`` and beside any other
file there. A bad input ends with one sentence on stderr and exit code 1 (2
for a malformed command line, 130 for Ctrl-C outside the painter; Ctrl-C
while it paints is its one sentence and 1); it leaves OUTDIR as it was (an OUTDIR this
run made is removed again), with any earlier painting in it.
"""

from __future__ import annotations

import argparse
import importlib
import json
import math
import shutil
import signal
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from extension import extension_package  # noqa: E402 (the launcher's folder first)
from model_files import ModelError, is_model, open_model  # noqa: E402

FILMS = ("relit", "paper", "original")
SEAM_OFFSET = 2.0
"""Pixels: how far on either side of an edge's picture the colour step across it is sampled."""
EDGE_POINTS = (0.25, 0.5, 0.75)
"""Where along each edge the step is sampled (fractions of its length)."""
SUN_ELEVATION = 25.0
"""Degrees: the raking sun's height above the horizon."""
CAMERA_ELEVATION = 20.0
"""Degrees: the camera's height above the object's centre, seen from it."""


def arguments(argv):
    parser = argparse.ArgumentParser(prog="paint_object.py", description=__doc__.splitlines()[0])
    parser.add_argument("scene", nargs="?", type=Path, metavar="MODEL",
                        help="the .blend scene, or the .glb, .gltf, .obj or .fbx model, holding the objects "
                             "(default: the demo)")
    parser.add_argument("--object", default=None, metavar="NAME",
                        help="the mesh object to paint (default: every mesh object that has a material; Box of "
                             "the demo)")
    parser.add_argument("-o", "--output", type=Path, required=True, metavar="OUTDIR", help="folder for the results")
    parser.add_argument("--texture-size", type=int, default=2048, metavar="N",
                        help="texels a side of the painted texture, 64 to 16384; one of the panel's Texture Size "
                             "choices (1024, 2048, 4096, 8192) is also set there (default 2048)")
    parser.add_argument("--views", type=int, default=24, metavar="V", help="turntable views (default 24)")
    parser.add_argument("--samples", type=int, default=16, metavar="S", help="Cycles samples (default 16)")
    parser.add_argument("--resolution", type=int, default=384, metavar="PX", help="square render size (default 384)")
    parser.add_argument("--seed", type=int, default=0, help="the painter's seed (default 0)")
    parser.add_argument("--relief", default="DISPLACE", choices=("DISPLACE", "CYCLES_ADAPTIVE", "NORMAL_MAP"),
                        help="how the paint's thickness shows on the object, as the panel's Relief (default DISPLACE)")
    args = parser.parse_args(argv[argv.index("--") + 1:] if "--" in argv else argv[1:])
    if args.views < 2 or args.samples < 1 or args.resolution < 16:
        parser.error("the turntable needs at least 2 views, 1 sample and 16 px")
    return args


class Failure(Exception):
    """A bad input or a failed step: the message is one sentence."""


def open_scene(args):
    """Open SCENE, import the model or build the demo; return the objects to paint, in name order: the one
    ``--object`` names (Box of the demo), else every mesh object of the scene that has a material."""
    import bpy

    if args.scene is None:
        sys.path.insert(0, str(Path(__file__).resolve().parent))
        import object_scene

        obj = object_scene.build()
        return [bpy.data.objects[args.object or obj.name]]
    if is_model(args.scene):
        try:
            open_model(args.scene)
        except ModelError as error:
            raise Failure(str(error)) from None
        kind = "model"
    elif not args.scene.suffix.lower().startswith(".blend"):
        raise Failure(f"The model {args.scene} is no file Blender imports here: give a .glb, .gltf, .obj or .fbx "
                      f"file, or a .blend scene.")
    else:
        if not args.scene.is_file():
            raise Failure(f"The scene {args.scene} does not exist.")
        try:
            bpy.ops.wm.open_mainfile(filepath=str(args.scene.resolve()))
        except RuntimeError:
            raise Failure(f"Blender {bpy.app.version_string} cannot open the scene {args.scene}: it is not a .blend "
                          f"file, or one this Blender cannot read.") from None
        kind = "scene"
    if args.object is not None:
        if args.object not in bpy.data.objects:
            raise Failure(f"The {kind} {args.scene} has no object named {args.object}.")
        return [bpy.data.objects[args.object]]
    found = sorted((obj for obj in bpy.context.scene.objects
                    if obj.type == "MESH" and any(slot.material for slot in obj.material_slots)),
                   key=lambda obj: obj.name)
    if not found:
        raise Failure(f"The {kind} {args.scene} has no mesh object with a material, so there is nothing to paint: "
                      f"give one a material, or name the object to paint with --object.")
    return found


def folder_name(name, taken):
    """A folder name for the object ``name``: its name with any character a file system might refuse as "_",
    made unique against ``taken`` (a set it is added to)."""
    safe = "".join(c if c.isalnum() or c in "-_. " else "_" for c in name).strip(" .") or "object"
    unique, k = safe, 2
    while unique.lower() in taken:
        unique, k = f"{safe}_{k}", k + 1
    taken.add(unique.lower())
    return unique


def paint(obj, args, maps):
    """Paint Object on ``obj`` into ``maps`` (through the operator, as the panel does)."""
    import bpy

    layer = bpy.context.view_layer
    if layer.objects.get(obj.name) is None:
        raise Failure(f"Object {obj.name} is not in view layer {layer.name}: include its collection, then paint.")
    for other in layer.objects:
        other.select_set(False)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    settings = bpy.context.scene.paint_relief
    if args.panel_size:
        settings.object_texture_size = str(args.texture_size)
    settings.object_output_dir = str(maps)
    settings.seed = args.seed
    settings.object_relief = args.relief
    try:
        result = bpy.ops.paint_relief.paint_object(texture_size=0 if args.panel_size else args.texture_size)
    except RuntimeError as error:
        if "KeyboardInterrupt" in str(error):     # Ctrl-C before the painter ran: Blender's own traceback
            raise KeyboardInterrupt from None
        text = " ".join(str(error).split())
        raise Failure(text[len("Error: "):] if text.startswith("Error: ") else text) from None
    if "FINISHED" not in result:
        raise Failure(f"Paint Object did not finish on {obj.name}.")
    return json.loads((maps / "report.json").read_text())


def turntable(objects, args):
    """A camera circling ``objects`` (a list; all in the picture: it turns about the centre of their bounding
    boxes' corners in the world, at 3.2 times the farthest corner's distance) over frames 1..V (one view a frame,
    so the Vector pass holds its motion), one raking sun, Cycles with the Vector pass into multilayer EXR; returns
    the scene."""
    import bpy
    from mathutils import Vector

    scene = bpy.context.scene
    corners = [obj.matrix_world @ Vector(corner) for obj in objects for corner in obj.bound_box]
    if len(objects) == 1:
        centre = sum(corners, Vector()) / len(corners)
    else:
        centre = Vector([(min(c[axis] for c in corners) + max(c[axis] for c in corners)) / 2 for axis in range(3)])
    radius = max((c - centre).length for c in corners)
    pivot = bpy.data.objects.new("Turntable", None)
    pivot.location = centre
    scene.collection.objects.link(pivot)
    camera = bpy.data.objects.new("Turntable Camera", bpy.data.cameras.new("Turntable Camera"))
    scene.collection.objects.link(camera)
    distance = 3.2 * radius
    camera.location = (0.0, -distance * math.cos(math.radians(CAMERA_ELEVATION)),
                       distance * math.sin(math.radians(CAMERA_ELEVATION)))
    camera.rotation_euler = (math.radians(90 - CAMERA_ELEVATION), 0.0, 0.0)
    camera.parent = pivot
    scene.camera = camera
    scene.frame_start, scene.frame_end = 1, args.views
    edit = bpy.context.preferences.edit
    interpolation, edit.keyframe_new_interpolation_type = edit.keyframe_new_interpolation_type, "LINEAR"
    for frame in (1, args.views + 1):
        pivot.rotation_euler = (0.0, 0.0, 2 * math.pi * (frame - 1) / args.views)
        pivot.keyframe_insert("rotation_euler", index=2, frame=frame)
    edit.keyframe_new_interpolation_type = interpolation
    sun = bpy.data.objects.new("Raking Sun", bpy.data.lights.new("Raking Sun", "SUN"))
    sun.rotation_euler = (math.radians(90 - SUN_ELEVATION), 0.0, math.radians(60))
    sun.data.energy = 3.0
    scene.collection.objects.link(sun)
    scene.world = scene.world or bpy.data.worlds.new("World")
    render = scene.render
    render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = args.samples
    scene.cycles.use_denoising = False
    render.resolution_x = render.resolution_y = args.resolution
    render.resolution_percentage = 100
    render.use_motion_blur = False
    scene.view_settings.view_transform = "Standard"
    bpy.context.view_layer.use_pass_vector = True
    bpy.context.view_layer.use_pass_z = True
    image = render.image_settings
    if hasattr(image, "media_type"):
        image.media_type = "MULTI_LAYER_IMAGE"
    image.file_format = "OPEN_EXR_MULTILAYER"
    image.color_depth = "32"
    return scene


def paper_material(maps, uv_map):
    """A material showing ``maps``/lit_paper.png as emission (the paper's lighting, which knows no surface)
    through the UV map ``uv_map`` (the atlas's for a texture set of several sources or tiles)."""
    import bpy

    material = bpy.data.materials.new("Paint Relief Paper Lighting")
    if material.node_tree is None:
        material.use_nodes = True
    tree = material.node_tree
    for node in list(tree.nodes):
        tree.nodes.remove(node)
    texture = tree.nodes.new("ShaderNodeTexImage")
    texture.image = bpy.data.images.load(str(maps / "lit_paper.png"))
    coordinates = tree.nodes.new("ShaderNodeUVMap")
    coordinates.uv_map = uv_map
    emission = tree.nodes.new("ShaderNodeEmission")
    output = tree.nodes.new("ShaderNodeOutputMaterial")
    tree.links.new(coordinates.outputs["UV"], texture.inputs["Vector"])
    tree.links.new(texture.outputs["Color"], emission.inputs["Color"])
    tree.links.new(emission.outputs["Emission"], output.inputs["Surface"])
    return material


def render_film(scene, folder, seen=None):
    """Render frames 1..V into ``folder``/NNNN.exr; returns the paths. ``seen(frame)`` (optional) is called with
    each frame set, before its render."""
    import bpy

    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for frame in range(scene.frame_start, scene.frame_end + 1):
        scene.frame_set(frame)
        if seen is not None:
            seen(frame)
        scene.render.filepath = str(folder / f"{frame:04d}.exr")
        bpy.ops.render.render(write_still=True)
        paths.append(folder / f"{frame:04d}.exr")
    return paths


def mesh_edges(obj):
    """(seams, inner): the object's edges between two faces, as (K, 2, 3) world positions of their ends, split by
    whether the two faces' UVs meet along them (inner) or part there (a UV seam)."""
    import numpy as np

    mesh = obj.data
    layer = mesh.uv_layers.active.data
    world = np.array(obj.matrix_world)
    corners = {}
    for polygon in mesh.polygons:
        for loop in polygon.loop_indices:
            corners.setdefault(mesh.loops[loop].vertex_index, []).append((polygon.index, tuple(layer[loop].uv)))
    faces = {}
    for polygon in mesh.polygons:
        for key in polygon.edge_keys:
            faces.setdefault(key, []).append(polygon.index)
    seams, inner = [], []
    for key, owners in faces.items():
        if len(owners) != 2:
            continue
        uv = [{face: uv for face, uv in corners[vertex]} for vertex in key]
        split = any(np.abs(np.subtract(ends[owners[0]], ends[owners[1]])).max() > 1e-6 for ends in uv)
        ends = [(world @ np.array([*mesh.vertices[v].co, 1.0]))[:3] for v in key]
        (seams if split else inner).append(ends)
    return np.array(seams).reshape(-1, 2, 3), np.array(inner).reshape(-1, 2, 3)


def edge_views(scene, edges):
    """For the frame set now: each edge sample's picture (``EDGE_POINTS`` along each of (K, 2, 3) ``edges``) as
    (K * P, 2) pixel positions (x right, y down), the unit normal of the edge's picture there (K * P, 2) and the
    sample's distance from the camera (K * P,)."""
    import numpy as np
    from bpy_extras.object_utils import world_to_camera_view
    from mathutils import Vector

    width, height = scene.render.resolution_x, scene.render.resolution_y
    points, normals, depths = [], [], []
    for start, end in edges:
        ends = [world_to_camera_view(scene, scene.camera, Vector(p)) for p in (start, end)]
        along = np.array([(ends[1].x - ends[0].x) * width, (ends[0].y - ends[1].y) * height])
        normal = np.array([-along[1], along[0]]) / max(np.hypot(*along), 1e-9)
        for t in EDGE_POINTS:
            at = world_to_camera_view(scene, scene.camera, Vector(start + t * (end - start)))
            points.append((at.x * width, (1.0 - at.y) * height))
            normals.append(normal)
            depths.append((Vector(start + t * (end - start)) - scene.camera.matrix_world.translation).length)
    return np.array(points).reshape(-1, 2), np.array(normals).reshape(-1, 2), np.array(depths)


def render_seam_steps(core, pictures, views, depth_paths, count_seams):
    """{film: {"seam": step, "inner": step}}: the mean absolute difference (sRGB, over RGB) of the pixels
    SEAM_OFFSET on either side of each visible edge sample, over the views, for the seam samples (the first
    ``count_seams`` edges' of each view) and the inner ones. A sample is visible where the render's depth there
    is its own distance (within 3 %) and both sides lie in the picture."""
    import numpy as np

    reading = importlib.import_module(core.__name__ + ".files.reading")
    steps = {film: {"seam": [], "inner": []} for film in pictures}
    for k, (points, normals, distances) in enumerate(views):
        depth = reading.read_pass(depth_paths[k], "Depth", "Z")[..., 0]
        h, w = depth.shape
        sides = [np.rint(points + sign * SEAM_OFFSET * normals).astype(int) for sign in (-1, 1)]
        centre = np.rint(points).astype(int)
        inside = np.all([(p[:, 0] >= 0) & (p[:, 0] < w) & (p[:, 1] >= 0) & (p[:, 1] < h) for p in sides + [centre]],
                        axis=0)
        seen = np.zeros(len(points), bool)
        seen[inside] = np.abs(depth[centre[inside, 1], centre[inside, 0]] - distances[inside]) \
            < 0.03 * distances[inside]
        seam = np.arange(len(points)) < count_seams * len(EDGE_POINTS)
        for film, frames in pictures.items():
            frame = frames[k]
            step = np.abs(frame[sides[0][seen, 1], sides[0][seen, 0]] - frame[sides[1][seen, 1], sides[1][seen, 0]])
            step = step.mean(axis=1)
            steps[film]["seam"].extend(step[seam[seen]].tolist())
            steps[film]["inner"].extend(step[~seam[seen]].tolist())
    return {film: {kind: float(np.mean(values)) if values else None for kind, values in found.items()}
            | {"samples": {kind: len(values) for kind, values in found.items()}} for film, found in steps.items()}


def film_statistics(core, films, out, views, count_seams):
    """Each film's warping error from each view to the next by the relit film's Vector pass (the camera moves
    alike in every film) and its steps across seams and inner edges (``render_seam_steps`` of the edge samples
    ``views``); its PNG frames into ``out``/turntable/<film>/ and relit | paper side by side."""
    reading = importlib.import_module(core.__name__ + ".files.reading")
    writing = importlib.import_module(core.__name__ + ".files.writing")
    frames_module = importlib.import_module(core.__name__ + ".files.frames")
    motion = importlib.import_module(core.__name__ + ".motion")
    pictures = {name: [reading.read_image(path) for path in paths] for name, paths in films.items()}
    for name, frames in pictures.items():
        (out / "turntable" / name).mkdir(parents=True, exist_ok=True)
        for number, picture in enumerate(frames, 1):
            writing.write_png(out / "turntable" / name / f"{number:04d}.png", picture)
    sides = out / "turntable" / "side_by_side"
    sides.mkdir(parents=True, exist_ok=True)
    import numpy as np

    for number, (relit, paper) in enumerate(zip(pictures["relit"], pictures["paper"], strict=True), 1):
        writing.write_png(sides / f"{number:04d}.png", np.concatenate([relit, paper], axis=1))
    errors = {name: [] for name in films}
    vectors = [frames_module.read_vector_pass(path) for path in films["relit"]]
    for k in range(len(vectors) - 1):
        forward, backward = motion.motion_pair(vectors[k], vectors[k + 1])
        visible = motion.visible_in_both(forward, backward)
        for name, frames in pictures.items():
            errors[name].append(float(motion.warping_error(frames[k], frames[k + 1], forward, visible)))
    means = {name: float(np.nanmean(values)) for name, values in errors.items()}
    return {"warping_error": errors, "mean_warping_error": means,
            "relit_over_original": means["relit"] / means["original"] if means["original"] else None,
            "render_seam_steps": render_seam_steps(core, pictures, views, films["relit"], count_seams)}


def random_choice(count, wanted, seed):
    """(min(count, wanted),) int: that many of ``count`` indices, drawn without replacement (seeded), in order."""
    import numpy as np

    return np.sort(np.random.default_rng(seed).choice(count, min(count, wanted), replace=False))


def main(argv):
    args = arguments(argv)
    started, times = time.perf_counter(), []
    out = args.output.resolve()
    created = not out.exists()      # a failed run removes the folder it made; an existing one keeps what it held

    def step(name):
        # Ctrl-C is this script's to answer in every step (one sentence, its folder left whole), also when the
        # process that started it ignores SIGINT (a shell's background command, `core object`) or Blender took
        # the signal for itself in the step before.
        signal.signal(signal.SIGINT, signal.default_int_handler)
        times.append((name, time.perf_counter()))
        print(f"[{name}]", flush=True)

    partial = out / "original.partial.blend"    # original.blend until the painted scene is saved beside it
    try:
        step("scene")
        import bpy
        import numpy as np

        objects = open_scene(args)
        shown_frame = bpy.context.scene.frame_current     # the pose the scenes are saved in
        single = args.object is not None or args.scene is None
        if out.exists() and not out.is_dir():
            raise Failure(f"Cannot write to output folder {out}: a file of that name is in the way.")
        out.mkdir(parents=True, exist_ok=True)
        bpy.ops.wm.save_as_mainfile(filepath=str(partial), copy=True, check_existing=False)
        package = extension_package("PAINT_RELIEF_OT_paint_object")
        if not hasattr(bpy.types, "PAINT_RELIEF_OT_paint_object"):
            package.register()
        core = importlib.import_module(package.__name__ + ".core")
        object_material = importlib.import_module(package.__name__ + ".addon.objects.object_material")
        surface = importlib.import_module(package.__name__ + ".addon.objects.surface")
        choices = importlib.import_module(package.__name__ + ".addon.values").TEXTURE_SIZE_CHOICES
        args.panel_size = args.texture_size in choices
        if not 64 <= args.texture_size <= 16384:
            raise Failure(f"The texture size must be a whole number of texels from 64 to 16384, got "
                          f"{args.texture_size}.")
        step("paint")
        painted, refused, taken = {}, {}, set()
        for obj in objects:
            maps = out / "maps" if single else out / "maps" / folder_name(obj.name, taken)
            try:
                painted[obj.name] = (obj, maps, paint(obj, args, maps))
            except Failure as error:
                if single or len(objects) == 1 or str(error).startswith(f"Painting {obj.name} was stopped"):
                    raise
                refused[obj.name] = str(error)
                sys.stderr.write(f"{error}\n")
        if not painted:
            raise Failure(f"No object of {args.scene} was painted: Paint Object refused each of its "
                          f"{len(objects)} mesh objects with a material, as said above.")
        objects = [obj for obj, _, _ in painted.values()]
        step("renders")
        scene = turntable(objects, args)
        edges = [mesh_edges(obj) for obj in objects]
        seams = np.concatenate([found[0] for found in edges])
        inner = np.concatenate([found[1] for found in edges])
        inner = inner[random_choice(len(inner), len(seams), args.seed)]
        views = []
        films = {"relit": render_film(scene, out / "renders" / "relit", lambda frame: views.append(
            edge_views(scene, np.concatenate([seams, inner]))))}
        for obj in objects:
            object_material.show_painting(obj, False)
        films["original"] = render_film(scene, out / "renders" / "original")
        for obj, maps, _ in painted.values():
            atlas = obj.data.uv_layers.get(object_material.ATLAS_UV_MAP)
            paper = paper_material(maps, (atlas or obj.data.uv_layers[surface.uv_map_name(obj)]).name)
            for slot in obj.material_slots:
                slot.material = paper
        films["paper"] = render_film(scene, out / "renders" / "paper")
        for obj in objects:
            object_material.show_painting(obj, True)
        step("figures")
        statistics = film_statistics(core, films, out, views, len(seams))
        common = {"texture_size": args.texture_size, "views": args.views, "relief": args.relief}
        if single:
            ((obj, _, report),) = painted.values()
            summary = {"object": obj.name, **common, "stroke_mm": report["stroke_mm"], "islands": report["islands"],
                       "texture_seam_steps": report["seam_steps"], **statistics}
        else:
            summary = {"objects": list(painted), "refused": refused, **common,
                       "per_object": {name: {"maps": maps.relative_to(out).as_posix(),
                                             "stroke_mm": report["stroke_mm"], "islands": report["islands"],
                                             "texture_seam_steps": report["seam_steps"]}
                                      for name, (_, maps, report) in painted.items()},
                       "islands": [{"object": name, **island} for name, (_, _, report) in painted.items()
                                   for island in report["islands"]], **statistics}
        (out / "object.json").write_text(json.dumps(summary, indent=2) + "\n")
        step("blend")
        scene.frame_set(shown_frame)
        bpy.ops.wm.save_as_mainfile(filepath=str(out / "scene.blend"), check_existing=False)
        partial.replace(out / "original.blend")
    except KeyboardInterrupt:   # Ctrl-C outside the painter (which says so in its own sentence)
        if created:
            shutil.rmtree(out, ignore_errors=True)
        else:
            partial.unlink(missing_ok=True)
        step = times[-1][0] if times else "scene"
        kept = (f"the folder {out} it made was removed" if created else
                f"{out} holds what the steps before it wrote" if step not in ("scene", "paint") else f"{out} is as it was")
        sys.stderr.write(f"Interrupted (Ctrl-C) in the {step} step: {kept}.\n")
        return 130
    except Exception as error:  # a bad input or a failed step: one sentence
        if created:
            shutil.rmtree(out, ignore_errors=True)
        elif out.is_dir():
            partial.unlink(missing_ok=True)
        if type(error).__name__ not in ("Failure", "InputError", "OutputError", "ParameterError", "Cancelled"):
            raise
        sys.stderr.write(f"{error}\n")
        return 1
    times.append(("end", time.perf_counter()))
    for (name, start), (_, stop) in zip(times, times[1:], strict=False):
        print(f"    {name:<8} {stop - start:7.1f} s")
    print(f"    {'total':<8} {time.perf_counter() - started:7.1f} s")
    means, ratio = summary["mean_warping_error"], summary["relit_over_original"]
    print("Mean warping error from view to view: relit {relit:.5f}, paper {paper:.5f}, original {original:.5f}"
          .format(**means) + "; relit / original {}.".format("n/a (the original's is 0)" if ratio is None
                                                             else f"{ratio:.2f}"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
