"""The analysis half of the painter: reference, importance, partition, orientation."""

from __future__ import annotations

import math
import time
from typing import Dict, Optional

import numpy as np

from ..colour import luminance
from ..errors import InputError
from ..params import Params, scaled_sizes
from ..progress import CancelFn, ProgressFn, Stage
from ..results import Analysis
from .importance import importance_map, reference_image
from .orientation import orientation_field
from .partition import detail_threshold, nearest_size, partition


def check_image(image: np.ndarray) -> np.ndarray:
    """The image as float32 (H, W, 3) in [0, 1]; InputError for any other shape or non-finite values.

    A float32 image already in [0, 1] comes back as it is, not copied (the
    painter only reads it): at 16 MP a copy would hold 183 MiB more.
    """
    a = np.asarray(image, dtype=np.float32)
    if a.ndim != 3 or a.shape[2] != 3 or a.shape[0] < 1 or a.shape[1] < 1:
        raise InputError(f"The image must be an (H, W, 3) array with H, W >= 1, got shape {a.shape}.")
    if not np.all(np.isfinite(a)):
        raise InputError("The image holds NaN or infinite values.")
    if a.min() < 0.0 or a.max() > 1.0:
        return np.clip(a, 0.0, 1.0)
    return a


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
    importance = timed("importance", 0.35, "Computing the importance map", importance_map,
                       reference, params.energy_percentile, mask, params.mask_strength)
    sizes = scaled_sizes(params, h, w)
    threshold = detail_threshold(importance, params.detail, sizes)
    grids = timed("partition", 0.45, "Partitioning the canvas", partition,
                  importance, sizes, threshold, params.partition_delta, params.partition_gamma)
    grid_sizes = nearest_size(grids, sizes)
    orientation = timed("orientation", 0.65, "Computing the orientation field", orientation_field,
                        luminance(reference), importance, params, scale)
    stage.report(1.0, "Analysis done")
    return Analysis(reference, importance, grids, grid_sizes, orientation, sizes, seconds)
