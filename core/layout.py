"""Content-dependent stroke layout (ALGORITHM §3): where each layer puts its strokes."""

from __future__ import annotations

from typing import Optional, Tuple

import numpy as np


def grid_order(grids: np.ndarray) -> np.ndarray:
    """Indices of (N, 4) grids (x0, y0, x1, y1) by area, largest first (ties keep partition order)."""
    areas = (grids[:, 2] - grids[:, 0]).astype(np.int64) * (grids[:, 3] - grids[:, 1])
    return np.argsort(-areas, kind="stable")


def choose_anchor(grid, coverage: np.ndarray, colour: np.ndarray, reference: np.ndarray,
                  coverage_threshold: float, difference_threshold: float) -> Optional[Tuple[int, int]]:
    """The anchor (x, y) of this layer's stroke in ``grid`` (x0, y0, x1, y1), or None.

    1. p_min, the least-covered pixel, if its coverage < T_c;
    2. else p_max, the pixel whose canvas colour differs most from the
       reference, if that Euclidean RGB distance > T_d;
    3. else no stroke. Ties go to the first pixel in raster order.
    """
    x0, y0, x1, y1 = grid
    cov = coverage[y0:y1, x0:x1]
    k = int(np.argmin(cov))
    gw = x1 - x0
    if cov.flat[k] < coverage_threshold:
        return x0 + k % gw, y0 + k // gw
    diff = colour[y0:y1, x0:x1] - reference[y0:y1, x0:x1]
    dist2 = np.einsum("ijk,ijk->ij", diff, diff)
    k = int(np.argmax(dist2))
    if dist2.flat[k] > difference_threshold * difference_threshold:
        return x0 + k % gw, y0 + k // gw
    return None
