# SPDX-License-Identifier: GPL-3.0-or-later
"""What the extension's command-line runs share (the lighting comparison, ``comparison/compare_command.py``,
and the relit film, ``film/film_command.py``): their arguments, their log, their one-sentence failures, the
extension loaded and the canvas staged in an empty scene.

``bpy`` is imported inside the functions that need it, so the argument
parsers serve ``blender --command paint_relief`` before any scene exists.
"""

import argparse
import importlib
import math
import os
import sys
import time

CANVAS_WIDTH_CM = 40.0
KEY_BRIGHTNESS = 1.0
"""Brightness of the key light on a flat canvas: white paint renders at 1.0, so the renders stay well above the
comparison's dark-pixel threshold."""

USER_ERRORS = ("Failure", "SweepError", "FilmError", "CanvasError", "InputError", "OutputError", "ParameterError",
               "PaintReliefError", "Cancelled", "ValueError", "OSError")
"""The exceptions whose messages are sentences for the user as they stand."""


class Failure(Exception):
    """The run cannot go on; the message is one sentence."""


class Parser(argparse.ArgumentParser):
    """argparse, but a malformed command line ends with ONE sentence (no usage block) and exit code 2."""

    def error(self, message):
        message = message.rstrip(".")
        self.exit(2, "{}: {} (see --help).\n".format(self.prog, message[:1].upper() + message[1:]))


def number(text, convert, not_a_number):
    """``convert(text)`` (``int`` or ``float``); argparse's error ``not_a_number`` (formatted with ``text``)
    when ``text`` is not such a number."""
    try:
        return convert(text)
    except ValueError:
        raise argparse.ArgumentTypeError(not_a_number.format(text)) from None


def positive_int(text):
    value = number(text, int, "{!r} is not a whole number")
    if value < 1:
        raise argparse.ArgumentTypeError("{} must be at least 1".format(value))
    return value


def elevation_degrees(text):
    value = number(text, float, "{!r} is not a number of degrees")
    if not 0.0 < value <= 90.0:
        raise argparse.ArgumentTypeError("the light elevation must be above 0 and at most 90 degrees, got {:g}".format(value))
    return value


def thickness_millimetres(text):
    value = number(text, float, "{!r} is not a number of millimetres")
    if not value > 0.0:
        raise argparse.ArgumentTypeError("the paint thickness must be above 0 mm, got {:g}".format(value))
    return value


def add_canvas_arguments(parser):
    """The options of the canvas both runs build: ``--method`` and ``--thickness-mm``."""
    parser.add_argument("--method", choices=("MESH", "CYCLES_ADAPTIVE"), default="MESH",
                        help="how the relief becomes geometry (default MESH)")
    parser.add_argument("--thickness-mm", type=thickness_millimetres, default=2.0, metavar="MM",
                        help="height in millimetres of paint of height 1 (default 2)")


def script_arguments(argv):
    """The script's own arguments: those after "--" when there is one (Blender), else argv[1:]."""
    return argv[argv.index("--") + 1:] if "--" in argv else argv[1:]


class Log:
    """Progress lines and step times on stdout (nothing with --quiet)."""

    def __init__(self, quiet):
        self.quiet = quiet
        self.times = []
        self.stream = None  # a file to print to instead of sys.stdout
        self._start = None
        self._name = None

    def say(self, text):
        if not self.quiet:
            print(text, file=self.stream or sys.stdout, flush=True)

    def step(self, name, text):
        self.end()
        self._name, self._start = name, time.perf_counter()
        self.say("[{}] {}".format(name, text))

    def end(self):
        if self._name is not None:
            self.times.append((self._name, time.perf_counter() - self._start))
            self._name = None

    def seconds(self, started):
        """The seconds of every step and of the whole run (begun at ``time.perf_counter()`` = ``started``)."""
        self.say("")
        self.say("Seconds per step:")
        for name, seconds in self.times:
            self.say("    {:<11} {:7.1f}".format(name, seconds))
        self.say("    {:<11} {:7.1f}".format("total", time.perf_counter() - started))


