"""The detail pass (ALGORITHM §5): point highlights dotted last.

After the layers, isolated point features that the painting still misses (a
light, a star, a glint) get one dab of the smallest brush each, as a painter
dots highlights last. The partition alone does not find them: a star in a
smooth sky lies in a grid of the largest size, whose strokes take their
colour from the reference smoothed at their own scale. Edges, thin lines and
texture are not this pass's work: the partition gives detailed areas small
strokes that run along them. A point feature is a pixel brighter (or darker)
than all but one pixel of a square ring around it, at the smallest brush's
scale, by a clear margin: along a line or an edge the ring meets pixels as
bright as the feature, and in fine texture it meets the texture's own peaks.
"""

from __future__ import annotations

from typing import Dict

import numpy as np
from scipy import ndimage

from .. import tuning
from ..workers import in_row_blocks
from .smoothing import SmoothedImage


def size_map(grids: np.ndarray, grid_sizes: np.ndarray, shape: tuple) -> np.ndarray:
    """(H, W) int32: the stroke size (px) of the grid each pixel lies in.

    grids: (N, 4) int (x0, y0, x1, y1) half-open, tiling the (H, W) canvas; grid_sizes: (N,) px.
    """
    out = np.zeros(shape, np.int32)
    for (x0, y0, x1, y1), s in zip(grids.tolist(), grid_sizes.tolist(), strict=True):
        out[y0:y1, x0:x1] = s
    return out


POINT_CONTRAST = 2.0
"""A point feature's lightness stands this many difference thresholds (T_d) above (or below) its ring."""
RING_ALLOWANCE = 1
"""A light may have this many ring pixels as bright as itself (a dark point as dark): a neighbouring star of
one pixel. A line or an edge through the ring, or its end, fills at least two of its pixels, texture many."""


def ring_footprint(smallest: int) -> np.ndarray:
    """(2b + 1, 2b + 1) bool: the square ring between half-widths a < d <= b around a pixel (Chebyshev distance).

    smallest: the smallest stroke size in px. b = max(4, smallest) (the
    surroundings one brush width away, and at least 56 pixels of them), a =
    max(1, smallest // 2) (a feature up to about half the brush wide fits inside).
    """
    outer = max(4, int(smallest))
    inner = min(outer - 1, max(1, int(smallest) // 2))
    d = np.maximum(*np.abs(np.mgrid[-outer:outer + 1, -outer:outer + 1]))
    return d > inner


def point_features(lum: np.ndarray, smallest: int, contrast: float, where: np.ndarray = None) -> np.ndarray:
    """(H, W) bool: isolated point features of a lightness image (ALGORITHM §5, detail pass).

    lum: (H, W) float lightness in [0, 1]; smallest: the smallest stroke size
    (px); contrast: lightness margin; where: optional (H, W) bool, the pixels
    to test (default all). True where a pixel is a 3 x 3 maximum lighter by
    more than ``contrast`` than every pixel of its ``ring_footprint`` but the
    RING_ALLOWANCE brightest (a light), or a 3 x 3 minimum darker by more than
    every one but the RING_ALLOWANCE darkest (a dark point). The ring is
    gathered at the tested extremes only, ``tuning.RING_CHUNK_VALUES`` values at a time;
    pixels beyond the border repeat the nearest one.
    """
    top = lum == ndimage.maximum_filter(lum, size=3)
    bottom = lum == ndimage.minimum_filter(lum, size=3)
    test = (top | bottom) if where is None else (top | bottom) & where
    rows, cols = np.nonzero(test)
    found = np.zeros(lum.shape, bool)
    ring_mask = ring_footprint(smallest)
    dy, dx = np.nonzero(ring_mask)
    reach = ring_mask.shape[0] // 2
    step = max(1, tuning.RING_CHUNK_VALUES // len(dy))
    for first in range(0, rows.size, step):
        r, c = rows[first:first + step], cols[first:first + step]
        ring = np.take(lum, np.clip(r[:, None] + (dy - reach), 0, lum.shape[0] - 1) * lum.shape[1]
                       + np.clip(c[:, None] + (dx - reach), 0, lum.shape[1] - 1))
        centre = lum[r, c]
        k = RING_ALLOWANCE
        light = top[r, c] & (centre - np.partition(ring, -1 - k, axis=1)[:, -1 - k] > contrast)
        dark = bottom[r, c] & (np.partition(ring, k, axis=1)[:, k] - centre > contrast)
        found[r, c] = light | dark
    return found


def detail_scores(reference: np.ndarray, canvas_colour: np.ndarray, sizes_px: np.ndarray,
                  smoothed: Dict[int, SmoothedImage], smallest: int, threshold: float) -> np.ndarray:
    """(H, W) float32: how far the canvas misses each candidate pixel of the detail pass (0 elsewhere).

    reference, canvas_colour: (H, W, 3) sRGB [0, 1]. sizes_px: (H, W) stroke
    size of each pixel's grid (``size_map``); smoothed: {size: the reference
    at that size's scale}; smallest: the smallest stroke size (px). A pixel is
    a candidate where it is a point feature of the reference's lightness
    (``point_features``, margin POINT_CONTRAST x ``threshold``), it stands out
    from the reference at its grid's scale by more than 3 x ``threshold``
    (no stroke of its grid would paint it) and the canvas still differs from
    the reference there by more than ``threshold`` (Euclidean RGB). Computed in
    blocks of rows (``in_row_blocks``, so the pass holds no full-size colour
    temporaries), side by side on the worker threads.
    """
    h, w = sizes_px.shape
    score = np.zeros((h, w), np.float32)
    halo = max(4, int(smallest)) + 1                             # rows of context for the ring and 3 x 3 tests

    def score_rows(band: slice) -> None:
        top, bottom = band.start, band.stop
        lo, hi = max(0, top - halo), min(h, bottom + halo)
        lum = reference[lo:hi].mean(axis=2)
        diff = reference[top:bottom] - canvas_colour[top:bottom]
        miss = np.sqrt(np.einsum("ijk,ijk->ij", diff, diff))
        missing = np.zeros(lum.shape, bool)
        missing[top - lo:top - lo + bottom - top] = miss > threshold
        points = point_features(lum, smallest, POINT_CONTRAST * threshold, missing)[top - lo:top - lo + bottom - top]
        block = np.where(points, miss, 0.0).astype(np.float32)
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

    in_row_blocks(score_rows, h, w)
    return score


def detail_anchors(reference: np.ndarray, canvas_colour: np.ndarray, sizes_px: np.ndarray,
                   smoothed: Dict[int, SmoothedImage], smallest: int, threshold: float) -> np.ndarray:
    """(N, 2) int (x, y) anchors of the detail pass, most visible miss first.

    Of the candidates of ``detail_scores`` (same arguments), the one with the
    largest miss in each (2 smallest + 1)-pixel square neighbourhood is kept,
    ``smallest`` being the smallest stroke size (px); equal misses keep raster order.
    """
    score = detail_scores(reference, canvas_colour, sizes_px, smoothed, smallest, threshold)
    peak = (score > 0) & (score == ndimage.maximum_filter(score, size=2 * max(1, int(smallest)) + 1, mode="constant"))
    rows, cols = np.nonzero(peak)
    order = np.argsort(-score[rows, cols], kind="stable")
    return np.stack([cols[order], rows[order]], axis=1).astype(np.int64)
