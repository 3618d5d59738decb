"""Benchmark of the stroke engine's speed-ups against their plain forms, each as a share of a painting's time.

Each speed-up kept in core/strokes says in a comment what it saves of a
1 MP painting; this measures it. For each photograph of sample_scenes/
(by default the Hubble deep field and the coffee cup, resized bilinearly to
--megapixels), it paints in this process at default settings, with each
speed-up in turn in the engine's form and in its plain form (defined here
and swapped in for the painting), every form once per run, and prints the
seconds the function spent in the painting in both forms and the saving
as a share of the painting's seconds (medians over the runs). Both forms
must paint the same bytes: the last column compares a digest of the maps.
The speed-ups: ``compositing.full_deposits`` (runs padded to powers of
two, partitioned and sorted as blocks) against np.percentile run by run,
and ``compositing.box_sums`` (a sparse product) against np.add.at per
value column. The painter is held to --cores cores (one by default: one
worker thread, no time of other threads counted in, steadier ratios).
Usage: python bench/speedups.py [--runs N] [--megapixels MP] [--photos hubble,coffee] [--cores N]
"""

from __future__ import annotations

import argparse
import hashlib
import os
import statistics
import time

import numpy as np

from common import ROOT, photo
from core.methods import huang11
from core.params import Params
from core.strokes import compositing


def percentile_by_run(deposit: np.ndarray, starts: np.ndarray) -> np.ndarray:
    """The plain form of ``full_deposits``: np.percentile of each run's positive entries, one run at a time."""
    full = np.zeros(len(starts) - 1, np.float32)
    for i, (first, stop) in enumerate(zip(starts[:-1].tolist(), starts[1:].tolist(), strict=True)):
        positive = deposit[first:stop][deposit[first:stop] > 0]
        if positive.size:
            full[i] = np.percentile(positive.astype(np.float64), 90)
    return full


def add_at_by_column(weights: np.ndarray, corners: np.ndarray, values: np.ndarray, pixels: int) -> np.ndarray:
    """The plain form of ``box_sums``: np.add.at of each value column, samples and corners in order, float32."""
    sums = np.zeros((values.shape[1], pixels), np.float32)
    index, weight = corners.ravel(), weights.ravel()
    for column in range(values.shape[1]):
        np.add.at(sums[column], index, weight * np.repeat(values[:, column], corners.shape[1]))
    return np.ascontiguousarray(sums.T)


SPEEDUPS = {"full_deposits": percentile_by_run, "box_sums": add_at_by_column}
"""{name in core.strokes.compositing: its plain form}."""


def timed_painting(pixels: np.ndarray, name: str, form) -> tuple:
    """Paint ``pixels`` with compositing.``name`` replaced by ``form``, timed: (seconds in it, painting seconds,
    digest of the painted maps)."""
    spent = [0.0]

    def timed(*args):
        start = time.perf_counter()
        result = form(*args)
        spent[0] += time.perf_counter() - start
        return result

    engine = getattr(compositing, name)
    setattr(compositing, name, timed)
    try:
        start = time.perf_counter()
        painting = huang11.paint(pixels, Params())
        seconds = time.perf_counter() - start
    finally:
        setattr(compositing, name, engine)
    maps = (painting.colour, painting.height, painting.opacity, painting.coverage)
    return spent[0], seconds, hashlib.sha256(b"".join(m.tobytes() for m in maps)).hexdigest()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--megapixels", type=float, default=1.0)
    parser.add_argument("--photos", default="hubble,coffee", help="photographs of sample_scenes/ by name")
    parser.add_argument("--cores", type=int, default=1, help="cores the painter may use (its worker threads)")
    args = parser.parse_args()
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, sorted(os.sched_getaffinity(0))[:args.cores])
    print(f"{'photo':<8} {'speed-up':<14} {'s with it':>9} {'s plain':>8} {'saving':>7} {'painting s':>10}  same bytes")
    for name in args.photos.split(","):
        found = sorted((ROOT / "sample_scenes").glob(f"{name}.*g"))
        if not found:
            raise SystemExit(f"no photograph named {name} in {ROOT / 'sample_scenes'}")
        pixels = photo(args.megapixels, found[0])
        timings = {(speedup, plain): [] for speedup in SPEEDUPS for plain in (False, True)}
        for _ in range(args.runs):
            for speedup, plain_form in SPEEDUPS.items():
                for plain in (False, True):
                    form = plain_form if plain else getattr(compositing, speedup)
                    timings[speedup, plain].append(timed_painting(pixels, speedup, form))
        for speedup in SPEEDUPS:
            fast, plain = timings[speedup, False], timings[speedup, True]
            with_it = statistics.median(f[0] for f in fast)
            without = statistics.median(f[0] for f in plain)
            painting = statistics.median(f[1] for f in fast)
            same = len({f[2] for f in fast + plain}) == 1
            print(f"{name:<8} {speedup:<14} {with_it:>9.3f} {without:>8.3f} {100 * (without - with_it) / painting:>6.1f}% "
                  f"{painting:>10.2f}  {'yes' if same else 'NO'}", flush=True)


if __name__ == "__main__":
    main()
