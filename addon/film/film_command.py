# SPDX-License-Identifier: GPL-3.0-or-later
"""The relit painted film from the command line: paint a shot, build its animated canvas, render it, measure it.

Part of the extension, so an installed extension runs it
(``blender --command paint_relief animate FRAMES -o OUTDIR``, addon/cli_command.py);
``sample_scenes/animate.py`` launches the same :func:`main` from a checkout,
under Blender or with the ``bpy`` module (under Blender the arguments follow ``--``)::

    blender -b --python-exit-code 1 --python sample_scenes/animate.py -- FRAMES -o OUTDIR [options]
    .venv/bin/python sample_scenes/animate.py FRAMES -o OUTDIR [options]

FRAMES is footage (a folder of frames, a ``#`` pattern such as
``render/frame_####.exr``, as ``python -m core sequence`` takes it) or a
folder already painted by ``python -m core sequence``. Steps, each printed
with its time:

1. load the extension (``addon/command_line.py``);
2. paint: footage is painted with ``core.paint_sequence_files`` into
   ``OUTDIR/painted`` at the footage's size (a run stopped part way goes on
   after its last complete frame; a painted folder is used as it is);
3. scene: an empty scene; the Build Canvas operator builds the animated
   canvas (``--method``, ``--thickness-mm``, 40 cm wide) and sets the scene's
   frame range to the sequence; the key light alone (brightness 1, so white
   paint on a flat canvas renders 1.0) at ``--azimuth`` and ``--elevation``,
   and the orthographic camera; the render is the map's aspect with its
   longer side ``--size`` px (never larger than the maps);
4. film: every frame rendered with Cycles into ``OUTDIR/relit/NNNN.png``
   (``addon/film/relit.py``), one line per frame with its seconds;
5. ``OUTDIR/scene.blend``, set to render the same film (Render Animation);
6. ``core.evaluation.film.run_film``: the paper's 2-D lighting
   of every frame (``OUTDIR/paper/NNNN.png``), footage | relit | paper side by
   side (``OUTDIR/side_by_side/NNNN.png``, ``animation.gif``), the warping
   errors (``animation.json``, ``animation.md``);
7. ``OUTDIR/animation.mp4`` from the side-by-side frames with Blender's own
   FFmpeg, when this Blender has it.

Azimuths are degrees in the image from +x (right) towards +y (down), as for
the painter's ``light`` command and ``compare.py``. A bad input ends with one
sentence on stderr and exit code 1 (2 for a malformed command line).
"""

import importlib
import os
import sys
import time
from pathlib import Path

from .. import command_line

DEFAULT_SIZE = 480
DEFAULT_SAMPLES = 16
DEFAULT_AZIMUTH = 135.0
"""Degrees (the painter's convention): the light comes from the lower left of the picture, raking."""
DEFAULT_ELEVATION = 30.0


def _azimuth(text):
    return command_line.number(text, float, "{!r} is not a number of degrees") % 360.0


def build_parser(prog="animate.py"):
    parser = command_line.Parser(
        prog=prog,
        description="Paint a shot (or take a painted sequence), build its animated relief canvas in Blender, render "
                    "every frame with Cycles under a raking light, light it with the paper's 2-D model too, and "
                    "measure how steady both films are against the footage.",
        epilog="Azimuths follow the painter: degrees from image +x (right) towards +y (down). Under Blender: "
               "blender -b --python-exit-code 1 --python sample_scenes/animate.py -- FRAMES -o OUTDIR.")
    parser.add_argument("frames", metavar="FRAMES",
                        help="footage (a folder of frames or a pattern such as render/frame_####.exr) or a folder "
                             "painted by `python -m core sequence`")
    parser.add_argument("-o", "--output", metavar="OUTDIR", required=True,
                        help="output folder: painted/, relit/, paper/, side_by_side/, animation.gif, animation.mp4, "
                             "animation.json, animation.md, scene.blend")
    parser.add_argument("--samples", type=command_line.positive_int, default=DEFAULT_SAMPLES, metavar="N",
                        help="Cycles samples per pixel (default {})".format(DEFAULT_SAMPLES))
    parser.add_argument("--size", type=command_line.positive_int, default=DEFAULT_SIZE, metavar="PX",
                        help="longer side of the renders and films in pixels, at most the painted maps' "
                             "(default {}); the painting keeps the footage's size".format(DEFAULT_SIZE))
    parser.add_argument("--azimuth", type=_azimuth, default=DEFAULT_AZIMUTH, metavar="DEG",
                        help="the light's azimuth in degrees (default {:g}: from the lower left)".format(DEFAULT_AZIMUTH))
    parser.add_argument("--elevation", type=command_line.elevation_degrees, default=DEFAULT_ELEVATION, metavar="DEG",
                        help="the light's elevation above the canvas in degrees (default {:g})".format(DEFAULT_ELEVATION))
    parser.add_argument("--seed", type=int, default=0, help="the painter's seed (default 0)")
    command_line.add_canvas_arguments(parser)
    parser.add_argument("--denoise", action="store_true", help="Cycles' denoiser on (off by default)")
    parser.add_argument("--quiet", action="store_true", help="print nothing but errors")
    return parser


