"""Memory of a long `core sequence` run, and a SIGKILL at a random frame followed by a rerun.

One uninterrupted run paints the clip; while it runs, its peak resident
memory (VmHWM of /proc/PID/status) is read as each frame is committed (when
report.json lists one more frame). It prints the peak after frame --early
(default 20) and at the end, and their ratio: a run whose memory does not
grow with the frames has a ratio near 1.

Then a second run into another folder is killed with SIGKILL once a random
number of frames (between 2 and the clip's length minus 1, from --seed) is
committed, and run again to its end with the same command. Every frame's
files, the lives file and the state must be the same bytes as the
uninterrupted run's (report.json differs only in its seconds).

Usage: python bench/sequence_memory.py CLIP [--frames A-B] [--early 20] [--seed 1] [--work DIR]
CLIP is what `core sequence` takes (a folder, a # pattern).
"""

from __future__ import annotations

import argparse
import json
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def command(clip: str, out: Path, frames) -> list:
    """The `core sequence` command painting ``clip`` into ``out`` at seed 5 (``frames`` "A-B" or None)."""
    return ([sys.executable, "-m", "core", "sequence", clip, "-o", str(out), "--seed", "5", "-q"]
            + (["--frames", frames] if frames else []))


def frames_done(out: Path) -> int:
    """How many frames report.json lists as committed (0 before the first)."""
    try:
        return len(json.loads((out / "report.json").read_text())["per_frame"])
    except (OSError, ValueError, KeyError):
        return 0


def peak_kib(pid: int) -> int:
    """The process's peak resident memory so far (VmHWM, KiB), 0 when it has ended."""
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1])
    except OSError:
        pass
    return 0


def watched_run(clip: str, out: Path, frames) -> dict:
    """Run the sequence to its end; {frames done: peak KiB then} sampled every 50 ms, and the seconds taken."""
    start = time.perf_counter()
    process = subprocess.Popen(command(clip, out, frames), cwd=ROOT)
    peaks = {}
    while process.poll() is None:
        peak = peak_kib(process.pid)
        if peak:
            peaks[frames_done(out)] = peak
        time.sleep(0.05)
    if process.returncode != 0:
        sys.exit(f"core sequence exited with status {process.returncode}")
    return {"peaks": peaks, "seconds": time.perf_counter() - start}


def killed_run(clip: str, out: Path, frames, kill_after: int) -> None:
    """Run the sequence, SIGKILL it once ``kill_after`` frames are committed, then run it again to its end."""
    process = subprocess.Popen(command(clip, out, frames), cwd=ROOT)
    while process.poll() is None and frames_done(out) < kill_after:
        time.sleep(0.01)
    process.send_signal(signal.SIGKILL)
    process.wait()
    print(f"killed after {frames_done(out)} frames committed", flush=True)
    subprocess.run(command(clip, out, frames), cwd=ROOT, check=True)


def files_of(folder: Path) -> dict:
    """{name: bytes} of a sequence folder's files but report.json."""
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file() and p.name != "report.json"}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("clip")
    parser.add_argument("--frames", default=None, metavar="A-B")
    parser.add_argument("--early", type=int, default=20, help="the frame whose peak the end's is compared with")
    parser.add_argument("--seed", type=int, default=1, help="seed of the random frame the second run is killed at")
    parser.add_argument("--work", default=None, help="keep the painted folders here (default: a temporary folder)")
    args = parser.parse_args()
    work = Path(args.work) if args.work else Path(tempfile.mkdtemp(prefix="sequence_memory-"))
    whole, killed = work / "whole", work / "killed"
    for folder in (whole, killed):
        shutil.rmtree(folder, ignore_errors=True)
    run = watched_run(args.clip, whole, args.frames)
    count = frames_done(whole)
    early = max(k for k in run["peaks"] if k <= args.early)
    end = max(run["peaks"].values())
    print(f"frames {count}, {run['seconds'] / count:.2f} s per frame")
    print(f"peak memory after frame {early}: {run['peaks'][early] / 1024:.0f} MiB; at the end: {end / 1024:.0f} MiB; "
          f"end / frame {early}: {end / run['peaks'][early]:.3f}")
    kill_after = random.Random(args.seed).randint(2, count - 1)
    killed_run(args.clip, killed, args.frames, kill_after)
    same = files_of(killed) == files_of(whole)
    print(f"SIGKILL after frame {kill_after}, then the same command: {'the same bytes' if same else 'OTHER BYTES'} "
          f"as the uninterrupted run ({len(files_of(whole))} files)")
    if not args.work:
        shutil.rmtree(work, ignore_errors=True)
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
