"""Benchmark of ``core paint --timelapse N`` (core/strokes/snapshots.py, core/files/timelapse.py): what the
time-lapse adds to a painting.

Resamples a bundled photograph to about 1 megapixel, then paints it with ``python -m core paint`` in a child
process (default settings, seed 0) into a fresh temporary folder, without and with ``--timelapse N``, the two
alternating, several runs each; prints side by side the median wall seconds, the peak resident memory of the
child, the image size, the stroke count, the time-lapse's bytes on disk and the ratio of the medians. The target:
at N = 100 the time-lapse adds at most 30 % to the painting.
Usage: python bench/timelapse.py [--runs N] [--frames N] [--megapixels MP] [--sample coffee|astronaut|chelsea|hubble]
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
from pathlib import Path

from common import ROOT, SAMPLE, photo, run_child
from core.files import writing
from core.files.timelapse import TIMELAPSE_DIR


def folder_bytes(folder: Path) -> int:
    """The bytes of the files under ``folder``, a file under several names (hard links) counted once."""
    sizes = {(stat.st_dev, stat.st_ino): stat.st_size for stat in (path.stat() for path in folder.rglob("*")
                                                                   if path.is_file())}
    return sum(sizes.values())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--frames", type=int, default=100)
    parser.add_argument("--megapixels", type=float, default=1.0)
    parser.add_argument("--sample", default="astronaut",
                        help="a photograph of sample_scenes/ by its name (default: %(default)s)")
    args = parser.parse_args()
    sample = next((ROOT / "sample_scenes").glob(f"{args.sample}.*"), SAMPLE)
    with tempfile.TemporaryDirectory() as temp:
        root = Path(temp)
        source = root / "photo.png"
        image = photo(args.megapixels, sample)
        writing.write_png(source, image)
        seconds = {0: [], args.frames: []}
        memory = {0: [], args.frames: []}
        found = {}
        for run in range(args.runs):
            for frames in seconds:
                out = root / f"out_{frames}_{run}"
                command = [sys.executable, "-m", "core", "paint", source, "-o", out, "-q"]
                wall, peak = run_child(command + (["--timelapse", str(frames)] if frames else []),
                                       f"painting with --timelapse {frames}")
                seconds[frames].append(wall)
                memory[frames].append(peak)
                report = json.loads((out / "report.json").read_text())
                found[frames] = (report["strokes"], folder_bytes(out / TIMELAPSE_DIR) if frames else 0,
                                 report.get("timelapse", {}))
    alone, timed = (statistics.median(seconds[k]) for k in seconds)
    strokes = found[0][0]
    print(f"{sample.name} at {image.shape[1]} x {image.shape[0]} px ({image.shape[0] * image.shape[1] / 1e6:.2f} MP), "
          f"{strokes} strokes, median of {args.runs} runs each (wall seconds of `python -m core paint`)")
    print(f"{'':>22} {'seconds':>8} {'peak MiB':>9} {'time-lapse MB':>14}")
    print(f"{'painting alone':>22} {alone:>8.2f} {max(memory[0]):>9.0f} {'':>14}")
    print(f"{f'--timelapse {args.frames}':>22} {timed:>8.2f} {max(memory[args.frames]):>9.0f} "
          f"{found[args.frames][1] / 1e6:>14.1f}")
    summary = found[args.frames][2]
    print(f"ratio {timed / alone:.2f} (the time-lapse adds {100 * (timed / alone - 1):.0f} %); writing the frames "
          f"took {summary.get('seconds', float('nan')):.2f} s of the last run, the snapshots held "
          f"{summary.get('snapshot_bytes', 0) / 1e6:.1f} MB at a step of {summary.get('step')} strokes")


if __name__ == "__main__":
    main()
