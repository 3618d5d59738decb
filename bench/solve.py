"""Benchmark of the orientation field's stacked solve, with BLAS free and held to one thread.

The orientation field solves one (k+1) × (k+1) system per local RBF fit
(about 1,700 of them with k = 32 at any image size). np.linalg.solve hands
each to LAPACK; the OpenBLAS of NumPy 1.x (Blender 4.2 to 5.0) runs each of
these tiny solves on all its threads, which spin against whatever else the
machine runs. This prints, for BLAS free and for BLAS held to one thread by
threadpoolctl (as core/analysis/orientation.py does), the best and median
wall seconds and the CPU seconds per wall second, with --busy N processes
spinning beside it (a busy machine). Run it under each NumPy to compare.
Usage: python bench/solve.py [--runs N] [--systems C] [--neighbors K] [--busy N]
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time

import numpy as np
from threadpoolctl import threadpool_limits

from common import ROOT  # noqa: F401  (puts the repository on sys.path)
from core.analysis.orientation import _pairwise


def systems(count: int, k: int) -> tuple:
    """Random RBF systems as the orientation field builds them: lhs (c, k+1, k+1), rhs (c, k+1, 2) float64."""
    rng = np.random.default_rng(0)
    p = rng.random((count, k, 2))
    lhs = np.zeros((count, k + 1, k + 1))
    lhs[:, :k, :k] = 1e-6 * np.eye(k) - _pairwise(p, p)
    lhs[:, :k, k] = lhs[:, k, :k] = 1.0
    rhs = np.zeros((count, k + 1, 2))
    rhs[:, :k] = rng.standard_normal((count, k, 2))
    return lhs, rhs


def timed(solve, runs: int) -> tuple:
    """(best wall s, median wall s, median CPU s per wall s) of ``runs`` calls of ``solve``."""
    walls, loads = [], []
    for _ in range(runs):
        wall, cpu = time.perf_counter(), time.process_time()
        solve()
        walls.append(time.perf_counter() - wall)
        loads.append((time.process_time() - cpu) / walls[-1])
    return min(walls), statistics.median(walls), statistics.median(loads)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--systems", type=int, default=1700)
    parser.add_argument("--neighbors", type=int, default=32)
    parser.add_argument("--busy", type=int, default=0, help="processes spinning beside the solve")
    args = parser.parse_args()
    lhs, rhs = systems(args.systems, args.neighbors)
    spinners = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(args.busy)]
    try:
        free = timed(lambda: np.linalg.solve(lhs, rhs), args.runs)

        def pinned():
            with threadpool_limits(limits=1, user_api="blas"):
                np.linalg.solve(lhs, rhs)

        one = timed(pinned, args.runs)
    finally:
        for child in spinners:
            child.kill()
            child.wait()
    print(f"NumPy {np.__version__}, {args.systems} systems of {args.neighbors + 1} unknowns, {args.busy} busy")
    for name, (best, median, load) in (("BLAS free", free), ("BLAS 1 thread", one)):
        print(f"{name:>14}: best {best:.3f} s, median {median:.3f} s, {load:.2f} CPU s per s")


if __name__ == "__main__":
    main()
