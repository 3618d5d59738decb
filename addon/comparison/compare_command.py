# SPDX-License-Identifier: GPL-3.0-or-later
"""The lighting comparison from the command line: paint, stage, render a light sweep, compare.

Part of the extension, so an installed extension runs it
(``blender --command paint_relief compare INPUT -o OUTDIR``, addon/cli_command.py);
``sample_scenes/compare.py`` launches the same :func:`main` from a checkout,
under Blender or with the ``bpy`` module (under Blender the arguments follow ``--``)::

    blender -b --python-exit-code 1 --python sample_scenes/compare.py -- INPUT -o OUTDIR [options]
    .venv/bin/python sample_scenes/compare.py INPUT -o OUTDIR [options]

Steps, each printed with its time:

1. load the extension: the package this module belongs to, registered
   when its operators are not (and its libraries checked);
2. paint: INPUT scaled so its longer side is at most ``--size`` px (never
   enlarged; a 16-bit PNG ``OUTDIR/input.png``) is painted with
   ``core.paint_file`` into ``OUTDIR/painting`` - or the maps there are
   reused when that folder's report.json has the same parameters and
   ``input.png`` came out byte for byte the same;
3. scene: an empty scene; the extension's operators build the canvas (the
   chosen displacement method and paint thickness, 40 cm wide), add the key
   light only (no fill, so the comparison has one light; brightness 1, so
   white paint renders 1.0) and the orthographic camera; Cycles on the CPU,
   render size = map size (100 %), 'Standard' view, float RGB OpenEXR;
4. renders: for every azimuth, ``OUTDIR/renders/relief_AAA.exr`` and, with
   the relief switched off, ``flat_AAA.exr`` (``addon/comparison/compare.py``);
5. ``OUTDIR/scene.blend``;
6. ``core.evaluation.comparison.run_comparison`` writes comparison.json, comparison.md,
   comparison.png, correlation.png and light_sweep.gif into OUTDIR.

Azimuths are degrees in the image from +x (right) towards +y (down): 0 =
light from the right, 90 = from the bottom, 180 = left, 270 = top, the same
convention as the painter's ``light`` command and the add-on's Lighting panel.

A bad input (no image, an unreadable image, an output folder that cannot be
written, ``--azimuths 0``, ...) ends with one sentence on stderr and exit
code 1 (2 for a malformed command line). The script calls ``sys.exit(code)``,
which ends Blender with that code too; ``--python-exit-code 1`` makes an
unexpected Python exception in the script end Blender with 1 as well.
"""

import argparse
import importlib
import os
import sys
import time
from pathlib import Path

from .. import command_line

DEFAULT_SIZE = 384


def _azimuth_count(text):
    value = command_line.number(text, int, "the light sweep's azimuth count must be a whole number, got {!r}")
    if value < 1:
        raise argparse.ArgumentTypeError("a light sweep needs at least 1 azimuth, got {}".format(value))
    return value


def build_parser():
    parser = command_line.Parser(
        prog="compare.py",
        description="Paint INPUT, render its canvas in Cycles under a sweep of raking lights with and without "
                    "relief, and compare the renders with the painter's 2-D lighting models.",
        epilog="Azimuths follow the painter: degrees from image +x (right) towards +y (down). "
               "Under Blender: blender -b --python-exit-code 1 --python sample_scenes/compare.py -- INPUT -o OUTDIR.")
    parser.add_argument("input", metavar="INPUT", help="the photograph to paint (PNG, JPEG, TIFF, EXR, ...)")
    parser.add_argument("-o", "--output", metavar="OUTDIR", required=True,
                        help="output folder: painting/, renders/, scene.blend and the comparison files")
    parser.add_argument("--azimuths", type=_azimuth_count, default=8, metavar="N",
                        help="number of light azimuths, evenly spaced from 0 degrees (default 8)")
    parser.add_argument("--elevation", type=command_line.elevation_degrees, default=30.0, metavar="DEG",
                        help="light elevation above the canvas in degrees (default 30)")
    parser.add_argument("--size", type=command_line.positive_int, default=DEFAULT_SIZE, metavar="PX",
                        help="the input is scaled so its longer side is at most this many pixels before painting; "
                             "maps and renders have that size (default {})".format(DEFAULT_SIZE))
    parser.add_argument("--samples", type=command_line.positive_int, default=16, metavar="N",
                        help="Cycles samples per pixel (default 16)")
    command_line.add_canvas_arguments(parser)
    parser.add_argument("--seed", type=int, default=0, help="the painter's seed (default 0)")
    parser.add_argument("--quiet", action="store_true", help="print nothing but errors")
    return parser


def scaled_input(core, image, out_dir, size):
    """Write ``image`` (INPUT as read) scaled to a longer side of at most ``size`` px as OUTDIR/input.png.

    Returns (path, changed): changed is False when input.png was there already with the same bytes.
    """
    import numpy as np
    import OpenImageIO as oiio

    writing = importlib.import_module(core.__name__ + ".files.writing")
    h, w = image.shape[:2]
    scale = min(1.0, size / max(w, h))
    if scale < 1.0:
        nw, nh = max(1, round(w * scale)), max(1, round(h * scale))
        resized = oiio.ImageBufAlgo.resize(oiio.ImageBuf(np.ascontiguousarray(image)),
                                           roi=oiio.ROI(0, nw, 0, nh, 0, 1, 0, 3))
        image = np.clip(resized.get_pixels(oiio.FLOAT), 0.0, 1.0).astype(np.float32)
    path = Path(out_dir) / "input.png"
    temp = path.with_name(".input.tmp-{}.png".format(os.getpid()))
    writing.write_png(temp, image, bits=16)
    changed = not (path.is_file() and path.read_bytes() == temp.read_bytes())
    os.replace(temp, path)
    return path, changed


