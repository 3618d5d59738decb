"""Benchmark of painting a scene's objects side by side (``core.paint_objects``) against one after another.

Four objects, each a mesh of ``tests/seam_meshes.py`` (two UV spheres, two
cubes of six islands) with a bundled photograph as its texture, painted at
``--size`` texels (1024: several seconds each). In one run, alternating
``--runs`` times: the four painted one after another by ``core.paint_object``
in this process, then all four by ``core.paint_objects`` on the machine's
cores (``--processes``, default one per core), and with ``--farm-workers N``
all four on a local Dask cluster of N worker processes (``core.paint_objects``
with a farm: one task per object; the seconds include starting the cluster,
as each such call does), each time into new folders.
Printed: the median and every wall-clock second of each way, the ratios to
one after another, the median processor seconds of each (user and system,
this process and its workers: what other work on the machine blurs least),
the strokes of each object, the peak resident memory (this process one after
another; this process and the processes below it together side by side and
on the farm, sampled every 50 ms), whether every way wrote the same bytes
(every file report.json lists), and the load average before and after (other
work on the machine slows them all).

Usage: python bench/scene_objects.py [--size 1024] [--runs 3] [--processes N] [--farm-workers N]
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import sys
import tempfile
import threading
import time
from pathlib import Path

from common import ROOT

sys.path.insert(0, str(ROOT / "tests"))

from seam_meshes import cube, uv_sphere  # noqa: E402

import core  # noqa: E402
from core.params import Params  # noqa: E402

SAMPLES = ROOT / "sample_scenes"


def scene_jobs(size: int, root: Path) -> list:
    """The four objects' jobs (module docstring), painted into folders under ``root``."""
    objects = [("sphere", uv_sphere(), "coffee.png"), ("cube", cube(), "chelsea.png"),
               ("small_sphere", uv_sphere(32, 16, 0.35), "astronaut.png"), ("big_cube", cube(0.4, 6), "coffee.png")]
    return [dict(texture_path=str(SAMPLES / picture), mesh=mesh, output_dir=str(root / name), params=Params(seed=k),
                 texture_size=size) for k, (name, mesh, picture) in enumerate(objects)]


def resident_mib(pids) -> float:
    """The resident memory of the processes ``pids`` together, in MiB (Linux /proc; gone ones count 0)."""
    total = 0
    for pid in pids:
        try:
            with open(f"/proc/{pid}/status", encoding="ascii") as status:
                total += next(int(line.split()[1]) for line in status if line.startswith("VmRSS:"))
        except (OSError, StopIteration):
            pass
    return total / 1024


def children(pid: int) -> list:
    """The processes below ``pid``, its children and theirs (Linux /proc)."""
    found = []
    for task in Path(f"/proc/{pid}/task").glob("*"):
        try:
            found += [int(p) for p in (task / "children").read_text().split()]
        except OSError:
            pass
    return found + [below for child in found for below in children(child)]


class PeakMemory:
    """The peak resident memory of this process and its children together while the block runs, sampled."""

    def __init__(self, seconds: float = 0.05):
        self.seconds, self.peak, self._done = seconds, 0.0, threading.Event()

    def _sample(self) -> None:
        while not self._done.is_set():
            me = os.getpid()
            self.peak = max(self.peak, resident_mib([me] + children(me)))
            self._done.wait(self.seconds)

    def __enter__(self) -> "PeakMemory":
        self._thread = threading.Thread(target=self._sample, daemon=True)
        self._thread.start()
        return self

    def __exit__(self, *exc) -> None:
        self._done.set()
        self._thread.join()


def processor_seconds() -> float:
    """User and system seconds of this process and of its children waited for, so far."""
    return sum(getattr(resource.getrusage(who), field) for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)
               for field in ("ru_utime", "ru_stime"))


def one_after_another(jobs: list) -> list:
    """Each job painted by ``core.paint_object``, in order; the reports."""
    return [core.paint_object(**job) for job in jobs]


def side_by_side(jobs: list, processes) -> list:
    """The jobs painted by ``core.paint_objects``; the reports (every job must be painted)."""
    outcomes = core.paint_objects(jobs, processes=processes)
    for outcome in outcomes:
        if not outcome.ok:
            raise SystemExit(str(outcome.error))
        assert outcome.report["batch"] == "painted"
    return [outcome.report for outcome in outcomes]


def on_farm(jobs: list, workers: int) -> list:
    """The jobs painted by ``core.paint_objects`` on a local Dask cluster of ``workers`` processes, started for
    the call; the reports (every job must be painted)."""
    from core.farm.cluster import Farm

    outcomes = core.paint_objects(jobs, farm=Farm(workers=workers))
    for outcome in outcomes:
        if not outcome.ok:
            raise SystemExit(str(outcome.error))
        assert outcome.report["batch"] == "painted"
    return [outcome.report for outcome in outcomes]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=1024)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--processes", type=int, default=None)
    parser.add_argument("--farm-workers", type=int, default=None, metavar="N",
                        help="also paint the four on a local Dask cluster of N worker processes")
    args = parser.parse_args()
    print(f"load average before: {' '.join(f'{v:.2f}' for v in os.getloadavg())}; cores: "
          f"{len(os.sched_getaffinity(0))}")
    seconds = {"one after another": [], "side by side": []}
    if args.farm_workers:
        seconds[f"farm of {args.farm_workers}"] = []
    processor = {name: [] for name in seconds}
    peaks = {name: 0.0 for name in seconds}
    same = True
    with tempfile.TemporaryDirectory(prefix="scene-objects-") as work:
        core.paint_object(**dict(scene_jobs(64, Path(work) / "warm")[0]))     # the imports, outside the timing
        for run in range(args.runs):
            done = {}
            for name in seconds:
                jobs = scene_jobs(args.size, Path(work) / f"{run}_{name.replace(' ', '_')}")
                with PeakMemory() as memory:
                    t0, c0 = time.perf_counter(), processor_seconds()
                    if name == "one after another":
                        reports = one_after_another(jobs)
                    elif name == "side by side":
                        reports = side_by_side(jobs, args.processes)
                    else:
                        reports = on_farm(jobs, args.farm_workers)
                    seconds[name].append(time.perf_counter() - t0)
                    processor[name].append(processor_seconds() - c0)
                peaks[name] = max(peaks[name], memory.peak)
                done[name] = reports
                print(f"run {run + 1} {name}: {seconds[name][-1]:.2f} s", flush=True)
            serial = done["one after another"]
            same &= all(a["files"] == b["files"] for name in done for a, b in zip(serial, done[name], strict=True))
    medians = {name: statistics.median(values) for name, values in seconds.items()}
    print(f"\n{args.size} texels, 4 objects, strokes {[report['strokes'] for report in serial]}")
    for name in seconds:
        print(f"{name:>18}: median {medians[name]:.2f} s  ({', '.join(f'{v:.2f}' for v in seconds[name])})  "
              f"processor {statistics.median(processor[name]):.1f} s  peak resident {peaks[name]:.0f} MiB")
    for name in list(seconds)[1:]:
        print(f"ratio {name} / one after another: {medians[name] / medians['one after another']:.2f}")
    print(f"same bytes every way: {same}")
    print(f"load average after: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")


if __name__ == "__main__":
    main()
