"""Benchmark of the 2-D lighting models (core/lighting/models.py).

Prints, for a photograph of about 1 megapixel, the median seconds of each
model (paper, directional, bump) and of the normal map over several runs,
seconds per megapixel, and the peak memory of one run. The colour is the
bundled photograph; height and orientation are synthetic fields of the same
size (the lighting cost does not depend on their content), so the benchmark
does not wait for a painting.
Usage: python bench/lighting.py [--runs N] [--megapixels X]
"""

from __future__ import annotations

import argparse

import numpy as np

from common import median_runs, peak_mib, photo
from core import lighting


def synthetic_maps(shape: tuple, seed: int = 0) -> tuple:
    """(height, orientation) float32 (H, W): stroke-like height in [0, 1] and angles in [0, pi)."""
    rng = np.random.default_rng(seed)
    h, w = shape
    y, x = np.mgrid[0:h, 0:w].astype(np.float32)
    height = 0.5 + 0.2 * np.sin(x / 7.0) * np.cos(y / 11.0) + 0.1 * rng.random((h, w), dtype=np.float32)
    orientation = np.mod(np.arctan2(y - h / 2, x - w / 2) + np.pi / 2, np.pi).astype(np.float32)
    return np.clip(height, 0, 1).astype(np.float32), orientation


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--megapixels", type=float, default=1.0)
    args = parser.parse_args()
    colour = photo(args.megapixels)
    height, orientation = synthetic_maps(colour.shape[:2])
    rows, cols = colour.shape[:2]
    mp = rows * cols / 1e6
    jobs = {
        "paper": lambda: lighting.light("paper", colour, height, orientation),
        "directional": lambda: lighting.light("directional", colour, height),
        "bump": lambda: lighting.light("bump", colour, height),
        "normal_map": lambda: lighting.encode_normals(lighting.normal_map(height)),
    }
    print(f"image {cols}x{rows} ({mp:.2f} MP), median of {args.runs} runs")
    print(f"{'model':>12} {'seconds':>8} {'s/MP':>6} {'peak MiB':>9}")
    for name, job in jobs.items():
        medians = median_runs(lambda: (job(), {})[1], args.runs)
        peak = peak_mib(job)
        print(f"{name:>12} {medians['total']:>8.3f} {medians['total'] / mp:>6.3f} {peak:>9.0f}", flush=True)


if __name__ == "__main__":
    main()