def paint(core, args, photo, params, out_dir, log):
    """Paint (or reuse) OUTDIR/painting from ``photo`` (INPUT as read); return its folder."""
    import json

    from ...core.files import shot_files

    image, changed = scaled_input(core, photo, out_dir, args.size)
    painting_dir = out_dir / "painting"
    if not changed and (painting_dir / shot_files.REPORT_FILE).is_file():
        try:
            report = shot_files.read_report(painting_dir) or {}
        except (OSError, ValueError):
            report = {}
        same_input = Path(str(report.get("input", ""))).resolve() == image.resolve()
        maps = all((painting_dir / name).is_file() for name in ("color.exr", "height.exr", "opacity.exr",
                                                                  "orientation.exr"))
        if same_input and maps and report.get("params") == json.loads(json.dumps(params.to_dict())):
            log.say("    reusing the painting in {} (same input and parameters)".format(painting_dir))
            return painting_dir
    report = core.paint_file(str(image), str(painting_dir), params)
    log.say("    {} strokes, {} x {} px".format(report.get("strokes", "?"), *_map_size(painting_dir, core)))
    return painting_dir


def _map_size(painting_dir, core):
    data = importlib.import_module(core.__name__ + ".files.reading").read_exr(painting_dir / "height.exr")[0]
    return data.shape[1], data.shape[0]


def stage_scene(package, args, painting_dir, azimuths):
    """An empty scene with the canvas, the key light at the first azimuth and the camera (one render pixel per
    map pixel), set to render the sweep; returns the canvas."""
    scene = command_line.stage_canvas(painting_dir, args, azimuths[0])
    package.addon.comparison.compare.configure_render(scene, args.samples)
    return package.addon.scene.canvas_plane.find_role(scene, "canvas")


def main(argv, prog=None):
    """Run the comparison for ``argv`` (a program name first; Blender's own arguments end at "--"); return the exit code."""
    parser = build_parser()
    if prog:
        parser.prog = prog
    args = parser.parse_args(command_line.script_arguments(argv))
    log = command_line.Log(args.quiet)
    started = time.perf_counter()
    try:
        input_path = Path(args.input)
        if not input_path.is_file():
            raise command_line.Failure("The input image {} does not exist.".format(input_path)
                          if not input_path.exists() else "The input {} is not a file.".format(input_path))

        log.step("extension", "Loading the Paint Relief extension")
        import bpy

        package, where = command_line.load_extension()
        core = importlib.import_module(package.__name__ + ".core")
        reading = importlib.import_module(core.__name__ + ".files.reading")
        writing = importlib.import_module(core.__name__ + ".files.writing")
        importlib.import_module(package.__name__ + ".addon.comparison.compare")
        log.say("    from {}".format(where))
        values = package.addon.values
        azimuths = values.sweep_azimuths(args.azimuths)
        values.check_render_names(azimuths)
        params = core.Params(seed=args.seed).validate()
        photo = reading.read_image(input_path, params.max_megapixels, params.canvas_colour)  # checked before any output
        out_dir = Path(writing.ensure_output_dir(args.output)).resolve()

        log.step("paint", "Painting {} (longer side at most {} px) into {}".format(
            input_path, args.size, out_dir / "painting"))
        painting_dir = paint(core, args, photo, params, out_dir, log)

        log.step("scene", "Building the canvas, the key light and the camera ({}, {:g} mm paint)".format(
            args.method, args.thickness_mm))
        with command_line.quiet_stdout(args.quiet):
            canvas_obj = stage_scene(package, args, painting_dir, azimuths)
        compare = package.addon.comparison.compare

        log.step("renders", "Rendering {} lights x (relief, flat) with Cycles, {} samples, elevation {:g} degrees"
                 .format(len(azimuths), args.samples, args.elevation))
        renders_dir = out_dir / "renders"

        def progress(fraction, message):
            log.say("    {:3.0f}% {}".format(100 * fraction, message))

        with command_line.quiet_stdout(args.quiet):
            compare.render_sweep(bpy.context, canvas_obj, azimuths, args.elevation, str(renders_dir), args.samples,
                                 progress=progress)

        log.step("blend", "Saving {}".format(out_dir / "scene.blend"))
        with command_line.quiet_stdout(args.quiet):
            bpy.ops.wm.save_as_mainfile(filepath=str(out_dir / "scene.blend"), check_existing=False)

        log.step("comparison", "Comparing the renders with the 2-D lighting models")
        result = compare.compare(core, str(painting_dir), str(renders_dir), azimuths, args.elevation, str(out_dir),
                                 relief_px=compare.relief_pixels(canvas_obj))
        log.end()
    except SystemExit:
        raise
    except Exception as error:  # every failure ends with one sentence
        sys.stderr.write(command_line.sentence(error, "compare.py") + "\n")
        return 1

    log.seconds(started)
    best = result.get("best_azimuth_deg")
    if best is not None:
        log.say("The paper's lighting matches the relief best with the light at {:g} degrees (r = {:+.3f})."
                .format(best, result.get("best_pearson", float("nan"))))
    log.say("Pictures: {0}/comparison.png, {0}/correlation.png, {0}/light_sweep.gif; figures: {0}/comparison.md, "
            "{0}/comparison.json; renders in {0}/renders, the scene in {0}/scene.blend".format(out_dir))
    return 0
