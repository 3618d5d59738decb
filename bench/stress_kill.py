"""Stress test of the all-or-nothing commit: SIGKILL `core paint` at random moments while it writes.

A folder first holds a complete painting (seed 1). Then, N times: a run
with a new seed paints into it and is killed with SIGKILL at a random moment
of its writing phase (from the appearance of its staging folder to the end of
its commit); right after the kill the folder must hold exactly one complete
painting, the previous or the new one (``core.files.maps.check_painting``: every
file's size and SHA-256 as report.json lists them and every EXR's header
seed equal to the report's). A kill between the commit point and the end of
the commit leaves a journal, which ``staging.settle`` (what the next run does
first) completes: such folders are checked after that and counted apart.
Then the run is repeated to its end and the folder must hold the new
painting with no staging folder, journal or lock left.

Usage: python bench/stress_kill.py [--kills 50] [--megapixels 0.25] [--seed 7]
Prints one line per kill and a summary "complete after kill: K/N".
"""

from __future__ import annotations

import argparse
import os
import random
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from core.errors import InputError  # noqa: E402
from core.files import writing  # noqa: E402
from core.files.maps import check_painting  # noqa: E402
from core.files.staging import JOURNAL_NAME, STAGING_PREFIX, settle  # noqa: E402


def paint_command(image: Path, out: Path, seed: int) -> list:
    """The command line of one run."""
    return [sys.executable, "-m", "core", "paint", str(image), "-o", str(out), "--seed", str(seed), "-q"]


def _env() -> dict:
    return dict(os.environ, PYTHONPATH=str(ROOT), PYTHONDONTWRITEBYTECODE="1")


def leftovers(out: Path) -> list:
    """Names of staging folders, journals and lock files in ``out``."""
    return sorted(p.name for p in out.iterdir()
                  if p.name.startswith((STAGING_PREFIX, JOURNAL_NAME, ".paint-relief")))


def wait_for_staging(proc: subprocess.Popen, out: Path, timeout: float = 120.0) -> float:
    """Poll until ``proc`` has a staging folder in ``out`` (its writing began); return that moment (monotonic)."""
    end = time.monotonic() + timeout
    while time.monotonic() < end and proc.poll() is None:
        if any(name.startswith(STAGING_PREFIX) for name in os.listdir(out)):
            return time.monotonic()
        time.sleep(0.0005)
    return time.monotonic()


def writing_seconds(image: Path, out: Path, seed: int) -> float:
    """Seconds from the appearance of the staging folder to the end of a whole run (the writing phase)."""
    proc = subprocess.Popen(paint_command(image, out, seed), env=_env(), cwd=ROOT)
    start = wait_for_staging(proc, out)
    proc.wait()
    if proc.returncode != 0:
        raise SystemExit(f"calibration run failed with exit status {proc.returncode}")
    return time.monotonic() - start


def kill_once(image: Path, out: Path, seed: int, window: float, rng: random.Random) -> dict:
    """One killed run and its checks; returns what was found."""
    before = check_painting(out)
    proc = subprocess.Popen(paint_command(image, out, seed), env=_env(), cwd=ROOT,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    start = wait_for_staging(proc, out)
    delay = rng.uniform(0.0, window)
    time.sleep(max(0.0, start + delay - time.monotonic()))
    alive = proc.poll() is None
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    journal = (out / JOURNAL_NAME).exists()
    if journal:
        settle(out)
    try:
        found = check_painting(out)
        complete = found in (before, str(seed))
    except InputError as exc:
        found, complete = f"broken: {exc}", False
    rerun = subprocess.run(paint_command(image, out, seed), env=_env(), cwd=ROOT, capture_output=True, text=True)
    after = check_painting(out) if rerun.returncode == 0 else f"rerun failed: {rerun.stderr.strip()}"
    return {"delay_ms": round(delay * 1000, 1), "killed_alive": alive, "journal": journal, "found": found,
            "complete": complete, "rerun_ok": after == str(seed) and not leftovers(out)}


def stress(kills: int, megapixels: float, seed: int, work: Path, verbose: bool = True) -> dict:
    """Run ``kills`` killed runs into one folder; returns counts."""
    sys.path.insert(0, str(ROOT / "bench"))
    from common import photo

    image = work / "photo.png"
    writing.write_png(image, photo(megapixels))
    out = work / "out"
    first = subprocess.run(paint_command(image, out, 1), env=_env(), cwd=ROOT, capture_output=True, text=True)
    if first.returncode != 0:
        raise SystemExit(f"first run failed: {first.stderr.strip()}")
    window = writing_seconds(image, out, 1)
    rng = random.Random(seed)
    counts = {"kills": 0, "complete": 0, "journal": 0, "rerun_ok": 0, "finished_before_kill": 0}
    if verbose:
        print(f"writing phase: {window * 1000:.0f} ms; killing at a uniform moment within it", flush=True)
    for i in range(kills):
        result = kill_once(image, out, 1000 + i, window, rng)
        counts["kills"] += 1
        counts["complete"] += result["complete"]
        counts["journal"] += result["journal"]
        counts["rerun_ok"] += result["rerun_ok"]
        counts["finished_before_kill"] += not result["killed_alive"]
        if verbose:
            print(f"kill {i + 1:2d}: after {result['delay_ms']:7.1f} ms, journal {str(result['journal']):5}, "
                  f"folder seed {result['found']}, complete {result['complete']}, rerun {result['rerun_ok']}",
                  flush=True)
    return counts


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--kills", type=int, default=50)
    parser.add_argument("--megapixels", type=float, default=0.25)
    parser.add_argument("--seed", type=int, default=7)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        counts = stress(args.kills, args.megapixels, args.seed, Path(tmp))
    print(f"complete after kill: {counts['complete']}/{counts['kills']} "
          f"(commit completed from a journal: {counts['journal']}; run had already ended: "
          f"{counts['finished_before_kill']}); complete after rerun: {counts['rerun_ok']}/{counts['kills']}")


if __name__ == "__main__":
    main()
