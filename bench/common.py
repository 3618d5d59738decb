"""Shared helpers of the benchmarks: test images of a given size, medians, peak memory, file digests."""

from __future__ import annotations

import hashlib
import math
import os
import statistics
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path
from typing import Callable, Dict, Iterable, List, Sequence

import numpy as np
from scipy import ndimage

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from core.files import reading  # noqa: E402

SAMPLE = ROOT / "sample_scenes" / "coffee.png"


def photo(megapixels: float, source: Path = SAMPLE) -> np.ndarray:
    """A bundled photograph resampled (bilinear) to about ``megapixels``, float32 (H, W, 3) sRGB."""
    image = reading.read_image(source)
    h, w = image.shape[:2]
    scale = math.sqrt(megapixels * 1e6 / (h * w))
    return np.clip(ndimage.zoom(image, (scale, scale, 1), order=1), 0.0, 1.0).astype(np.float32)


def median_runs(fn: Callable[[], Dict[str, float]], runs: int) -> Dict[str, float]:
    """Run ``fn`` (which returns named seconds) ``runs`` times; the median of each name plus 'total'."""
    samples: Dict[str, List[float]] = {}
    for _ in range(runs):
        t0 = time.perf_counter()
        run_seconds = dict(fn())
        run_seconds["total"] = time.perf_counter() - t0
        for k, v in run_seconds.items():
            samples.setdefault(k, []).append(v)
    return {k: statistics.median(v) for k, v in samples.items()}


def peak_mib(fn: Callable[[], object]) -> float:
    """Peak memory allocated through Python and NumPy while ``fn`` runs, in MiB."""
    tracemalloc.start()
    try:
        fn()
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    return peak / 2**20


def run_child(command: Sequence[str], what: str, quiet: bool = False) -> tuple:
    """Run ``command`` from the repository root: (wall seconds, peak resident MiB of the child).

    ``quiet`` drops what it prints on stdout. SystemExit with one sentence naming ``what`` and the last line
    the child wrote on stderr when it fails.
    """
    start = time.perf_counter()
    child = subprocess.Popen([str(c) for c in command], cwd=ROOT, stdout=subprocess.DEVNULL if quiet else None,
                             stderr=subprocess.PIPE, text=True)
    err = child.stderr.read()
    _, status, usage = os.wait4(child.pid, 0)
    seconds = time.perf_counter() - start
    code = os.waitstatus_to_exitcode(status)
    child.returncode = code
    if code != 0:
        last = err.strip().splitlines()[-1] if err.strip() else "no message"
        raise SystemExit(f"{what} failed with exit code {code}: {last}")
    return seconds, usage.ru_maxrss / 1024.0  # KiB on Linux


def file_digests(folder: Path, suffixes: Iterable[str]) -> Dict[str, str]:
    """{file name: SHA-256 hex} of the files in ``folder`` (not its subfolders) whose names end in one of
    ``suffixes`` (".png", ".exr", ...)."""
    endings = tuple(suffixes)
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(Path(folder).iterdir()) if p.is_file() and p.name.endswith(endings)}
