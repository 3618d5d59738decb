"""Content-dependent stroke layout (ALGORITHM §3): where each layer puts its strokes."""

from __future__ import annotations

from typing import NamedTuple, Optional

import numpy as np

from .. import tuning
from ..workers import balanced_runs, bounded_runs, run_all, worker_count
from .canvas import Canvas


def size_runs(sizes: np.ndarray) -> list:
    """[(size, first, stop), ...]: the runs of equal stroke size in ``sizes`` (N,) (grids in painting order)."""
    sizes = np.asarray(sizes)
    if sizes.size == 0:
        return []
    cut = np.flatnonzero(sizes[1:] != sizes[:-1]) + 1
    bounds = np.concatenate(([0], cut, [len(sizes)]))
    return [(int(sizes[a]), int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:], strict=True)]


def painting_order(grids: np.ndarray, sizes: np.ndarray) -> np.ndarray:
    """Indices of (N, 4) grids in the paper's order, largest first: by stroke size (N,), then area (ties keep
    partition order), so each size's grids are one run."""
    areas = (grids[:, 2] - grids[:, 0]).astype(np.int64) * (grids[:, 3] - grids[:, 1])
    return np.lexsort((np.arange(len(grids)), -areas, -np.asarray(sizes, np.int64)))


class GridPixels(NamedTuple):
    """The P pixels of N grids, grid after grid; grid i's pixels are [starts[i], starts[i + 1])."""

    x: np.ndarray               # int64 (P,) columns
    y: np.ndarray               # int64 (P,) rows
    starts: np.ndarray          # int64 (N + 1,)


def grid_pixels(grids: np.ndarray) -> GridPixels:
    """The pixels of (N, 4) grids (x0, y0, x1, y1), grid after grid in row-major order:
    (x (P,), y (P,), starts (N + 1,)), grid i's pixels [starts[i], starts[i + 1])."""
    grids = np.asarray(grids, np.int64).reshape(-1, 4)
    widths = grids[:, 2] - grids[:, 0]
    areas = widths * (grids[:, 3] - grids[:, 1])
    starts = np.zeros(len(grids) + 1, np.int64)
    np.cumsum(areas, out=starts[1:])
    owner = np.repeat(np.arange(len(grids)), areas)
    ly, lx = np.divmod(np.arange(starts[-1]) - starts[owner], widths[owner])
    return GridPixels(grids[owner, 0] + lx, grids[owner, 1] + ly, starts)


class ChosenAnchors(NamedTuple):
    """The anchors of N grids of one layer and stroke size."""

    anchors: np.ndarray         # int64 (N, 2) (x, y) px, meaningful where ``chosen``
    chosen: np.ndarray          # bool (N,) the grid gets a stroke
    by_difference: np.ndarray   # bool (N,) chosen by rule 2 (the canvas differs from the reference)


