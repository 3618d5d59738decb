# SPDX-License-Identifier: GPL-3.0-or-later
"""Check what `make demo` wrote: every output it promises is there and whole.

    .venv/bin/python tools/check_demo.py [OUT] [--views V]

OUT is the demo's output folder (default ``out``), V the turntable views
``sample_scenes/paint_object.py`` filmed (default 8, as ``make demo`` asks).
Each picture must be a non-empty file that OpenImageIO reads (the GIF: a
GIF header and its size), at least 16 px a side and not one flat colour;
each JSON file must parse; each .blend and Markdown file must be non-empty.
Every problem is printed on a line of its own; the exit status is 1 when
there is one, else 0 after one line counting what was checked.
"""

import argparse
import json
import struct
import sys
from pathlib import Path

MIN_SIDE = 16
"""Pixels: the smallest width and height a demo picture may have."""
FILMS = ("relit", "paper", "original", "side_by_side")
"""The turntable films paint_object.py writes, one PNG a view each."""


def expected(views):
    """The files `make demo` promises, relative to its output folder."""
    files = ["analysis/" + name for name in ("reference.png", "importance.png", "importance.exr", "partition.png",
                                             "orientation.png", "analysis.json")]
    painted = ("color.exr", "height.exr", "opacity.exr", "orientation.exr", "painting.png", "lit_paper.png",
               "strokes.json", "report.json")
    files += ["painting/" + name for name in painted]
    files += ["compare/" + name for name in ("comparison.png", "correlation.png", "light_sweep.gif",
                                             "comparison.md", "comparison.json", "scene.blend",
                                             "renders/relief_000.exr", "renders/flat_000.exr")]
    files += ["object/maps/" + name for name in painted]
    files += ["object/object.json", "object/scene.blend"]
    files += ["object/turntable/{}/{:04d}.png".format(film, view) for film in FILMS for view in range(1, views + 1)]
    return files


def picture_problem(path):
    """Why ``path`` is not a whole picture (one sentence), or None."""
    if path.suffix == ".gif":
        head = path.read_bytes()[:10]
        if head[:6] not in (b"GIF87a", b"GIF89a") or len(head) < 10:
            return "is not a GIF file"
        width, height = struct.unpack("<HH", head[6:10])
        return None if min(width, height) >= MIN_SIDE else "is {} x {} px".format(width, height)
    import OpenImageIO as oiio

    source = oiio.ImageInput.open(str(path))
    if source is None:
        return "cannot be read: {}".format(oiio.geterror())
    try:
        spec = source.spec()
        if min(spec.width, spec.height) < MIN_SIDE:
            return "is {} x {} px".format(spec.width, spec.height)
        pixels = source.read_image(0, 0, 0, min(spec.nchannels, 3), "float")
        if pixels is None:
            return "cannot be read: {}".format(source.geterror())
    finally:
        source.close()
    if not pixels.size or float(pixels.max()) <= float(pixels.min()):
        return "is one flat colour"
    return None


def problem(path):
    """Why the demo's output ``path`` is missing or broken (one sentence), or None."""
    if not path.is_file():
        return "is missing"
    if path.stat().st_size == 0:
        return "is empty"
    if path.suffix in (".png", ".exr", ".gif"):
        return picture_problem(path)
    if path.suffix == ".json":
        try:
            json.loads(path.read_text())
        except ValueError as error:
            return "is not JSON: {}".format(error)
    return None


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default="out", type=Path, help="the demo's output folder (default out)")
    parser.add_argument("--views", type=int, default=8, help="turntable views the demo filmed (default 8)")
    args = parser.parse_args(argv)
    files = expected(args.views)
    problems = [(name, problem(args.out / name)) for name in files]
    problems = [(name, found) for name, found in problems if found is not None]
    for name, found in problems:
        print("check_demo: {} {}".format(args.out / name, found))
    if problems:
        print("check_demo: {} of the demo's {} outputs are missing or broken".format(len(problems), len(files)))
        return 1
    print("check_demo: all {} outputs of the demo in {} are there and whole".format(len(files), args.out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
