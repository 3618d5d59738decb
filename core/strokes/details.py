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


BLOCK_PIXELS = 1 << 20
"""Candidates are scored this many pixels at a time, so the pass holds no full-size colour temporaries."""


def detail_scores(reference: np.ndarray, canvas_colour: np.ndarray, sizes_px: np.ndarray,
                  smoothed: Dict[int, SmoothedImage], threshold: float) -> np.ndarray:
    """(H, W) float32: how far the canvas misses each candidate pixel of the detail pass (0 elsewhere).

    reference, canvas_colour: (H, W, 3) sRGB [0, 1]. sizes_px: (H, W) stroke
    size of each pixel's grid (``size_map``); smoothed: {size: the reference
    at that size's scale}. A pixel is a candidate where its brightness is a
    local extreme (3 x 3: the top of a light, the bottom of a dark dot, the
    ridge of a wire), it stands out from the reference at its grid's scale by
    more than 3 x ``threshold`` (a feature smaller than the grid's strokes)
    and the canvas still differs from the reference there by more than
    ``threshold`` (Euclidean RGB). Computed in blocks of rows.
    """
    h, w = sizes_px.shape
    score = np.zeros((h, w), np.float32)
    step = max(1, BLOCK_PIXELS // max(w, 1))
    for top in range(0, h, step):
        bottom = min(h, top + step)
        lo, hi = max(0, top - 1), min(h, bottom + 1)          # one row of halo for the 3 x 3 extreme test
        lum = reference[lo:hi].mean(axis=2)
        extreme = (lum == ndimage.maximum_filter(lum, size=3)) | (lum == ndimage.minimum_filter(lum, size=3))
        extreme = extreme[top - lo:top - lo + bottom - top]
        diff = reference[top:bottom] - canvas_colour[top:bottom]
        miss = np.sqrt(np.einsum("ijk,ijk->ij", diff, diff))
        block = np.where((miss > threshold) & extreme, miss, 0.0).astype(np.float32)
        rows, cols = np.nonzero(block > 0)
        if rows.size:
            grid_size = sizes_px[top + rows, cols]
            for size, level in smoothed.items():
                pick = grid_size == size
                if not pick.any():
                    continue
                r, c = rows[pick], cols[pick]
                local = level.sample(c.astype(np.float32), (top + r).astype(np.float32))
                feature = np.sqrt(np.sum((reference[top + r, c] - local) ** 2, axis=1))
                faint = feature <= 3.0 * threshold
                block[r[faint], c[faint]] = 0.0
        score[top:bottom] = block
    return score


def detail_anchors(reference: np.ndarray, canvas_colour: np.ndarray, sizes_px: np.ndarray,
                   smoothed: Dict[int, SmoothedImage], smallest: int, threshold: float) -> np.ndarray:
    """(N, 2) int (x, y) anchors of the detail pass, most visible miss first.

    Of the candidates of ``detail_scores`` (same arguments), the one with the
    largest miss in each (2 smallest + 1)-pixel square neighbourhood is kept,
    ``smallest`` being the smallest stroke size (px); equal misses keep raster order.
    """
    score = detail_scores(reference, canvas_colour, sizes_px, smoothed, threshold)
    peak = (score > 0) & (score == ndimage.maximum_filter(score, size=2 * max(1, int(smallest)) + 1, mode="constant"))
    rows, cols = np.nonzero(peak)
    order = np.argsort(-score[rows, cols], kind="stable")
    return np.stack([cols[order], rows[order]], axis=1).astype(np.int64)