def choose_anchors(grids: np.ndarray, coverage: np.ndarray, colour: np.ndarray, reference,
                   coverage_threshold: float, difference_threshold: float, ties: np.ndarray,
                   eligible: np.ndarray = None, holding: Optional[np.ndarray] = None) -> ChosenAnchors:
    """This layer's anchors (x, y) in N (N, 4) grids (x0, y0, x1, y1) of one stroke size, all at once.

    coverage: (H, W) in [0, 1], how fully each pixel is painted (the painter
    passes the canvas opacity, where paint really lies; ALGORITHM §3's
    coverage map counts faint fringe stamps as half a cover).
    reference: a ``SmoothedImage`` of what the grids' strokes aim at (the
    painter passes the reference at the grids' brush scale: a stroke cannot
    paint detail finer than its brush, so a later layer adds a stroke only
    where the canvas misses what a stroke of this size can give).
    In each grid:
    1. p_min, the least-covered pixel, if its coverage < T_c;
    2. else p_max, the pixel whose canvas colour differs most from the
       reference, if that Euclidean RGB distance > T_d;
    3. else no stroke. Only the pixels where the (H, W) bool ``eligible`` is True
       take part when it is given (a sequence's births, ALGORITHM §9): a grid
       with none gets no stroke. Ties (e.g. a whole grid still at coverage 0) go to
       tied pixel floor(u k) of the k tied ones in row-major order, u being
       the grid's ``ties`` (N,) uniform number in [0, 1), so anchors do not
       line up on grid corners.
    Grids are looked at in runs of about equal pixels on the worker threads
    (each grid's choice is its own): one per worker, or as many as keep each
    within tuning.ANCHOR_CHUNK_PIXELS / workers pixels (so the workers look at about
    tuning.ANCHOR_CHUNK_PIXELS at a time), none of fewer than tuning.ANCHOR_LEAST_PIXELS.
    ``holding`` (N,) bool, with ``eligible``: which grids hold an eligible pixel (``grids_holding``); the others
    get no stroke without being looked at.
    """
    grids = np.asarray(grids, np.int64).reshape(-1, 4)
    if holding is not None and not holding.all():
        found = ChosenAnchors(np.zeros((len(grids), 2), np.int64), np.zeros(len(grids), bool),
                              np.zeros(len(grids), bool))
        if holding.any():
            looked = choose_anchors(grids[holding], coverage, colour, reference, coverage_threshold,
                                    difference_threshold, np.asarray(ties)[holding], eligible)
            for whole, part in zip(found, looked, strict=True):
                whole[holding] = part
        return found
    if len(grids) == 0:
        return ChosenAnchors(np.zeros((0, 2), np.int64), np.zeros(0, bool), np.zeros(0, bool))
    areas = (grids[:, 2] - grids[:, 0]) * (grids[:, 3] - grids[:, 1])
    workers = worker_count()
    count = max(workers, len(bounded_runs(areas, max(1, tuning.ANCHOR_CHUNK_PIXELS // workers))))
    parts = run_all(lambda run: _choose_anchors(grids[slice(*run)], coverage, colour, reference, coverage_threshold,
                                                difference_threshold, ties[slice(*run)], eligible),
                    balanced_runs(areas, count, tuning.ANCHOR_LEAST_PIXELS))
    return ChosenAnchors(*(np.concatenate(arrays) for arrays in zip(*parts, strict=True)))


def grids_holding(grids: np.ndarray, places: np.ndarray) -> np.ndarray:
    """(N,) bool: which of N (N, 4) grids (x0, y0, x1, y1) hold a pixel where (H, W) bool ``places`` is True, by a
    summed-area table of ``places``."""
    table = summed_area(places)
    x0, y0, x1, y1 = np.asarray(grids, np.int64).reshape(-1, 4).T
    return (table[y1, x1] - table[y0, x1] - table[y1, x0] + table[y0, x0]) > 0


def summed_area(mask: np.ndarray) -> np.ndarray:
    """(H + 1, W + 1) int32 (int64 beyond 2^31 pixels): the summed-area table of (H, W) bool ``mask``: entry [r, c]
    counts the True pixels of rows < r and columns < c."""
    h, w = mask.shape
    table = np.zeros((h + 1, w + 1), np.int32 if h * w < 2 ** 31 else np.int64)
    np.cumsum(np.cumsum(mask, axis=0, dtype=table.dtype), axis=1, out=table[1:, 1:])
    return table


def _choose_anchors(grids: np.ndarray, coverage: np.ndarray, colour: np.ndarray, reference,
                    coverage_threshold: float, difference_threshold: float, ties: np.ndarray,
                    eligible: np.ndarray = None) -> ChosenAnchors:
    """``choose_anchors`` of a chunk of grids."""
    n = len(grids)
    x, y, starts = grid_pixels(grids)
    owner = np.repeat(np.arange(n), np.diff(starts))
    cov = coverage[y, x]
    if eligible is not None:
        left_out = ~eligible[y, x]
        cov = np.where(left_out, np.float32(np.inf), cov)
    low = np.minimum.reduceat(cov, starts[:-1])
    cover = low < coverage_threshold
    candidate = cover[owner] & (cov == low[owner])
    chosen = cover.copy()
    rest = ~cover[owner]
    if rest.any():
        looked = rest if eligible is None else rest & ~left_out        # a pixel left out keeps -inf
        xs, ys = x[looked], y[looked]
        diff = np.take(colour.reshape(-1, 3), ys * colour.shape[1] + xs, axis=0)
        diff -= reference.sample(xs.astype(np.float32), ys.astype(np.float32))
        dist2 = np.full(len(x), -np.inf, np.float32)
        dist2[looked] = np.einsum("ij,ij->i", diff, diff)
        high = np.maximum.reduceat(dist2, starts[:-1])
        chosen |= ~cover & (high > np.float32(difference_threshold * difference_threshold))
        candidate |= rest & (dist2 == high[owner])
    candidate &= chosen[owner]
    count = np.add.reduceat(candidate.astype(np.int64), starts[:-1])
    pick = np.minimum((np.asarray(ties, np.float64) * count).astype(np.int64), np.maximum(count - 1, 0))
    rank = np.cumsum(candidate) - 1
    before = np.concatenate(([0], np.cumsum(count)[:-1]))
    hit = np.flatnonzero(candidate & (rank == before[owner] + pick[owner]))
    anchors = np.zeros((n, 2), np.int64)
    anchors[owner[hit], 0], anchors[owner[hit], 1] = x[hit], y[hit]
    return ChosenAnchors(anchors, chosen, chosen & ~cover)


def canvas_error(canvas: Canvas, reference: np.ndarray) -> np.ndarray:
    """Hertzmann 1998's error, what ``hertzmann_anchors`` reads: (H, W) float64 Euclidean RGB distance between
    ``reference`` (H, W, 3) sRGB [0, 1] and the canvas colour, on the 0-255 scale; +inf where the canvas is bare
    (coverage 0)."""
    diff = reference - canvas.colour
    error = np.sqrt(np.einsum("ijk,ijk->ij", diff, diff, dtype=np.float64)) * 255.0
    error[canvas.coverage <= 0.0] = np.inf
    return error


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
