"""Shared helpers of the benchmarks: test images of a given size, medians, peak memory."""

from __future__ import annotations

import math
import statistics
import sys
import time
import tracemalloc
from pathlib import Path
from typing import Callable, Dict, List

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
        figures = dict(fn())
        figures["total"] = time.perf_counter() - t0
        for k, v in figures.items():
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
