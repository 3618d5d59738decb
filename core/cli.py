"""Command line: ``python -m core analyze INPUT -o OUTDIR`` and friends.

Every failure caused by input or settings ends with one sentence on stderr
and a non-zero exit; outputs are written only after all work succeeded,
each through a temporary name.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import List, Optional

from . import io
from .analysis import Analysis, analyze
from .errors import Cancelled, PaintReliefError, ParameterError
from .params import Params
from .progress import ConsoleProgress
from .staging import staged_outputs
from .version import __version__
from .visualize import orientation_picture, partition_overlay

DEFAULTS = Params()


def _sizes(text: str) -> tuple:
    try:
        sizes = tuple(int(s) for s in text.split(",") if s.strip())
    except ValueError:
        raise argparse.ArgumentTypeError(f"sizes must be whole numbers separated by commas, got {text!r}")
    return sizes


def _add_analysis_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("input", help="photograph to read (PNG, JPEG, TIFF, EXR, ...)")
    p.add_argument("-o", "--output", required=True, metavar="OUTDIR", help="folder for the outputs (created if missing)")
    p.add_argument("--sizes", type=_sizes, default=DEFAULTS.stroke_sizes, metavar="64,32,16,8,4",
                   help="standard stroke widths in px at 1 megapixel, scaled with the image (default: %(default)s)")
    p.add_argument("--detail", type=float, default=DEFAULTS.detail, metavar="X",
                   help="0..1, how finely detailed areas are split; the stop energy is "
                        "T_e = total energy * 10^-(2 + 3 X) (default: %(default)s)")
    p.add_argument("--mask", metavar="PATH", help="grayscale importance mask; white areas get smaller strokes (default: none)")
    p.add_argument("--mask-strength", type=float, default=DEFAULTS.mask_strength, metavar="K",
                   help="k in E' = E (1 + k mask) (default: %(default)s)")
    p.add_argument("--seed", type=int, default=DEFAULTS.seed, metavar="N", help="random seed (default: %(default)s)")
    p.add_argument("--max-megapixels", type=float, default=DEFAULTS.max_megapixels, metavar="N",
                   help="refuse inputs larger than this (default: %(default)s)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress line on stderr")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every subcommand."""
    parser = argparse.ArgumentParser(prog="python -m core", description="Paint Relief's painter.")
    parser.add_argument("--version", action="version", version=f"paint-relief {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    analyze_p = sub.add_parser(
        "analyze", help="reference image, importance map, canvas partition and orientation field",
        description="Write reference.png, importance.exr/.png, partition.png, orientation.png and analysis.json.")
    _add_analysis_options(analyze_p)
    analyze_p.set_defaults(run=run_analyze)

    paint_p = sub.add_parser(
        "paint", help="paint a photograph stroke by stroke and write its relief maps",
        description="Write color.exr (scene-linear RGB), height.exr, opacity.exr, painting.png, "
                    "strokes.json and report.json.")
    _add_analysis_options(paint_p)
    paint_p.add_argument("--layers", type=int, default=DEFAULTS.layers, metavar="N",
                         help="layers of strokes, each one pass over all grids (default: %(default)s)")
    paint_p.add_argument("--brush", default=DEFAULTS.brush, metavar="flat|round|filbert|PATH",
                         help="a shipped brush or a grayscale PNG brush map, wide side across "
                              "(default: %(default)s)")
    paint_p.add_argument("--height-mode", choices=("over", "accumulate"), default=DEFAULTS.height_mode,
                         help="'over': each stroke's height covers what is below (the paper); "
                              "'accumulate': paint piles up (default: %(default)s)")
    paint_p.add_argument("--alpha", type=float, default=DEFAULTS.bristle_alpha, metavar="A",
                         help="weight of each bristle's own colour in Eq. 5 (default: %(default)s)")
    paint_p.set_defaults(run=run_paint)
    return parser


def params_from_args(args: argparse.Namespace) -> Params:
    """Params from parsed options (those the subcommand has), validated."""
    fields = {"stroke_sizes": tuple(args.sizes), "detail": args.detail, "mask_strength": args.mask_strength,
              "seed": args.seed, "max_megapixels": args.max_megapixels}
    for option, name in (("layers", "layers"), ("brush", "brush"), ("height_mode", "height_mode"),
                         ("alpha", "bristle_alpha")):
        if hasattr(args, option):
            fields[name] = getattr(args, option)
    return Params(**fields).validate()


def run_analyze(args: argparse.Namespace, progress) -> None:
    """The ``analyze`` subcommand."""
    params = params_from_args(args)
    out = io.ensure_output_dir(args.output)
    image = io.read_image(args.input, params.max_megapixels, params.canvas_colour)
    mask = io.read_gray(args.mask, params.max_megapixels) if args.mask else None
    analysis = analyze(image, params, mask=mask, progress=progress)
    with staged_outputs(out) as staging:
        write_analysis(staging, analysis, params, args.input)


def run_paint(args: argparse.Namespace, progress) -> None:
    """The ``paint`` subcommand."""
    from .api import paint_file

    paint_file(args.input, args.output, params_from_args(args), progress=progress, mask_path=args.mask)


def write_analysis(out: Path, analysis: Analysis, params: Params, source: str) -> None:
    """Write the analysis pictures, maps and figures into folder ``out``."""
    t0 = time.perf_counter()
    attributes = {"paint_relief:version": __version__, "paint_relief:seed": params.seed,
                  "paint_relief:params": json.dumps(params.to_dict(), sort_keys=True)}
    io.write_png(out / "reference.png", analysis.reference)
    io.write_exr(out / "importance.exr", analysis.importance, channels=("Y",), attributes=attributes)
    io.write_png(out / "importance.png", analysis.importance)
    io.write_png(out / "partition.png",
                 partition_overlay(analysis.reference, analysis.grids, analysis.grid_sizes, analysis.sizes))
    io.write_png(out / "orientation.png", orientation_picture(analysis.orientation, analysis.reference, params.seed))
    summary = analysis.summary()
    summary["seconds"]["pictures"] = round(time.perf_counter() - t0, 4)
    summary.update({"input": str(source), "version": __version__, "seed": params.seed, "params": params.to_dict()})
    io.write_json(out / "analysis.json", summary)


def main(argv: Optional[List[str]] = None) -> int:
    """Entry point; returns the process exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    console = None if args.quiet else ConsoleProgress()
    try:
        args.run(args, console)
    except Cancelled as exc:
        return _fail(console, str(exc), 130)
    except KeyboardInterrupt:
        return _fail(console, "Interrupted; no output was written.", 130)
    except PaintReliefError as exc:
        return _fail(console, f"error: {exc}", 2)
    if console is not None:
        console.close()
    return 0


def _fail(console, message: str, status: int) -> int:
    """End the progress line, print one line to stderr, return ``status``."""
    if console is not None:
        console.close()
    print(f"paint-relief: {message}", file=sys.stderr)
    return status
