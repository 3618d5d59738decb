"""The detail pass (ALGORITHM §5): highlights dotted last.

After the layers, features smaller than their grid's stroke size that the
painting still misses (lights, stars, glints, thin wires) get dabs or short
strokes of the smallest brush, as a painter dots highlights last. The
partition alone does not find them: a star in a smooth sky lies in a grid of
the largest size, whose strokes take their colour from the reference
smoothed at their own scale.
"""

from __future__ import annotations

from typing import Dict

import numpy as np
from scipy import ndimage

from .smoothing import SmoothedImage


def size_map(grids: np.ndarray, grid_sizes: np.ndarray, shape: tuple) -> np.ndarray:
    """(H, W) int32: the stroke size (px) of the grid each pixel lies in.

    grids: (N, 4) int (x0, y0, x1, y1) half-open, tiling the (H, W) canvas; grid_sizes: (N,) px.
    """
    out = np.zeros(shape, np.int32)
    for (x0, y0, x1, y1), s in zip(grids.tolist(), grid_sizes.tolist(), strict=True):
        out[y0:y1, x0:x1] = s
    return out


def detail_anchors(reference: np.ndarray, canvas_colour: np.ndarray, sizes_px: np.ndarray,
                   smoothed: Dict[int, SmoothedImage], smallest: int, threshold: float) -> np.ndarray:
    """(N, 2) int (x, y) anchors of the detail pass, most visible miss first.

    reference, canvas_colour: (H, W, 3) sRGB [0, 1]. sizes_px: (H, W) stroke
    size of each pixel's grid (``size_map``); smoothed: {size: the reference
    at that size's scale}. A pixel is a candidate where its grid's size is
    above ``smallest``, it stands out from the reference at its grid's scale
    by more than ``threshold`` (a feature smaller than the grid's strokes)
    and the canvas still differs from the reference there by more than
    ``threshold`` (Euclidean RGB), and its brightness is a local extreme
    (3 x 3: the top of a light, the bottom of a dark dot, the ridge of a
    wire). Of the candidates, the one with the
    largest miss in each ``smallest`` x ``smallest`` neighbourhood is kept
    (ties to the first in raster order).
    """
    miss = np.sqrt(np.einsum("ijk,ijk->ij", reference - canvas_colour, reference - canvas_colour))
    lum = reference.mean(axis=2)
    extreme = (lum == ndimage.maximum_filter(lum, size=3)) | (lum == ndimage.minimum_filter(lum, size=3))
    score = np.where((miss > threshold) & extreme, miss, 0.0).astype(np.float32)
    for size, level in smoothed.items():
        inside = sizes_px == size
        rows, cols = np.nonzero(inside & (score > 0))
        if rows.size == 0:
            continue
        local = level.sample(cols.astype(np.float32), rows.astype(np.float32))
        feature = np.sqrt(np.sum((reference[rows, cols] - local) ** 2, axis=1))
        faint = feature <= 3.0 * threshold
        score[rows[faint], cols[faint]] = 0.0
    peak = (score > 0) & (score == ndimage.maximum_filter(score, size=2 * max(1, int(smallest)) + 1, mode="constant"))
    rows, cols = np.nonzero(peak)
    order = np.argsort(-score[rows, cols], kind="stable")
    return np.stack([cols[order], rows[order]], axis=1).astype(np.int64)
