"""Benchmark of the whole `core paint` command at default settings.

For a bundled photograph resized to each size, runs `python -m core paint`
as a user would (imports, analysis, strokes, writing) several times and
prints the median and best wall-clock seconds, the seconds per megapixel,
the stroke count, the peak resident memory of the process and the size of
the painted folder, then the median split over the stages of report.json.
With --widths it paints each size once more in this process and splits the
stroke stage by brush width (strokes, seconds, milliseconds per stroke).
Usage: python bench/paint.py [--runs N] [--sizes 1,4,16] [--widths]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from common import ROOT, photo
from core.files import io


def run_command(image: Path, out: Path) -> tuple:
    """One `core paint` run: (wall seconds, peak resident MiB, report dict)."""
    start = time.perf_counter()
    child = subprocess.Popen([sys.executable, "-m", "core", "paint", str(image), "-o", str(out), "-q"], cwd=ROOT)
    _, status, usage = os.wait4(child.pid, 0)
    seconds = time.perf_counter() - start
    child.returncode = os.waitstatus_to_exitcode(status)
    if child.returncode != 0:
        raise SystemExit(f"core paint failed on {image} with exit code {child.returncode}")
    peak = usage.ru_maxrss / 1024.0  # KiB on Linux
    return seconds, peak, json.loads((out / "report.json").read_text())


def strokes_by_width(pixels) -> dict:
    """One in-process paint of (H, W, 3) ``pixels`` at default settings: {brush width px: (strokes, seconds)}."""
    from core.methods import huang11
    from core.params import Params

    spent = {}
    lay = huang11.paint_stroke

    def timed(canvas, sources, orientation, anchor, size, *rest):
        start = time.perf_counter()
        stroke = lay(canvas, sources, orientation, anchor, size, *rest)
        count, seconds = spent.get(size, (0, 0.0))
        spent[size] = (count + 1, seconds + time.perf_counter() - start)
        return stroke

    huang11.paint_stroke = timed
    try:
        huang11.paint(pixels, Params())
    finally:
        huang11.paint_stroke = lay
    return spent


def folder_mib(folder: Path) -> float:
    """Total size of the files in ``folder`` (MiB)."""
    return sum(p.stat().st_size for p in folder.iterdir() if p.is_file()) / 2**20


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--sizes", default="1,4,16", help="megapixels, comma-separated")
    parser.add_argument("--widths", action="store_true", help="split the stroke stage by brush width")
    args = parser.parse_args()
    print(f"{'MP':>5} {'size':>11} {'strokes':>8} {'median s':>9} {'best s':>7} {'s/MP':>6} {'peak MiB':>9} "
          f"{'MiB out':>8} {'MiB/MP':>7}  stages (median s)")
    with tempfile.TemporaryDirectory() as tmp:
        for mp in (float(s) for s in args.sizes.split(",")):
            image = Path(tmp) / f"photo_{mp:g}mp.png"
            pixels = photo(mp)
            io.write_png(image, pixels)
            h, w = pixels.shape[:2]
            del pixels
            walls, peaks, stages = [], [], {}
            for i in range(args.runs):
                out = Path(tmp) / f"out_{mp:g}_{i}"
                seconds, peak, report = run_command(image, out)
                walls.append(seconds)
                peaks.append(peak)
                for name, value in report["seconds"].items():
                    stages.setdefault(name, []).append(value)
            size = folder_mib(out)
            mpx = h * w / 1e6
            split = " ".join(f"{name} {statistics.median(v):.2f}" for name, v in stages.items())
            print(f"{mpx:5.2f} {w:>5}x{h:<5} {report['strokes']:>8} {statistics.median(walls):>9.2f} "
                  f"{min(walls):>7.2f} {statistics.median(walls) / mpx:>6.2f} {max(peaks):>9.0f} {size:>8.1f} "
                  f"{size / mpx:>7.1f}  {split}", flush=True)
            if args.widths:
                spent = strokes_by_width(io.read_image(image))
                print("      by width: " + ", ".join(
                    f"{width} px {n} strokes {s:.2f} s ({1e3 * s / n:.2f} ms each)"
                    for width, (n, s) in sorted(spent.items())), flush=True)


if __name__ == "__main__":
    main()
