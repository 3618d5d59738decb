# SPDX-License-Identifier: GPL-3.0-or-later
"""``blender --command paint_relief paint|canvas|compare|animate ...``: the extension from a pipeline, no checkout needed.

Registered with ``bpy.utils.register_cli_command`` (Blender 4.2+). The
subcommands take the same options as the painter's command line and the
comparison script:

- ``paint INPUT -o OUTDIR [...]``: ``python -m core paint`` (exit 0, 2 for a
  bad input or command line, 130 when interrupted);
- ``canvas PAINTED_DIR -o SCENE.blend [--width-cm 40] [--thickness-mm 2]
  [--method MESH|CYCLES_ADAPTIVE|NORMAL_MAP] [--lights] [--camera]``: build
  the canvas in an empty scene and save it (exit 0, 1 on failure, 2 for a
  malformed command line);
- ``compare INPUT -o OUTDIR [...]``: ``sample_scenes/compare.py``;
- ``animate FRAMES -o OUTDIR [...]``: ``sample_scenes/animate.py``.
"""

import importlib
import sys

import bpy

COMMAND = "paint_relief"
USAGE = "usage: blender --command paint_relief paint|canvas|compare|animate ARGUMENTS (--help after each for its options)"
_handle = None


def _package():
    return importlib.import_module(__package__.rpartition(".")[0])


def _paint(argv):
    from . import dependencies

    missing = dependencies.problem()
    if missing is not None:
        sys.stderr.write(missing + "\n")
        return 1
    cli = importlib.import_module(_package().__name__ + ".core.cli")
    return cli.main(["paint", *argv])


def _canvas_parser():
    from .command_line import Parser

    parser = Parser(prog="blender --command paint_relief canvas",
                    description="Build a Paint Relief canvas from a painted folder in an empty scene and save it.")
    parser.add_argument("painting", metavar="PAINTED_DIR", help="folder with color.exr, height.exr, opacity.exr")
    parser.add_argument("-o", "--output", metavar="SCENE.blend", required=True, help="the .blend file to write")
    parser.add_argument("--width-cm", type=float, default=40.0, help="canvas width in cm (default 40)")
    parser.add_argument("--thickness-mm", type=float, default=2.0, help="paint thickness in mm (default 2)")
    parser.add_argument("--method", choices=("MESH", "CYCLES_ADAPTIVE", "NORMAL_MAP"), default="MESH",
                        help="how the relief is made (default MESH)")
    parser.add_argument("--lights", action="store_true", help="add the key and fill lights")
    parser.add_argument("--camera", action="store_true", help="add the camera, render size = map size")
    return parser


def _canvas(argv):
    import os

    args = _canvas_parser().parse_args(argv)
    if not hasattr(bpy.types, "PAINT_RELIEF_OT_build_canvas"):
        _package().register()
    bpy.ops.wm.read_homefile(use_empty=True)
    settings = bpy.context.scene.paint_relief
    settings.painting_dir = os.path.abspath(args.painting)
    settings.canvas_width_cm = args.width_cm
    settings.thickness_mm = args.thickness_mm
    settings.displacement_method = args.method
    settings.camera_match_resolution = True
    steps = [bpy.ops.paint_relief.build_canvas]
    steps += [bpy.ops.paint_relief.add_lights] if args.lights else []
    steps += [bpy.ops.paint_relief.add_camera] if args.camera else []
    try:
        for operator in steps:
            operator()
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.output), check_existing=False)
    except RuntimeError as error:  # an operator's ERROR report
        text = " ".join(str(error).split())
        sys.stderr.write((text[len("Error: "):] if text.startswith("Error: ") else text) + "\n")
        return 1
    return 0


def _compare(argv):
    from .comparison import compare_command

    return compare_command.main(["compare", "--", *argv], prog="blender --command paint_relief compare")


def _animate(argv):
    from .film import film_command

    return film_command.main(["animate", "--", *argv], prog="blender --command paint_relief animate")


SUBCOMMANDS = {"paint": _paint, "canvas": _canvas, "compare": _compare, "animate": _animate}


def execute(argv):
    """The command's body: ``argv`` are the arguments after ``paint_relief``; returns the exit code."""
    argv = list(argv)
    if not argv or argv[0] not in SUBCOMMANDS:
        sys.stderr.write(USAGE + "\n")
        return 2
    try:
        return int(SUBCOMMANDS[argv[0]](argv[1:]) or 0)
    except SystemExit as exit_:  # argparse's --help (0) and malformed command lines (2)
        return exit_.code if isinstance(exit_.code, int) else 2


def register():
    global _handle
    if hasattr(bpy.utils, "register_cli_command"):
        _handle = bpy.utils.register_cli_command(COMMAND, execute)


def unregister():
    global _handle
    if _handle is not None:
        bpy.utils.unregister_cli_command(_handle)
        _handle = None
