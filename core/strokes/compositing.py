"""Whole-stroke compositing of stamped bristles (ALGORITHM §5, Eq. 4, and §6).

A stroke is the brush stamped along its path, turned along the path. Each
bristle of each stamp lands at a sub-pixel position and is splatted onto the
four pixels around it with bilinear weights w; a pixel receiving weight w of
a bristle of contact I is covered as by a bristle of contact 1 - (1 - I)^w
(contact adds as optical depth, so a bristle split over four pixels covers
exactly what it would on one, and a shifted stroke is the same stroke moved).
Every (stamp, bristle, pixel) triple is a contribution. Folding Eq. 4,
C <- a C_b + (1 - a) C, over a pixel's contributions in stamp order gives

    C = sum_s a_s C_s prod_{t>s} (1 - a_t) + C_0 prod_t (1 - a_t),

which is computed for all pixels at once: contributions are sorted by pixel
(stably, so stamp order is kept inside a pixel) and the suffix products come
from a cumulative sum of log(1 - a).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse

from .folding import MAX_INTENSITY, tip_grid, track_folds


@dataclass
class Footprint:
    """What one stroke does to the box of canvas pixels around it.

    top, left:     the box's first row and column on the canvas (px).
    transmittance: float32 (h, w) in [0, 1], prod (1 - a) over all contributions: the share
                   of the old canvas colour that shows through (1 where the stroke missed).
    paint:         float32 (h, w, 3) sum_s a_s C_s prod_{t>s} (1 - a_t): the paint laid on top.
    deposit:       float32 (h, w) >= 0, bristle contact that passed over the pixel, divided by
                   the brush's rows (a full pass of a uniform brush of contact I deposits I).
    height:        float32 (h, w) >= 0, the deposit shaped by the stroke's relief (ridges, build-up).
    """

    top: int
    left: int
    transmittance: np.ndarray
    paint: np.ndarray
    deposit: np.ndarray
    height: np.ndarray

    @classmethod
    def empty(cls) -> "Footprint":
        """A stroke that touches no pixel."""
        zero = np.zeros((0, 0), np.float32)
        return cls(0, 0, zero, np.zeros((0, 0, 3), np.float32), zero, zero)

    @property
    def touched(self) -> np.ndarray:
        """bool (h, w): the pixels of the box the stroke laid contact (and so paint) on."""
        return self.deposit > 0.0


def stamp_positions(samples: np.ndarray, angles: np.ndarray, along: np.ndarray, across: np.ndarray) -> tuple:
    """Positions (x, y), each (S, B) float32 px, of B bristles stamped at S path samples.

    samples (S, 2) (x, y); angles (S,) direction of travel; along/across (B,)
    bristle offsets along the path and towards its left-hand normal
    (direction turned by +90 degrees, in image axes).
    """
    c = np.cos(angles).astype(np.float32)[:, None]
    s = np.sin(angles).astype(np.float32)[:, None]
    along = np.asarray(along, np.float32)[None, :]
    across = np.asarray(across, np.float32)[None, :]
    x = samples[:, 0:1].astype(np.float32) + along * c - across * s
    y = samples[:, 1:2].astype(np.float32) + along * s + across * c
    return x, y


def bilinear_splat(x: np.ndarray, y: np.ndarray, shape: tuple) -> tuple:
    """The four pixels around each position and their bilinear weights.

    x, y: (N,) float32 px (pixel centres at integers). Returns (columns, rows)
    int32 (N, 4) and weights float32 (N, 4) summing to 1 per position.
    """
    fx = np.floor(x)
    fy = np.floor(y)
    ax = x - fx
    ay = y - fy
    bx = 1.0 - ax
    by = 1.0 - ay
    weights = np.stack([bx * by, ax * by, bx * ay, ax * ay], axis=1)
    ix = fx.astype(np.int32)[:, None] + np.array([0, 1, 0, 1], np.int32)
    iy = fy.astype(np.int32)[:, None] + np.array([0, 0, 1, 1], np.int32)
    return ix, iy, weights


def stroke_footprint(samples: np.ndarray, angles: np.ndarray, along: np.ndarray, across: np.ndarray,
                     intensity: np.ndarray, colours: np.ndarray, shape: tuple, repeat: int = 1,
                     contact: np.ndarray = None, stamp_relief: np.ndarray = None,
                     bristle_relief: np.ndarray = None, rows: float = 1.0) -> Footprint:
    """Composite a whole stroke: the Footprint of B bristles stamped at S samples on an (H, W) canvas.

    intensity (B,) in (0, 1]; colours (B, 3) sRGB, one per bristle, kept along the whole path.
    repeat: each stamp stands for this many identical stamps (a number, or (S,)
    one per stamp), so a bristle of contact I lets (1 - I)^repeat of the
    colour below show through.
    contact: (S,) in [0, 1], each stamp's pressure (the brush lifting at the
    ends), multiplying the bristles' contact; default 1.
    stamp_relief (S,), bristle_relief (B,): factors >= 0 on the height each
    contribution builds (paint gathering where the brush lifts, ridges at the
    sides); default 1. rows: the deposit's normaliser, the rows of the brush
    (with samples one px apart a bristle passing over a pixel deposits its
    contact once).
    Contributions off the canvas are dropped.
    """
    h, w = shape
    n_stamps, n_bristles = len(samples), len(intensity)
    x, y = stamp_positions(samples, angles, along, across)
    strength = np.broadcast_to(np.asarray(intensity, np.float32)[None, :], (n_stamps, n_bristles))
    if contact is not None:
        strength = strength * np.asarray(contact, np.float32)[:, None]
    strength = np.minimum(strength, np.float32(MAX_INTENSITY)).ravel()
    ix, iy, weight = bilinear_splat(x.ravel(), y.ravel(), shape)
    inside = (ix >= 0) & (ix < w) & (iy >= 0) & (iy < h) & (weight > 0)
    contribution = np.flatnonzero(inside.ravel()).astype(np.int32)
    if contribution.size == 0 or not np.any(strength > 0):
        return Footprint.empty()
    ix = ix.ravel()[contribution]
    iy = iy.ravel()[contribution]
    x0, y0 = int(ix.min()), int(iy.min())
    box_w = int(ix.max()) - x0 + 1
    local = (iy - y0) * np.int32(box_w) + (ix - x0)            # int32 keys: the stable sort is fast on them
    order = np.argsort(local, kind="stable")
    contribution = contribution[order]
    local = local[order]
    point = contribution >> 2                                  # (stamp, bristle) index
    weight = weight.ravel()[contribution].astype(np.float64)
    bristle = point % n_bristles

    new_pixel = np.empty(len(local), dtype=bool)
    new_pixel[0] = True
    np.not_equal(local[1:], local[:-1], out=new_pixel[1:])
    starts = np.flatnonzero(new_pixel)
    ends = np.append(starts[1:], len(local))
    counts = ends - starts

    repeat = np.broadcast_to(np.asarray(repeat, np.float64)[..., None], (n_stamps, n_bristles)).ravel()
    point_log_keep = repeat * np.log1p(-strength.astype(np.float64))
    log_keep = weight * point_log_keep[point]
    cumulative = np.cumsum(log_keep)
    segment_total_cum = np.repeat(cumulative[ends - 1], counts)
    after = np.exp(segment_total_cum - cumulative)             # prod over later contributions of (1 - a)
    paint_weight = (-np.expm1(log_keep) * after).astype(np.float32)
    paint = np.add.reduceat(paint_weight[:, None] * np.asarray(colours, dtype=np.float32)[bristle], starts, axis=0)
    before_start = cumulative[starts] - log_keep[starts]
    transmittance = np.exp(cumulative[ends - 1] - before_start)

    laid = (weight * (repeat[point] / float(rows))).astype(np.float32) * strength[point]
    deposit = np.add.reduceat(laid, starts)
    if stamp_relief is not None or bristle_relief is not None:
        gain = np.ones(len(point), np.float32)
        if stamp_relief is not None:
            gain *= np.asarray(stamp_relief, np.float32)[point // n_bristles]
        if bristle_relief is not None:
            gain *= np.asarray(bristle_relief, np.float32)[bristle]
        height = np.add.reduceat(laid * gain, starts)
    else:
        height = deposit
    box_h = int(local[-1]) // box_w + 1
    at = local[starts]
    box = Footprint(y0, x0, np.ones((box_h, box_w), np.float32), np.zeros((box_h, box_w, 3), np.float32),
                    np.zeros((box_h, box_w), np.float32), np.zeros((box_h, box_w), np.float32))
    box.transmittance.ravel()[at] = transmittance
    box.paint.reshape(-1, 3)[at] = paint
    box.deposit.ravel()[at] = deposit
    box.height.ravel()[at] = height
    return box


def path_at(samples: np.ndarray, angles: np.ndarray, arc: np.ndarray) -> tuple:
    """Positions (x, y) and directions (K,) along a path of S samples one px apart, at arc lengths ``arc`` (K,) px.

    Inside [0, S - 1] positions and unwrapped directions are interpolated
    linearly; beyond the ends the path goes on straight along its end directions.
    """
    s = len(samples)
    theta = np.unwrap(np.asarray(angles, np.float64))
    if s == 1:
        t = np.asarray(arc, np.float64)
        return samples[0, 0] + t * np.cos(theta[0]), samples[0, 1] + t * np.sin(theta[0]), np.full(len(t), theta[0])
    index = np.arange(s, dtype=np.float64)
    t = np.asarray(arc, np.float64)
    x = np.interp(t, index, samples[:, 0])
    y = np.interp(t, index, samples[:, 1])
    direction = np.interp(t, index, theta)
    before, after = t < 0, t > s - 1
    x[before] = samples[0, 0] + t[before] * np.cos(theta[0])
    y[before] = samples[0, 1] + t[before] * np.sin(theta[0])
    x[after] = samples[-1, 0] + (t[after] - (s - 1)) * np.cos(theta[-1])
    y[after] = samples[-1, 1] + (t[after] - (s - 1)) * np.sin(theta[-1])
    return x, y, direction


def track_footprint(samples: np.ndarray, angles: np.ndarray, along: np.ndarray, across: np.ndarray,
                    intensity: np.ndarray, colours: np.ndarray, shape: tuple, passes: float = 1.0,
                    contact: np.ndarray = None, stamp_relief: np.ndarray = None,
                    bristle_relief: np.ndarray = None, rows: float = 1.0) -> Footprint:
    """The Footprint of a stroke with every bristle column folded once: the fast form of ``stroke_footprint``.

    samples (S, 2), one px apart, and angles (S,): the path, stamped at every
    sample; the other arguments as ``stroke_footprint`` (``passes`` is its
    ``repeat``, the same for every stamp; contact and stamp_relief (S,)).
    On a straight path the bristle of row r stamped at sample s lands where
    the bristle of row r + 1 lands at sample s + 1: each column of the brush
    draws one track, and the rows passing over a point of it fold, in stamp
    order (front row first), into one contribution (paint, transmittance) of
    Eq. 4. The track is sampled every px of arc, each sample folding the rows
    whose stamps exist there (all of them inside the stroke, fewer at its
    ends), then splatted like a bristle (see the module docstring). This lays
    R times fewer contributions for a brush R rows long (the folds come from
    ``core.strokes.folding.track_folds``). The few track samples that meet
    at a pixel (neighbouring columns and arc positions of one stroke, whose
    colours are close) lay their paint together, mixed by the optical depth
    each lays (``splat_box``: one sparse product for the whole stroke); the
    order of Eq. 4 is kept between strokes and, through the fold, between a
    column's rows. On
    a curved path a track follows the path's normal at its own arc length,
    which differs from stamping by the brush's turn over its own length; the
    contact and relief of a track sample are the path's at its arc length.
    """
    h, w = shape
    n_samples = len(samples)
    row, column, n_rows, n_columns = tip_grid(along, across)
    grid = np.zeros((n_rows, n_columns), np.float32)
    grid[row, column] = intensity
    grid_colour = np.zeros((n_rows, n_columns, 3), np.float32)
    grid_colour[row, column] = colours
    offsets = (float(np.min(across)) + np.arange(n_columns)).astype(np.float32)
    ridge = np.ones(n_columns, np.float32)
    if bristle_relief is not None:
        ridge[column] = bristle_relief

    n_track = n_samples + n_rows - 1
    k = np.arange(n_track)
    arc = k - (n_rows - 1) + float(np.max(along))                    # arc length of each track sample (px)
    first_row = np.maximum(0, n_rows - 1 - k)
    last_row = np.minimum(n_rows - 1, n_samples + n_rows - 2 - k)
    stamp_index = np.arange(n_samples, dtype=np.float64)
    touch = np.ones(n_track) if contact is None else np.interp(arc, stamp_index, contact)
    colour, log_total, laid = track_folds(first_row, last_row, touch, grid, grid_colour, passes)
    build = np.ones(n_track, np.float32) if stamp_relief is None else \
        np.interp(arc, stamp_index, stamp_relief).astype(np.float32)

    # What each track sample lays, per unit of splat weight: optical depth, depth-weighted colour, contact, height.
    values = np.empty((n_track, n_columns, 6), np.float32)
    np.negative(log_total, out=values[..., 0])
    for ch in range(3):
        np.multiply(colour[ch], values[..., 0], out=values[..., 1 + ch])
    np.multiply(laid, np.float32(1.0 / float(rows)), out=values[..., 4])
    np.multiply(values[..., 4], build[:, None] * ridge[None, :], out=values[..., 5])

    px, py, direction = path_at(np.asarray(samples, np.float64), angles, arc)
    c, s = np.cos(direction)[:, None], np.sin(direction)[:, None]
    x = (px[:, None] - offsets[None, :] * s).astype(np.float32)                             # (K, W)
    y = (py[:, None] + offsets[None, :] * c).astype(np.float32)
    if n_track > 1:                                                                         # arc a track sample spans
        span = np.hypot(np.gradient(x, axis=0), np.gradient(y, axis=0)).astype(np.float32)
    else:
        span = np.ones_like(x)
    return splat_box(x.ravel(), y.ravel(), span.ravel(), values.reshape(-1, 6), shape)


def splat_box(x: np.ndarray, y: np.ndarray, weight: np.ndarray, values: np.ndarray, shape: tuple) -> Footprint:
    """The Footprint of N track samples at (x, y) (N,) px, each laying ``values`` (N, 6) times ``weight`` (N,).

    values: optical depth d, depth-weighted colour d C (3), contact, height.
    Each sample is splatted bilinearly onto the four pixels around it (one
    sparse product over the box for all six values); a pixel's transmittance
    is exp(-sum d) and its paint (1 - exp(-sum d)) sum d C / sum d.
    """
    h, w = shape
    fx = np.floor(x)
    fy = np.floor(y)
    ix = fx.astype(np.int32)
    iy = fy.astype(np.int32)
    x0, y0 = int(ix.min()), int(iy.min())
    box_w, box_h = int(ix.max()) - x0 + 2, int(iy.max()) - y0 + 2
    top, left = max(y0, 0), max(x0, 0)
    bottom, right = min(y0 + box_h, h), min(x0 + box_w, w)
    if top >= bottom or left >= right:
        return Footprint.empty()
    ax = x - fx
    ay = y - fy
    bx = 1.0 - ax
    by = (1.0 - ay) * weight
    ay *= weight
    weights = np.empty((len(x), 4), np.float32)                                              # bilinear, per corner
    np.multiply(bx, by, out=weights[:, 0])
    np.multiply(ax, by, out=weights[:, 1])
    np.multiply(bx, ay, out=weights[:, 2])
    np.multiply(ax, ay, out=weights[:, 3])
    base = (iy - np.int32(y0)) * np.int32(box_w) + (ix - np.int32(x0))
    corner = np.empty((len(x), 4), np.int32)
    for i, offset in enumerate((0, 1, box_w, box_w + 1)):
        np.add(base, np.int32(offset), out=corner[:, i])
    splat = sparse.csc_matrix((weights.ravel(), corner.ravel(), np.arange(0, weights.size + 1, 4, dtype=np.int32)),
                              shape=(box_h * box_w, len(x)))
    laid = (splat @ values).reshape(box_h, box_w, 6)[top - y0:bottom - y0, left - x0:right - x0]
    depth = laid[..., 0]
    transmittance = np.exp(-depth)
    share = np.divide(1.0 - transmittance, depth, out=np.zeros_like(depth), where=depth > 0)
    paint = np.empty(depth.shape + (3,), np.float32)
    for ch in range(3):
        np.multiply(laid[..., 1 + ch], share, out=paint[..., ch])
    return Footprint(top, left, transmittance, paint, np.ascontiguousarray(laid[..., 4]),
                     np.ascontiguousarray(laid[..., 5]))
