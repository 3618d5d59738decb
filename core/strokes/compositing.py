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

MAX_INTENSITY = 1.0 - 1e-6  # keeps log(1 - I) finite for full-contact bristles
MAX_ROWS_PER_PIXEL = 8  # brush rows a pixel gets from one stroke before stamps are spaced out


@dataclass
class Footprint:
    """What one stroke does to the pixels it touches.

    pixels:        int32 (U,) flat indices (row * W + column), ascending, unique.
    transmittance: float64 (U,) prod (1 - a) over all contributions: the share of
                   the old canvas colour that shows through.
    paint:         float32 (U, 3) sum_s a_s C_s prod_{t>s} (1 - a_t): the paint laid on top.
    deposit:       float32 (U,) bristle contact that passed over the pixel, divided by the
                   brush's rows (a full pass of a uniform brush of contact I deposits I).
    height:        float32 (U,) the deposit shaped by the stroke's relief (ridges, build-up).
    """

    pixels: np.ndarray
    transmittance: np.ndarray
    paint: np.ndarray
    deposit: np.ndarray
    height: np.ndarray

    @classmethod
    def empty(cls) -> "Footprint":
        """A stroke that touches no pixel."""
        zero = np.zeros(0, np.float32)
        return cls(np.zeros(0, np.int32), np.zeros(0), np.zeros((0, 3), np.float32), zero, zero)


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


def stamp_stride(brush_length: int, max_rows: int = MAX_ROWS_PER_PIXEL) -> int:
    """Path samples per stamp for a brush ``brush_length`` px along: 1 up to ``max_rows``, then more.

    A brush L rows long stamped every pixel lays L contributions on each pixel
    it crosses, so the cost of a stroke grows with its width times its area.
    Stamping every k = round(L / max_rows) samples, each stamp counted k times
    (see stroke_footprint's ``repeat``), keeps about ``max_rows`` rows per
    pixel and the painter's cost linear in pixels.
    """
    return max(1, int(round(brush_length / max_rows)))


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
    pixels = (local[starts] // box_w + y0) * np.int32(w) + (local[starts] % box_w + x0)
    return Footprint(pixels.astype(np.int32), transmittance, paint, deposit.astype(np.float32),
                     height.astype(np.float32))
