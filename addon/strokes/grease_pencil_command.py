# SPDX-License-Identifier: GPL-3.0-or-later
"""The Grease Pencil round trip from the command line (``sample_scenes/grease_pencil.py`` launches :func:`main`).

Under Blender the arguments follow ``--``; with the ``bpy`` module they follow the script::

    .venv/bin/python sample_scenes/grease_pencil.py PAINTED_DIR -o OUT.blend [--width-cm 40] [--thickness-mm 2]
        [--frames 1-250]
    .venv/bin/python sample_scenes/grease_pencil.py SCENE.blend --lay -o OUTDIR [--object NAME] [--reference PHOTO]

The first form builds, in an empty scene, the canvas of PAINTED_DIR (Build
Canvas, MESH relief) and the Grease Pencil object of its strokes on it
(Strokes as Grease Pencil), its Build modifier revealing the strokes over
the frame range (``--frames``, default 1-250, also the scene's), and saves
the scene as OUT.blend, written under a temporary name beside it and
renamed. The second opens SCENE.blend, takes its Grease Pencil object of a
painting (``--object``, else the active one, else the first) as it was saved
(strokes moved, deleted, recoloured, drawn anew in its Paint layer) and lays
it into the new painted folder OUTDIR (Lay Grease Pencil Strokes;
``--reference`` the photograph, else the one the painting's report.json
names). A bad input ends with one sentence on stderr and exit code 1 (2 for a
malformed command line).
"""

import argparse
import importlib
import os
import sys
import time

from .. import command_line

DEFAULT_FRAMES = (1, 250)


def _frames(text):
    parts = text.split("-")
    if len(parts) != 2 or not all(part.strip().isdigit() for part in parts):
        raise argparse.ArgumentTypeError("{!r} is not a frame range START-END".format(text))
    start, end = (int(part) for part in parts)
    if end <= start:
        raise argparse.ArgumentTypeError("the frame range {} ends before it starts".format(text))
    return start, end


def build_parser(prog="grease_pencil.py"):
    parser = command_line.Parser(
        prog=prog,
        description="Make a Grease Pencil object of a painting's strokes over its relief canvas and save the scene, "
                    "or lay the Grease Pencil strokes of a saved scene into a new painting.",
        epilog="Under Blender: blender -b --python-exit-code 1 --python sample_scenes/grease_pencil.py -- "
               "PAINTED_DIR -o OUT.blend.")
    parser.add_argument("input", metavar="PAINTED_DIR|SCENE.blend",
                        help="a folder painted by `python -m core paint` (with --strokes-to-lay to lay it again); "
                             "with --lay, a .blend holding a Grease Pencil object of a painting")
    parser.add_argument("-o", "--output", metavar="OUT.blend|OUTDIR", required=True,
                        help="the .blend file to write; with --lay, the folder of the new painting")
    parser.add_argument("--lay", action="store_true", help="lay the Grease Pencil strokes of SCENE.blend")
    parser.add_argument("--width-cm", type=float, default=command_line.CANVAS_WIDTH_CM, metavar="CM",
                        help="canvas width in cm (default {:g})".format(command_line.CANVAS_WIDTH_CM))
    parser.add_argument("--thickness-mm", type=command_line.thickness_millimetres, default=2.0, metavar="MM",
                        help="height in millimetres of paint of height 1 (default 2)")
    parser.add_argument("--frames", type=_frames, default=DEFAULT_FRAMES, metavar="START-END",
                        help="the frames over which the strokes appear (default {}-{})".format(*DEFAULT_FRAMES))
    parser.add_argument("--object", metavar="NAME", help="with --lay: the Grease Pencil object to lay")
    parser.add_argument("--reference", metavar="PHOTO",
                        help="with --lay: the photograph the painting was painted from (default: as its report.json "
                             "names it)")
    parser.add_argument("--quiet", action="store_true", help="print nothing but errors")
    return parser


def save_blend(bpy, path):
    """Save the open scene as ``path``: written under a temporary name in its folder, then renamed."""
    folder = os.path.dirname(os.path.abspath(path)) or "."
    os.makedirs(folder, exist_ok=True)
    temporary = os.path.join(folder, ".{}.{}.tmp.blend".format(os.path.basename(path), os.getpid()))
    try:
        bpy.ops.wm.save_as_mainfile(filepath=temporary, check_existing=False, copy=True)
        os.replace(temporary, path)
    finally:
        if os.path.exists(temporary):
            os.remove(temporary)