def sentence(error, prog):
    """One sentence for an exception: its own message when it has one (prefixed "``prog`` failed:" unless it is
    one of USER_ERRORS), else its kind."""
    text = " ".join(str(error).split())
    if isinstance(error, OSError) and error.strerror:
        text = "{}{}.".format(error.strerror, ": " + str(error.filename) if error.filename else "")
    if not text:
        text = "{} failed with {}.".format(prog, type(error).__name__)
    elif type(error).__name__ not in USER_ERRORS:
        text = "{} failed: {}".format(prog, text)
    return text if text.endswith(".") else text + "."


class quiet_stdout:
    """With --quiet, silence what Blender itself prints (render statistics, 'Saved: ...') on file descriptor 1.

    Given a ``log``, its lines still reach the real standard output meanwhile.
    """

    def __init__(self, quiet, log=None):
        self.quiet = quiet
        self.log = log

    def __enter__(self):
        if self.quiet:
            sys.stdout.flush()
            self._saved = os.dup(1)
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, 1)
            os.close(devnull)
            if self.log is not None:
                self.log.stream = os.fdopen(os.dup(self._saved), "w")
        return self

    def __exit__(self, *exc):
        if self.quiet:
            sys.stdout.flush()
            os.dup2(self._saved, 1)
            os.close(self._saved)
            if self.log is not None:
                self.log.stream.close()
                self.log.stream = None
        return False


def load_extension():
    """The Paint Relief package this module belongs to, with its operators registered (registered here if not),
    and the folder it was loaded from."""
    import bpy

    package = importlib.import_module(__name__.rpartition(".addon.")[0])
    if not hasattr(bpy.types, "PAINT_RELIEF_OT_build_canvas"):
        package.register()
    missing = package.addon.dependencies.problem()
    if missing is not None:
        raise Failure(missing)
    return package, os.path.dirname(os.path.abspath(package.__file__))


def run_operator(operator, **options):
    """Run a Paint Relief operator; Failure with its one-sentence report when it does not finish."""
    try:
        result = operator(**options)
    except RuntimeError as error:  # an operator's ERROR report raises in background mode
        text = " ".join(str(error).split())
        raise Failure(text[len("Error: "):] if text.startswith("Error: ") else text) from None
    if "FINISHED" not in result:
        raise Failure("The operator {} did not finish.".format(operator.idname_py()))


def stage_canvas(painting_dir, args, azimuth_deg, **build_options):
    """An empty scene with the canvas of ``painting_dir`` (Build Canvas with ``build_options``; ``args.method``,
    ``args.thickness_mm``, CANVAS_WIDTH_CM wide), the key light alone at ``azimuth_deg`` and
    ``args.elevation`` (KEY_BRIGHTNESS, no fill light) and the orthographic camera, one render pixel per map
    pixel, through the extension's operators; returns the scene."""
    import bpy

    scene = bpy.context.scene
    for obj in list(scene.objects):  # the start-up file's cube, light and camera
        bpy.data.objects.remove(obj)
    settings = scene.paint_relief
    settings.painting_dir = str(painting_dir)
    settings.canvas_width_cm = CANVAS_WIDTH_CM
    settings.thickness_mm = args.thickness_mm
    settings.displacement_method = args.method
    settings.light_azimuth = math.radians(azimuth_deg)
    settings.light_elevation = math.radians(args.elevation)
    settings.light_strength = KEY_BRIGHTNESS
    settings.fill_light = False
    settings.camera_match_resolution = True
    settings.camera_standard_view = True
    ops = bpy.ops.paint_relief
    run_operator(ops.build_canvas, **build_options)
    run_operator(ops.add_lights)
    run_operator(ops.add_camera)
    return scene
