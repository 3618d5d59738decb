"""Benchmark of ``core svg`` (core/files/svg.py): a painting's strokes written as an SVG picture.

Paints a bundled photograph at each size once (default settings, seed 0) into a
temporary folder, then prints, per size, the stroke count, the median seconds of
writing its strokes.json as SVG over several runs (reading and checking the list
included), the seconds per 10,000 strokes and the SVG's size. The target: a
1-megapixel painting's strokes (about 10,000) in at most 2 s.
Usage: python bench/svg.py [--runs N] [--megapixels 0.25,1] [--sample coffee|astronaut|chelsea|hubble]
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

from common import ROOT, SAMPLE, median_runs, photo
from core import Params
from core.api import paint_file
from core.files import writing
from core.files.svg import write_svg


def painted_folder(root: Path, megapixels: float, sample: Path) -> Path:
    """A folder painted by ``paint_file`` from the photograph ``sample`` resampled to about ``megapixels``."""
    source = root / f"photo_{megapixels:g}.png"
    writing.write_png(source, photo(megapixels, sample))
    folder = root / f"painted_{megapixels:g}"
    paint_file(source, folder, Params(seed=0))
    return folder


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--megapixels", default="0.25,1", help="sizes, comma separated (default: %(default)s)")
    parser.add_argument("--sample", default=SAMPLE.stem,
                        help="a photograph of sample_scenes/ by its name (default: %(default)s)")
    args = parser.parse_args()
    sample = next((ROOT / "sample_scenes").glob(f"{args.sample}.*"))
    print(f"{sample.name}, median of {args.runs} runs")
    print(f"{'MP':>5} {'size':>10} {'strokes':>8} {'seconds':>8} {'s/10k':>6} {'SVG MB':>7} {'JSON MB':>8}")
    with tempfile.TemporaryDirectory() as temp:
        root = Path(temp)
        for mp in (float(v) for v in args.megapixels.split(",")):
            folder = painted_folder(root, mp, sample)
            out = root / f"strokes_{mp:g}.svg"
            counts = []
            medians = median_runs(lambda folder=folder, out=out: (counts.append(write_svg(folder, out)), {})[1],
                                  args.runs)
            image = photo(mp, sample)
            size = f"{image.shape[1]}x{image.shape[0]}"
            print(f"{mp:>5g} {size:>10} {counts[0]:>8} {medians['total']:>8.3f} "
                  f"{medians['total'] / counts[0] * 1e4:>6.3f} {out.stat().st_size / 1e6:>7.2f} "
                  f"{(folder / 'strokes.json').stat().st_size / 1e6:>8.2f}", flush=True)


if __name__ == "__main__":
    main()
