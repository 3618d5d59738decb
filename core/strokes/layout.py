"""Content-dependent stroke layout (ALGORITHM §3): where each layer puts its strokes."""

from __future__ import annotations

from typing import Optional, Tuple

import numpy as np


def grid_order(grids: np.ndarray) -> np.ndarray:
    """Indices of (N, 4) grids (x0, y0, x1, y1) by area, largest first (ties keep partition order)."""
    areas = (grids[:, 2] - grids[:, 0]).astype(np.int64) * (grids[:, 3] - grids[:, 1])
    return np.argsort(-areas, kind="stable")


def grid_pixels(source, grid) -> np.ndarray:
    """(gh, gw, 3) float32 colours of ``grid`` (x0, y0, x1, y1) from an (H, W, 3) array or a ``SmoothedImage``."""
    x0, y0, x1, y1 = grid
    if isinstance(source, np.ndarray):
        return source[y0:y1, x0:x1]
    ys, xs = np.mgrid[y0:y1, x0:x1].astype(np.float32)
    return source.sample(xs, ys)


def choose_anchor(grid, coverage: np.ndarray, colour: np.ndarray, reference,
                  coverage_threshold: float, difference_threshold: float,
                  rng: np.random.Generator) -> Optional[Tuple[int, int]]:
    """The anchor (x, y) of this layer's stroke in ``grid`` (x0, y0, x1, y1), or None.

    coverage: (H, W) in [0, 1], how fully each pixel is painted (the painter
    passes the canvas opacity, where paint really lies; ALGORITHM §3's
    coverage map counts faint fringe stamps as half a cover).
    reference: what the grid's strokes aim at, an (H, W, 3) array or a
    ``SmoothedImage`` (the painter passes the reference at the grid's brush
    scale: a stroke cannot paint detail finer than its brush, so a later layer
    adds a stroke only where the canvas misses what a stroke of this size can give).
    1. p_min, the least-covered pixel, if its coverage < T_c;
    2. else p_max, the pixel whose canvas colour differs most from the
       reference, if that Euclidean RGB distance > T_d;
    3. else no stroke. Ties (e.g. a whole grid still at coverage 0) are broken
       by ``rng`` among the tied pixels, so anchors do not line up on grid corners.
    """
    x0, y0, x1, y1 = grid
    gw = x1 - x0
    cov = coverage[y0:y1, x0:x1]
    low = cov.min()
    if low < coverage_threshold:
        return pick_tied(np.flatnonzero(cov == low), x0, y0, gw, rng)
    diff = colour[y0:y1, x0:x1] - grid_pixels(reference, grid)
    dist2 = np.einsum("ijk,ijk->ij", diff, diff)
    high = dist2.max()
    if high > difference_threshold * difference_threshold:
        return pick_tied(np.flatnonzero(dist2 == high), x0, y0, gw, rng)
    return None


def pick_tied(tied: np.ndarray, x0: int, y0: int, grid_width: int, rng: np.random.Generator) -> Tuple[int, int]:
    """(x, y) of one of the ``tied`` flat indices of a grid at (x0, y0), ``grid_width`` px wide, drawn by ``rng``."""
    k = int(tied[0]) if len(tied) == 1 else int(tied[rng.integers(len(tied))])
    return x0 + k % grid_width, y0 + k // grid_width


def hertzmann_anchors(error: np.ndarray, spacing: int, threshold: float) -> np.ndarray:
    """Hertzmann 1998 layout: (N, 2) int (x, y) anchors of one layer, cells in raster order.

    error: (H, W) per-pixel error |reference - canvas| (any scale; +inf where
    the canvas is bare). The canvas is tiled by square cells of ``spacing``
    px (the last row and column may be narrower); a cell whose mean error is
    above ``threshold`` gets a stroke at its pixel of maximum error. Ties
    (a bare cell is all +inf) go to the pixel nearest the cell's centre, so a
    bare canvas gets anchors in the middle of its cells.
    """
    h, w = error.shape
    g = max(1, int(spacing))
    ny, nx = -(-h // g), -(-w // g)
    padded = np.zeros((ny * g, nx * g), np.float64)
    padded[:h, :w] = error
    blocks = padded.reshape(ny, g, nx, g).swapaxes(1, 2).reshape(ny, nx, g * g)
    cell_h = np.minimum(g, h - np.arange(ny) * g)
    cell_w = np.minimum(g, w - np.arange(nx) * g)
    mean = blocks.sum(axis=2) / (cell_h[:, None] * cell_w[None, :])
    cy, cx = np.nonzero(mean > threshold)
    if cy.size == 0:
        return np.zeros((0, 2), np.int64)
    ly, lx = np.divmod(np.arange(g * g), g)
    inside = (ly[None, :] < cell_h[cy][:, None]) & (lx[None, :] < cell_w[cx][:, None])
    values = np.where(inside, blocks[cy, cx], -np.inf)
    top = values.max(axis=1)
    centre_y = (cell_h[cy] - 1) / 2.0
    centre_x = (cell_w[cx] - 1) / 2.0
    dist2 = (ly[None, :] - centre_y[:, None]) ** 2 + (lx[None, :] - centre_x[:, None]) ** 2
    score = np.where(values == top[:, None], -dist2, -np.inf)
    k = np.argmax(score, axis=1)
    return np.stack([cx * g + lx[k], cy * g + ly[k]], axis=1).astype(np.int64)
