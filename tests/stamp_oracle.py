"""Test oracles and helpers for the stroke engine: a stamp-by-stamp stroke footprint and one-stroke painting.

``stroke_footprint`` composites every (stamp, bristle, pixel) contribution of
Eq. 4 in stamp order, bristle by bristle: the slow, direct reading of
ALGORITHM §5 that the engine's folded tracks are held to. Its result is a
``Footprints`` of one stroke, laid by the engine's own ``Canvas.lay``.
"""

import numpy as np

from core.strokes.compositing import Footprints, full_deposits
from core.strokes.folding import MAX_INTENSITY
from core.strokes.rounds import paint_round
from core.strokes.streams import visit_uniforms


def one_stroke(pixel, transmittance, paint, deposit, height) -> Footprints:
    """A ``Footprints`` of one stroke from its entries (pixel ascending)."""
    deposit = np.asarray(deposit, np.float32)
    starts = np.array([0, len(pixel)], np.int64)
    return Footprints(starts, np.asarray(pixel, np.int64), np.asarray(transmittance, np.float32),
                      np.asarray(paint, np.float32).reshape(-1, 3), deposit, np.asarray(height, np.float32),
                      full_deposits(deposit, starts))


def box_footprint(top, left, transmittance, paint, deposit, height, canvas_width) -> Footprints:
    """A ``Footprints`` of one stroke given as dense (h, w) boxes at (top, left) on a canvas ``canvas_width`` px wide."""
    h, w = np.shape(transmittance)
    rows, cols = np.mgrid[0:h, 0:w]
    pixel = ((top + rows) * canvas_width + left + cols).ravel()
    return one_stroke(pixel, np.ravel(transmittance), np.reshape(paint, (-1, 3)), np.ravel(deposit), np.ravel(height))


def paint_one(canvas, sources, orientation, anchor, size, tip, params, seed=0, layer=0):
    """Plan and lay one stroke from ``anchor`` (x, y) with the engine; returns its ``Stroke``."""
    draws = visit_uniforms(seed, layer, np.array([0]), 4)
    return paint_round(canvas, sources, orientation, np.array([anchor]), size, layer, tip, draws, params)[0]


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
                     intensity: np.ndarray, colours: np.ndarray, shape: tuple,
                     contact: np.ndarray = None, stamp_relief: np.ndarray = None,
                     bristle_relief: np.ndarray = None, rows: float = 1.0) -> Footprints:
    """Composite a whole stroke: the Footprints of B bristles stamped at S samples on an (H, W) canvas.

    intensity (B,) in (0, 1]; colours (B, 3) sRGB, one per bristle, kept along the whole path.
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
        return one_stroke(np.zeros(0, np.int64), np.zeros(0), np.zeros((0, 3)), np.zeros(0), np.zeros(0))
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

    point_log_keep = np.log1p(-strength.astype(np.float64))
    log_keep = weight * point_log_keep[point]
    cumulative = np.cumsum(log_keep)
    segment_total_cum = np.repeat(cumulative[ends - 1], counts)
    after = np.exp(segment_total_cum - cumulative)             # prod over later contributions of (1 - a)
    paint_weight = (-np.expm1(log_keep) * after).astype(np.float32)
    paint = np.add.reduceat(paint_weight[:, None] * np.asarray(colours, dtype=np.float32)[bristle], starts, axis=0)
    before_start = cumulative[starts] - log_keep[starts]
    transmittance = np.exp(cumulative[ends - 1] - before_start)

    laid = (weight * (1.0 / float(rows))).astype(np.float32) * strength[point]
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
    at = local[starts]
    pixel = (y0 + at // box_w).astype(np.int64) * w + (x0 + at % box_w)
    return one_stroke(pixel, transmittance, paint, deposit, height)




def engine_footprint(samples, angles, along, across, intensity, colours, shape, passes=1.0, contact=None,
                     stamp_relief=None, bristle_relief=None, rows=1.0) -> Footprints:
    """The engine's ``track_footprints`` of one stroke, called as ``stroke_footprint`` is."""
    from core.strokes.brush import BrushTip
    from core.strokes.compositing import track_footprints

    tip = BrushTip(np.asarray(along, np.float32), np.asarray(across, np.float32), np.asarray(intensity, np.float32),
                   1.0, 1.0)
    return track_footprints(np.asarray(samples, np.float64), np.asarray(angles, np.float64),
                            np.array([0, len(samples)]), tip, np.asarray(colours, np.float32)[None], shape, passes,
                            contact, stamp_relief, bristle_relief, rows)


def resampled(control: np.ndarray, spacing: float = 1.0) -> tuple:
    """Stamps one px apart along a Catmull-Rom curve through (K, 2) control points: (stamps (M, 2), arc (M,))."""
    from core.strokes.path import catmull_rom, resample_by_length

    step = np.hypot(*np.diff(control, axis=0).T).max()
    samples = catmull_rom(np.asarray(control, np.float64)[None], max(1, int(np.ceil(step))))
    stamps, arc, _ = resample_by_length(samples, np.array([0]), np.array([samples.shape[1] - 1]), spacing)
    return stamps, arc
