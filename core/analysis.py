"""The analysis half of the painter: reference, importance, partition, orientation."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Dict, Optional, Tuple

import numpy as np

from .colour import luminance
from .importance import importance_map, reference_image
from .orientation import orientation_field
from .params import Params, scaled_sizes
from .partition import detail_threshold, nearest_size, partition
from .progress import CancelFn, ProgressFn, Stage


@dataclass
class Analysis:
    """Everything the stroke layout needs to know about an (H, W) image.

    reference:   float32 (H, W, 3) sRGB [0, 1], bilateral-filtered input.
    intensity:   float32 (H, W) [0, 1], luminance of the reference.
    importance:  float32 (H, W) [0, 1], normalised Sobel energy Ẽ (Eq. 1).
    grids:       int32 (N, 4) rows (x0, y0, x1, y1), half-open, tiling the canvas.
    grid_sizes:  int32 (N,) standard stroke size (px) of each grid.
    orientation: float32 (H, W) [0, pi), stroke direction (Eq. 3).
    sizes:       standard stroke sizes (px) scaled to this image, descending.
    seconds:     wall-clock seconds of each stage.
    """

    reference: np.ndarray
    intensity: np.ndarray
    importance: np.ndarray
    grids: np.ndarray
    grid_sizes: np.ndarray
    orientation: np.ndarray
    sizes: Tuple[int, ...]
    seconds: Dict[str, float] = field(default_factory=dict)

    def summary(self) -> dict:
        """JSON-ready figures: grid count, histogram of grid sizes, seconds per stage."""
        counts = {int(s): int(np.count_nonzero(self.grid_sizes == s)) for s in self.sizes}
        areas = (self.grids[:, 2] - self.grids[:, 0]) * (self.grids[:, 3] - self.grids[:, 1])
        h, w = self.importance.shape
        return {
            "width": int(w),
            "height": int(h),
            "grids": int(len(self.grids)),
            "stroke_sizes_px": list(self.sizes),
            "grids_per_stroke_size": counts,
            "grid_area_px": {
                "min": int(areas.min()), "median": float(np.median(areas)), "max": int(areas.max()),
            },
            "seconds": {k: round(v, 4) for k, v in self.seconds.items()},
        }


def analyze(image: np.ndarray, params: Params, mask: Optional[np.ndarray] = None,
            progress: ProgressFn = None, cancel: CancelFn = None) -> Analysis:
    """Run ALGORITHM §1, §2 and §4 on an (H, W, 3) sRGB [0, 1] float32 image.

    mask: optional (h, w) importance mask in [0, 1] (any size, resized).
    progress(fraction, message) and cancel() are polled between stages.
    """
    params.validate()
    stage = Stage(progress, cancel)
    h, w = image.shape[:2]
    seconds: Dict[str, float] = {}
    scale = math.sqrt(h * w / 1e6)

    def timed(name, fraction, message, fn, *args):
        stage.report(fraction, message)
        t0 = time.perf_counter()
        result = fn(*args)
        seconds[name] = time.perf_counter() - t0
        return result

    reference = timed("reference", 0.0, "Filtering the reference image", reference_image,
                      image, params.bilateral_sigma_spatial, params.bilateral_sigma_range)
    intensity = luminance(reference)
    importance = timed("importance", 0.35, "Computing the importance map", importance_map,
                       reference, params.energy_percentile, mask, params.mask_strength)
    sizes = scaled_sizes(params, h, w)
    threshold = detail_threshold(importance, params.detail)
    grids = timed("partition", 0.45, "Partitioning the canvas", partition,
                  importance, sizes, threshold, params.partition_delta, params.partition_gamma)
    grid_sizes = nearest_size(grids, sizes)
    orientation = timed("orientation", 0.65, "Computing the orientation field", orientation_field,
                        intensity, importance, params, scale)
    stage.report(1.0, "Analysis done")
    return Analysis(reference, intensity, importance, grids, grid_sizes, orientation, sizes, seconds)