def make_scene(bpy, args, log):
    """An empty scene with the canvas of PAINTED_DIR and the Grease Pencil object of its strokes, saved."""
    folder = os.path.abspath(args.input)
    if not os.path.isdir(folder):
        raise command_line.Failure("The painted folder {} does not exist.".format(folder))
    if not args.output.lower().endswith(".blend"):
        raise command_line.Failure("The output {} is no .blend file: name it SCENE.blend.".format(args.output))
    scene = bpy.context.scene
    for obj in list(scene.objects):  # the start-up file's cube, light and camera
        bpy.data.objects.remove(obj)
    scene.frame_start, scene.frame_end = args.frames
    settings = scene.paint_relief
    settings.painting_dir = folder
    settings.canvas_width_cm = args.width_cm
    settings.thickness_mm = args.thickness_mm
    settings.displacement_method = "MESH"
    log.step("canvas", "Building the canvas of {}".format(folder))
    with command_line.quiet_stdout(True, log):
        command_line.run_operator(bpy.ops.paint_relief.build_canvas)
    log.step("strokes", "Making the Grease Pencil object of its strokes")
    started = time.perf_counter()
    command_line.run_operator(bpy.ops.paint_relief.strokes_to_grease_pencil)
    obj = bpy.context.view_layer.objects.active
    log.say("    {} strokes in {:.2f} s".format(len(_strokes(obj)), time.perf_counter() - started))
    log.step("blend", "Saving {}".format(os.path.abspath(args.output)))
    with command_line.quiet_stdout(True, log):
        save_blend(bpy, os.path.abspath(args.output))


def _strokes(obj):
    layer = obj.data.layers[0]
    frame = layer.frames[0]
    return frame.drawing.strokes if hasattr(frame, "drawing") else frame.strokes


def lay_scene(bpy, package, args, log):
    """Open SCENE.blend and lay its Grease Pencil object's strokes into OUTDIR; returns core's report."""
    path = os.path.abspath(args.input)
    if not os.path.isfile(path) or not path.lower().endswith(".blend"):
        raise command_line.Failure("The scene {} is no .blend file here: give the .blend holding the Grease Pencil "
                                   "object to lay.".format(path))
    grease_pencil = package.addon.strokes.grease_pencil
    round_trip = package.addon.strokes.round_trip
    log.step("open", "Opening {}".format(path))
    with command_line.quiet_stdout(True, log):
        bpy.ops.wm.open_mainfile(filepath=path)
    context = bpy.context
    if args.object:
        obj = context.scene.objects.get(args.object)
        if obj is None or obj.get(package.addon.scene.canvas_plane.ROLE_KEY) != grease_pencil.ROLE:
            raise command_line.Failure("The scene {} has no Grease Pencil object of a painting named {}.".format(
                path, args.object))
    else:
        obj = grease_pencil.active_strokes(context)
        if obj is None:
            raise command_line.Failure("The scene {} has no Grease Pencil object of a painting: make one with "
                                       "Strokes as Grease Pencil.".format(path))
    log.step("lay", "Laying the strokes of {} into {}".format(obj.name, os.path.abspath(args.output)))
    report = round_trip.lay_strokes(context, obj, os.path.abspath(args.output), reference=args.reference)
    log.say("    {} strokes laid".format(report.get("strokes")))
    return report


def main(argv, prog=None):
    """Run the command for ``argv`` (a program name first; Blender's own arguments end at "--"); return the exit
    code."""
    parser = build_parser(prog or "grease_pencil.py")
    args = parser.parse_args(command_line.script_arguments(argv))
    log = command_line.Log(args.quiet)
    started = time.perf_counter()
    try:
        if not os.path.exists(args.input):
            raise command_line.Failure("{} does not exist.".format(args.input))
        log.step("extension", "Loading the Paint Relief extension")
        import bpy

        package, where = command_line.load_extension()
        importlib.import_module(package.__name__ + ".addon.strokes.round_trip")
        log.say("    from {}".format(where))
        if args.lay:
            lay_scene(bpy, package, args, log)
        else:
            make_scene(bpy, args, log)
        log.end()
    except SystemExit:
        raise
    except Exception as error:  # every failure ends with one sentence
        sys.stderr.write(command_line.sentence(error, parser.prog) + "\n")
        return 1
    log.seconds(started)
    return 0
