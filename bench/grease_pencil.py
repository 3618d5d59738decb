"""Benchmark of Strokes as Grease Pencil (addon/strokes/): a painting's strokes made a Grease Pencil object, and read
back for laying.

Paints a bundled photograph at each size once (default settings, seed 0, with the laying data) into a temporary
folder, then prints, per size, the stroke count and the median seconds over several runs of making the Grease
Pencil object in an empty scene (reading strokes.json included, as the operator does) and of reading its strokes
back as drawn strokes (what Lay Grease Pencil Strokes reads before laying), and the making's seconds per 10,000
strokes, with the Blender version. The target: a
1-megapixel painting's strokes (about 10,000) in at most 10 s.
Run with a Python that has the bpy module (Blender 4.3 and later make Grease Pencil 3, 4.2 the legacy one):
Usage: python bench/grease_pencil.py [--runs N] [--megapixels 1,2] [--sizes 32,16,8,4,2]
       [--sample coffee|astronaut|chelsea|hubble]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

from common import ROOT, SAMPLE, photo
from core import Params
from core.api import paint_file
from core.files import writing


def painted_folder(root: Path, megapixels: float, sample: Path, sizes=None) -> Path:
    """A folder painted by ``paint_file`` (with laying data) from ``sample`` resampled to about ``megapixels``, with
    the stroke ``sizes`` (px at 1 megapixel; None: the defaults)."""
    source = root / f"photo_{megapixels:g}.png"
    writing.write_png(source, photo(megapixels, sample))
    folder = root / f"painted_{megapixels:g}"
    params = Params(seed=0) if sizes is None else Params(seed=0, stroke_sizes=sizes)
    paint_file(source, folder, params, strokes_to_lay=True)
    return folder


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--megapixels", default="1,2", help="sizes, comma separated (default: %(default)s)")
    parser.add_argument("--sizes", default=None,
                        help="stroke sizes of the painting, comma separated (default: the painter's; smaller sizes "
                             "give more strokes)")
    parser.add_argument("--sample", default=SAMPLE.stem,
                        help="a photograph of sample_scenes/ by its name (default: %(default)s)")
    args = parser.parse_args()
    import bpy

    sys.path.insert(0, str(ROOT / "sample_scenes"))
    from extension import extension_package

    package = extension_package()
    if not hasattr(bpy.types, "PAINT_RELIEF_OT_build_canvas"):
        package.register()
    round_trip = package.addon.strokes.round_trip
    grease_pencil = package.addon.strokes.grease_pencil
    kind = "Grease Pencil 3" if grease_pencil.is_grease_pencil_3() else "legacy Grease Pencil"
    sample = next((ROOT / "sample_scenes").glob(f"{args.sample}.*"))
    print(f"Blender {bpy.app.version_string} ({kind}), {sample.name}, median of {args.runs} runs")
    print(f"{'MP':>5} {'size':>10} {'strokes':>8} {'points':>8} {'make s':>7} {'s/10k':>6} {'read s':>7}")
    with tempfile.TemporaryDirectory() as temp:
        root = Path(temp)
        for mp in (float(v) for v in args.megapixels.split(",")):
            sizes = tuple(int(v) for v in args.sizes.split(",")) if args.sizes else None
            folder = painted_folder(root, mp, sample, sizes)
            make, read = [], []
            for _ in range(args.runs):
                bpy.ops.wm.read_homefile(use_empty=True)
                context = bpy.context
                t0 = time.perf_counter()
                obj, count = round_trip.make_strokes(context, str(folder), 40.0, 2.0, 1, 250)
                make.append(time.perf_counter() - t0)
                t0 = time.perf_counter()
                drawn = grease_pencil.read_drawn(obj, package.core)
                read.append(time.perf_counter() - t0)
                assert len(drawn) == count
            image = photo(mp, sample)
            size = f"{image.shape[1]}x{image.shape[0]}"
            print(f"{mp:>5g} {size:>10} {count:>8} {int(drawn.counts.sum()):>8} {statistics.median(make):>7.3f} "
                  f"{statistics.median(make) / count * 1e4:>6.3f} {statistics.median(read):>7.3f}", flush=True)


if __name__ == "__main__":
    main()
