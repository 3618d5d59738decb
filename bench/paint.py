"""Benchmark of the whole `core paint` command at default settings, on a detailed and a smooth photograph.

For each photograph of sample_scenes/ (by default the detailed Hubble deep
field, a photograph from outside the painter's own samples, and the smooth
coffee cup; the astronaut is the most detailed of the others), resized
bilinearly to each size (the photographs are 0.24-0.87 MP, so larger sizes
are upsampled), runs
`python -m core paint` as a user would (imports, reading, analysis,
strokes, writing) several times and prints the best and median wall-clock
seconds, the seconds per megapixel, the stroke count, the peak resident
memory of the child process (ru_maxrss), the size of the painted folder,
and the median seconds of each stage of report.json ("seconds"; "other" is
the median wall time outside them: start-up, imports, reading). The
painter spreads its work over the worker threads of ``core.workers``; the
first line (on stderr) says how many.
--markdown prints the same as rows of the README's speed table.
With --widths it paints each size once more in this process and splits the
stroke stage by brush width (strokes, seconds, milliseconds per stroke).
How detailed each is shows in its stroke count (`--runs 1 --sizes 0.25
--photos astronaut,hubble,coffee`).
Usage: python bench/paint.py [--runs N] [--sizes 1,4,16] [--photos hubble,coffee] [--markdown] [--widths]
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
from core.files import reading, writing
from core.workers import worker_count


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
    lay = huang11.paint_round

    def timed(canvas, sources, orientation, anchors, size, *rest, **options):
        start = time.perf_counter()
        strokes = lay(canvas, sources, orientation, anchors, size, *rest, **options)
        count, seconds = spent.get(size, (0, 0.0))
        spent[size] = (count + len(strokes), seconds + time.perf_counter() - start)
        return strokes

    huang11.paint_round = timed
    try:
        huang11.paint(pixels, Params())
    finally:
        huang11.paint_round = lay
    return spent


def folder_mib(folder: Path) -> float:
    """Total size of the files in ``folder`` (MiB)."""
    return sum(p.stat().st_size for p in folder.iterdir() if p.is_file()) / 2**20


def measure(source: Path, mp: float, runs: int, tmp: Path) -> dict:
    """``runs`` `core paint` commands on ``source`` resized to about ``mp`` megapixels.

    Returns {"pixels": (H, W), "image": the resized PNG, "strokes": count,
    "walls": [s], "peak": MiB (the largest run's), "folder": MiB,
    "stages": {stage: median s}}.
    """
    image = tmp / f"{source.stem}_{mp:g}mp.png"
    pixels = photo(mp, source)
    writing.write_png(image, pixels)
    walls, peaks, stages = [], [], {}
    for i in range(runs):
        out = tmp / f"out_{source.stem}_{mp:g}_{i}"
        seconds, peak, report = run_command(image, out)
        walls.append(seconds)
        peaks.append(peak)
        for name, value in report["seconds"].items():
            stages.setdefault(name, []).append(value)
    split = {name: statistics.median(v) for name, v in stages.items()}
    split["other"] = statistics.median(walls) - sum(split.values())
    return {"pixels": pixels.shape[:2], "image": image, "strokes": report["strokes"], "walls": walls,
            "peak": max(peaks), "folder": folder_mib(out), "stages": split}


ANALYSIS = ("reference", "importance", "partition", "orientation")


def markdown_row(name: str, mp: float, m: dict) -> str:
    """One row of the README's speed table; analysis is the sum of its four stages."""
    (h, w), st = m["pixels"], m["stages"]
    analysis = sum(st.get(s, 0.0) for s in ANALYSIS)
    rest = ", ".join(f"{k} {v:.2f}" for k, v in st.items() if k not in ANALYSIS)
    return (f"| {name} {mp:g} MP ({w}×{h}) | {m['strokes']} | {min(m['walls']):.2f} | "
            f"{statistics.median(m['walls']):.2f} | {m['peak']:.0f} MiB | {m['folder']:.1f} MiB | "
            f"analysis {analysis:.2f}, {rest} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--sizes", default="1,4,16", help="megapixels, comma-separated")
    parser.add_argument("--photos", default="hubble,coffee",
                        help="photographs of sample_scenes/ by name, comma-separated (also astronaut, chelsea)")
    parser.add_argument("--markdown", action="store_true", help="print rows of the README's speed table")
    parser.add_argument("--widths", action="store_true", help="split the stroke stage by brush width")
    args = parser.parse_args()
    sources = []
    for name in args.photos.split(","):
        found = sorted((ROOT / "sample_scenes").glob(f"{name}.*g"))
        if not found:
            raise SystemExit(f"no photograph named {name} in {ROOT / 'sample_scenes'}")
        sources.append(found[0])
    print(f"{worker_count()} worker threads (core.workers), {os.cpu_count()} cores", file=sys.stderr)
    if args.markdown:
        print("| photograph | strokes | best s | median s | peak memory | painted folder | stages (median s) |\n"
              "| --- | ---: | ---: | ---: | ---: | ---: | --- |")
    else:
        print(f"{'photo':<10} {'MP':>5} {'size':>11} {'strokes':>7} {'best s':>7} {'median s':>8} {'s/MP':>6} "
              f"{'peak MiB':>8} {'MiB out':>7} {'MiB/MP':>6}  stages (median s)")
    with tempfile.TemporaryDirectory() as tmp:
        for source in sources:
            for mp in (float(s) for s in args.sizes.split(",")):
                m = measure(source, mp, args.runs, Path(tmp))
                (h, w), median = m["pixels"], statistics.median(m["walls"])
                mpx = h * w / 1e6
                if args.markdown:
                    print(markdown_row(source.stem, mp, m), flush=True)
                else:
                    split = " ".join(f"{k} {v:.2f}" for k, v in m["stages"].items())
                    print(f"{source.stem:<10} {mpx:5.2f} {w:>5}x{h:<5} {m['strokes']:>7} {min(m['walls']):>7.2f} "
                          f"{median:>8.2f} {median / mpx:>6.2f} {m['peak']:>8.0f} {m['folder']:>7.1f} "
                          f"{m['folder'] / mpx:>6.1f}  {split}", flush=True)
                if args.widths:
                    spent = strokes_by_width(reading.read_image(m["image"]))
                    print("      by width: " + ", ".join(
                        f"{width} px {n} strokes {s:.2f} s ({1e3 * s / n:.2f} ms each)"
                        for width, (n, s) in sorted(spent.items())), flush=True)


if __name__ == "__main__":
    main()
