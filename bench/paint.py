"""Benchmark of the painter at default settings.

Prints, for photographs of 0.25, 1 and 4 megapixels, the median seconds over
several runs (analysis and strokes), the stroke count, strokes per second and
the peak memory.
Usage: python bench/paint.py [--runs N] [--sizes 0.25,1,4]
"""

from __future__ import annotations

import argparse

from common import median_runs, peak_mib, photo
from core import Params
from core.methods import paint


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--sizes", default="0.25,1,4", help="megapixels, comma-separated")
    args = parser.parse_args()
    params = Params()
    print(f"{'MP':>5} {'size':>11} {'strokes':>8} {'analysis s':>10} {'strokes s':>10} {'total s':>8} "
          f"{'s/MP':>6} {'strokes/s':>10} {'peak MiB':>9}")
    for mp in (float(s) for s in args.sizes.split(",")):
        image = photo(mp)
        h, w = image.shape[:2]
        result = {}

        def run():
            result["painting"] = painting = paint(image, params)
            seconds = painting.statistics["seconds"]
            return {"analysis": sum(v for k, v in seconds.items() if k != "strokes"), "strokes": seconds["strokes"]}

        figures = median_runs(run, args.runs)
        peak = peak_mib(lambda: paint(image, params))
        strokes = result["painting"].statistics["strokes"]
        print(f"{h * w / 1e6:5.2f} {w:>5}x{h:<5} {strokes:>8} {figures['analysis']:>10.2f} {figures['strokes']:>10.2f} "
              f"{figures['total']:>8.2f} {figures['total'] / (h * w / 1e6):>6.2f} "
              f"{strokes / figures['total']:>10.0f} {peak:>9.0f}", flush=True)


if __name__ == "__main__":
    main()