def paint(core, package, args, out_dir, log):
    """The painted sequence's folder: FRAMES when it is one, else OUTDIR/painted painted (or gone on with) from
    the footage FRAMES."""
    frames = os.path.abspath(args.frames)
    if package.addon.values.sequence_frames(frames) is not None:
        log.say("    {} is a painted sequence: using it as it is".format(frames))
        return Path(frames)
    painted = out_dir / "painted"
    done = package.addon.values.sequence_frames(str(painted))
    if done:
        log.say("    {} frames painted already in {}: going on after frame {}".format(len(done), painted, done[-1]))
    shown = {"frame": None}

    def progress(fraction, message):
        frame = message.split(":", 1)[0]
        if frame != shown["frame"]:
            shown["frame"] = frame
            log.say("    {:3.0f}% painting {}".format(100 * fraction, frame.lower()))

    params = core.Params(seed=args.seed).validate()
    report = core.paint_sequence_files([args.frames], str(painted), params, progress=progress)
    log.say("    {} frames, {} x {} px, motion from the {}".format(
        len(report["frames"]), report["width"], report["height"], report["motion"]))
    return painted


def stage_scene(package, args, painted_dir):
    """An empty scene with the animated canvas (the scene's frame range set to the sequence), the key light and
    the camera; returns (canvas, film size)."""
    scene = command_line.stage_canvas(painted_dir, args, args.azimuth, frame_range=True)
    canvas_obj = package.addon.scene.canvas_plane.find_role(scene, "canvas")
    relit = package.addon.film.relit
    size = package.addon.values.film_size(*relit.canvas_map_size(canvas_obj), args.size)
    return canvas_obj, size


def save_scene(relit, scene, out_dir, args, size):
    """Save OUTDIR/scene.blend set to render the film as it was rendered (Render Animation writes relit/NNNN.png)."""
    import bpy

    previous = relit.configure_film(scene, args.samples, args.denoise, size)
    previous.append((scene.render, "filepath", scene.render.filepath))
    scene.render.filepath = str(out_dir / "relit" / "####")
    try:
        bpy.ops.wm.save_as_mainfile(filepath=str(out_dir / "scene.blend"), check_existing=False)
    finally:
        relit.restore(previous)


