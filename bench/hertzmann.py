"""Benchmark of the Hertzmann 1998 baseline (Impressionist style) at default settings.

Prints, for photographs of 1 megapixel by default, the median seconds over
several runs (analysis, strokes, total), the stroke count, strokes per
second, the PSNR and the peak memory; and the paper's painter on the same
image for comparison.
Usage: python bench/hertzmann.py [--runs N] [--sizes 1] [--style impressionist]
"""

from __future__ import annotations

import argparse

from common import median_runs, peak_mib, photo
from core import Params
from core.methods import paint


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--sizes", default="1", help="megapixels, comma-separated")
    parser.add_argument("--style", default="impressionist")
    args = parser.parse_args()
    print(f"{'method':>24} {'MP':>5} {'size':>11} {'strokes':>8} {'analysis s':>10} {'strokes s':>10} "
          f"{'total s':>8} {'strokes/s':>10} {'PSNR dB':>8} {'peak MiB':>9}")
    for mp in (float(s) for s in args.sizes.split(",")):
        image = photo(mp)
        h, w = image.shape[:2]
        for label, params in ((f"hertzmann98/{args.style}", Params(method="hertzmann98", style=args.style)),
                              ("huang11", Params())):
            result = {}

            def run():
                result["painting"] = painting = paint(image, params)
                seconds = painting.statistics["seconds"]
                return {"analysis": sum(v for k, v in seconds.items() if k != "strokes"),
                        "strokes": seconds["strokes"]}

            medians = median_runs(run, args.runs)
            peak = peak_mib(lambda: paint(image, params))
            stats = result["painting"].statistics
            print(f"{label:>24} {h * w / 1e6:5.2f} {w:>5}x{h:<5} {stats['strokes']:>8} {medians['analysis']:>10.2f} "
                  f"{medians['strokes']:>10.2f} {medians['total']:>8.2f} {stats['strokes'] / medians['strokes']:>10.0f} "
                  f"{stats['psnr_db']:>8.2f} {peak:>9.0f}", flush=True)


if __name__ == "__main__":
    main()
