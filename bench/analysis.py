"""Benchmark of the analysis (reference, importance, partition, orientation).

Prints, for photographs of 0.25, 1 and 4 megapixels, the median seconds of
each stage over several runs, the grid count and the peak memory.
Usage: python bench/analysis.py [--runs N] [--sizes 0.25,1,4]
"""

from __future__ import annotations

import argparse

from common import median_runs, peak_mib, photo
from core import Params, analyze

STAGES = ("reference", "importance", "partition", "orientation")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--sizes", default="0.25,1,4", help="megapixels, comma-separated")
    args = parser.parse_args()
    params = Params()
    print(f"{'MP':>5} {'size':>11} {'grids':>6} " + " ".join(f"{s:>11}" for s in STAGES)
          + f" {'total s':>8} {'s/MP':>6} {'peak MiB':>9}")
    for mp in (float(s) for s in args.sizes.split(",")):
        image = photo(mp)
        h, w = image.shape[:2]
        result = {}

        def run():
            result["analysis"] = analyze(image, params)
            return result["analysis"].seconds

        medians = median_runs(run, args.runs)
        peak = peak_mib(lambda: analyze(image, params))
        grids = len(result["analysis"].grids)
        print(f"{h * w / 1e6:5.2f} {w:>5}x{h:<5} {grids:>6} "
              + " ".join(f"{medians[s]:>11.3f}" for s in STAGES)
              + f" {medians['total']:>8.3f} {medians['total'] / (h * w / 1e6):>6.2f} {peak:>9.0f}")


if __name__ == "__main__":
    main()