def main(argv, prog=None):
    """Run the film for ``argv`` (a program name first; Blender's own arguments end at "--"); return the exit code."""
    parser = build_parser(prog or "animate.py")
    args = parser.parse_args(command_line.script_arguments(argv))
    log = command_line.Log(args.quiet)
    started = time.perf_counter()
    try:
        if "#" not in args.frames and not os.path.exists(args.frames):
            raise command_line.Failure("The frames {} do not exist.".format(args.frames))

        log.step("extension", "Loading the Paint Relief extension")
        import bpy

        package, where = command_line.load_extension()
        core = importlib.import_module(package.__name__ + ".core")
        writing = importlib.import_module(core.__name__ + ".files.writing")
        evaluation = importlib.import_module(core.__name__ + ".evaluation.film")
        relit = importlib.import_module(package.__name__ + ".addon.film.relit")
        log.say("    from {}".format(where))
        out_dir = Path(writing.ensure_output_dir(args.output)).resolve()

        log.step("paint", "Painting {} into {}".format(args.frames, out_dir / "painted"))
        painted_dir = paint(core, package, args, out_dir, log)

        log.step("scene", "Building the animated canvas, the key light and the camera ({}, {:g} mm paint)".format(
            args.method, args.thickness_mm))
        with command_line.quiet_stdout(True, log):
            canvas_obj, size = stage_scene(package, args, painted_dir)
        frames = relit.check_film(bpy.context.scene, canvas_obj, args.samples)

        log.step("film", "Rendering {} frames at {} x {} px with Cycles, {} samples, light at {:g} degrees, elevation "
                 "{:g} degrees".format(len(frames), size[0], size[1], args.samples, args.azimuth, args.elevation))

        def progress(fraction, message):
            if message.startswith("Rendered"):
                log.say("    {:3.0f}% {}".format(100 * fraction, message))

        with command_line.quiet_stdout(True, log):  # Blender's render statistics hidden, the frame lines shown
            seconds = relit.render_film(bpy.context, canvas_obj, str(out_dir / "relit"), args.samples, size,
                                       args.denoise, progress=progress)

        log.step("blend", "Saving {}".format(out_dir / "scene.blend"))
        with command_line.quiet_stdout(True, log):
            save_scene(relit, bpy.context.scene, out_dir, args, size)

        log.step("measures", "Lighting every frame with the paper's model; warping errors against the footage")
        render = {"samples": args.samples, "denoise": args.denoise, "method": args.method,
                  "thickness_mm": args.thickness_mm, "seconds": [round(s, 3) for s in seconds],
                  "seconds_per_frame": round(sum(seconds) / len(seconds), 3)}
        result = evaluation.run_film(painted_dir, out_dir / "relit", out_dir, args.azimuth, args.elevation,
                                         render=render)

        movie = None
        if relit.movie_available():
            log.step("movie", "Encoding {} with Blender's FFmpeg".format(out_dir / "animation.mp4"))
            with command_line.quiet_stdout(True, log):
                movie = relit.encode_movie(str(out_dir / "side_by_side"), frames,
                                          _png_size(out_dir / "side_by_side" / relit.frame_file(frames[0])),
                                          str(out_dir / "animation.mp4"))
        log.end()
    except SystemExit:
        raise
    except Exception as error:  # every failure ends with one sentence
        sys.stderr.write(command_line.sentence(error, parser.prog) + "\n")
        return 1

    errors = result["warping_error"]
    log.seconds(started)
    log.say("Cycles took {:.2f} s per frame at {} x {} px.".format(render["seconds_per_frame"], *size))
    log.say("Warping error: footage {:.5f}, relit {:.5f} ({}), paper {:.5f} ({}), unlit painting {:.5f} "
            "({}).".format(errors["footage"]["mean"], errors["relit"]["mean"], _times(errors["relit"]["ratio"]),
                           errors["paper"]["mean"], _times(errors["paper"]["ratio"]), errors["painting"]["mean"],
                           _times(errors["painting"]["ratio"])))
    log.say("Films: {0}/relit, {0}/paper, {0}/animation.gif{1}; figures: {0}/animation.md, {0}/animation.json; "
            "the scene in {0}/scene.blend".format(out_dir, ", {}/animation.mp4".format(out_dir) if movie else ""))
    return 0


def _times(ratio):
    """A ratio to the footage's warping error as "1.23x", or "no ratio" when the footage's is 0 (a still's
    time-lapse) and the ratio has no value."""
    return "{:.2f}x".format(ratio) if ratio == ratio and abs(ratio) != float("inf") else "no ratio to a still"


def _png_size(path):
    """(width, height) of a PNG from its header."""
    with open(path, "rb") as file:
        header = file.read(24)
    return int.from_bytes(header[16:20], "big"), int.from_bytes(header[20:24], "big")
