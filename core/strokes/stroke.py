"""Paint strokes: their record, bristle colours (Eq. 5), end and ridge profiles, and solid strokes (ALGORITHM §5, §8)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, Iterable, NamedTuple

import numpy as np

from ..colour import lab_to_srgb, srgb_to_lab
from ..params import Params
from ..workers import run_all
from .brush import BrushTip
from .canvas import Canvas
from .smoothing import SmoothedImage, smooth, smoothing_cost

# A stroke covers as a brush at least this many rows long would: a short tip (small brushes have one or
# two rows) is counted as passing that many times, so small strokes are as opaque as large ones.
MIN_ROWS = 4.0

# Contact left at the very tip of a stroke's ends (the brush lifting off), as a fraction of full contact.
LIFT_FLOOR = 0.3


@dataclass
class Stroke:
    """A painted stroke as recorded in ``strokes.json``.

    layer: 0-based layer (the detail pass is the layer after the last).
    anchor: (x, y) pixel. size: brush width (px). path: (K, 2) float32 (x, y)
    points of the kept path: its ends and the control points between them.
    colour: sRGB anchor colour (3,).
    """

    layer: int
    anchor: tuple
    size: int
    path: np.ndarray
    colour: np.ndarray

    def to_dict(self) -> dict:
        """JSON-ready form."""
        return {"layer": self.layer, "anchor": [int(self.anchor[0]), int(self.anchor[1])], "size": int(self.size),
                "path": np.round(self.path, 2).tolist(), "colour": np.round(self.colour, 4).tolist()}


@dataclass(frozen=True)
class ColourSources:
    """Where the strokes of one brush width take their colours (ALGORITHM §5).

    reference: float32 (H, W, 3) sRGB [0, 1], the bilateral reference.
    edges: the reference smoothed at the brush's scale (the path's edge and colour tests).
    anchor: the reference smoothed for the anchor colour of Eq. 5.
    bristles: the reference lightly smoothed (each bristle's own colour).
    deviation: how far a bristle's own colour may stray from the anchor colour
    (Euclidean RGB), or None for ``Params.bristle_deviation``.
    """

    reference: np.ndarray
    edges: SmoothedImage
    anchor: SmoothedImage
    bristles: SmoothedImage
    deviation: float = None


def colour_sources(reference: np.ndarray, sizes: Iterable[int], params: Params) -> Dict[int, ColourSources]:
    """{width: ColourSources} for each brush width (px): sigmas edge_smoothing, anchor_smoothing and
    bristle_smoothing x width (equal sigmas share one smoothed image), the costliest first on the worker threads."""
    sigmas = {int(s): (params.edge_smoothing * s, params.anchor_smoothing * s, params.bristle_smoothing * s)
              for s in sizes}
    distinct = sorted({sigma for three in sigmas.values() for sigma in three}, key=smoothing_cost, reverse=True)
    levels = dict(zip(distinct, run_all(lambda sigma: smooth(reference, sigma), distinct), strict=True))
    return {s: ColourSources(reference, *(levels[sigma] for sigma in three)) for s, three in sigmas.items()}


def detail_sources(reference: np.ndarray) -> ColourSources:
    """ColourSources of the detail pass: the reference itself, one colour per stroke, so a dotted
    highlight keeps its full colour."""
    exact = smooth(reference, 0.0)
    return ColourSources(reference, exact, exact, exact, deviation=0.0)


class ColourJitter(NamedTuple):
    """N strokes' random colour changes (Eq. 5)."""

    shift: np.ndarray           # float64 (N,) CIELAB L* offsets
    offset: np.ndarray          # float32 (N, 3) RGB offsets


def colour_jitter(draws: np.ndarray, lightness: float, hue: float) -> ColourJitter:
    """N strokes' random colour changes of Eq. 5 from their (N, 4) uniform ``draws`` in [0, 1).

    The lightness offset ``shift`` is 100 U(-lightness, lightness) CIELAB L*
    units (a* and b* are kept, so hue and chroma stay); when ``hue`` > 0 the
    RGB ``offset`` adds U(-hue, hue) to each channel (hue jitter), else it is 0.
    """
    draws = np.asarray(draws, np.float64).reshape(-1, 4)
    shift = 100.0 * lightness * (2.0 * draws[:, 0] - 1.0)
    offset = (hue * (2.0 * draws[:, 1:4] - 1.0)).astype(np.float32)
    return ColourJitter(shift, offset)


class BristleColours(NamedTuple):
    """The colours N strokes of a brush of B bristles paint with (Eq. 5)."""

    bristles: np.ndarray        # float32 (N, B, 3) sRGB [0, 1], every bristle's colour
    anchor: np.ndarray          # float32 (N, 3) sRGB, C_anchor: ``sources.anchor`` at each anchor


def bristle_colours(sources: ColourSources, anchors: np.ndarray, angles: np.ndarray, tip: BrushTip, alpha: float,
                    deviation: float, shift: np.ndarray, offset: np.ndarray,
                    lightness: bool = True) -> BristleColours:
    """Eq. 5 for N strokes: the colour of every bristle of ``tip`` and the anchor colours.

    Each brush is centred on its anchor (``anchors`` (N, 2) (x, y)) and
    turned to its angle (``angles`` (N,), its along axis). C_anchor is
    ``sources.anchor`` at the anchor; each bristle samples
    ``sources.bristles`` under it (bilinear) and C = C_anchor + d, with
    d = alpha (C_bristle - C_anchor) shortened to at most ``deviation``
    (Euclidean RGB), then moved by the stroke's L* offset ``shift`` (N,)
    (through CIELAB, when ``lightness``) and RGB ``offset`` (N, 3), clipped to
    [0, 1]. So an anchor on a star or a glint neither tints the stroke nor
    drags it along as a scratch.
    """
    anchors = np.asarray(anchors, np.float64).reshape(-1, 2)
    c, s = np.cos(angles)[:, None], np.sin(angles)[:, None]
    x = anchors[:, 0:1] + tip.along * c - tip.across * s
    y = anchors[:, 1:2] + tip.along * s + tip.across * c
    at_anchor = sources.anchor.sample(anchors[:, 0], anchors[:, 1])
    d = np.float32(alpha) * (sources.bristles.sample(x, y) - at_anchor[:, None, :])
    norm = np.sqrt(np.sum(d * d, axis=2, keepdims=True))
    d *= np.minimum(np.float32(1.0), np.float32(deviation) / np.maximum(norm, np.float32(1e-12)))
    mixed = at_anchor[:, None, :] + d
    if lightness:
        lab = srgb_to_lab(mixed.reshape(-1, 3))
        lab[:, 0] += np.repeat(shift, d.shape[1])
        mixed = lab_to_srgb(lab).reshape(d.shape)
    mixed = mixed + offset[:, None, :]
    return BristleColours(np.clip(mixed, 0.0, 1.0).astype(np.float32), at_anchor)


def _smoothstep(t: np.ndarray) -> np.ndarray:
    """0 below 0, 1 above 1, 3t^2 - 2t^3 between."""
    t = np.clip(t, 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


class EndProfile(NamedTuple):
    """What S stamps of strokes press and build where the brush touches down and lifts off."""

    contact: np.ndarray         # float32 (S,) in (0, 1], the brush's pressure
    relief: np.ndarray          # float32 (S,) >= 1, the factor on the height the stamp builds


def end_profile(arc: np.ndarray, total: np.ndarray, width: float, taper: float, buildup: float) -> EndProfile:
    """The contact and relief of stamps at arc lengths ``arc`` (S,) px along strokes ``total`` (S,) px long
    (each stamp's own stroke's length).

    The brush lifts off over the last taper x width px (at most half the
    stroke) and touches down over the first half of that (at most a quarter
    of the stroke): the contact falls from 1 to LIFT_FLOOR at the very ends.
    Paint gathers where the brush starts to lift: relief 1 + buildup at one
    taper length before the end, fading to 1 within half a taper length.
    """
    arc = np.asarray(arc, np.float64)
    total = np.asarray(total, np.float64)
    lift = np.minimum(taper * width, 0.5 * total)
    touch = np.minimum(0.5 * taper * width, 0.25 * total)
    to_end = total - arc
    lifting = lift > 0
    ratio = np.divide(to_end, lift, out=np.ones_like(arc), where=lifting)
    contact = np.where(lifting, LIFT_FLOOR + (1.0 - LIFT_FLOOR) * _smoothstep(ratio), 1.0)
    relief = np.where(lifting, 1.0 + buildup * np.exp(-((ratio - 1.0) / 0.5) ** 2), 1.0)
    touching = touch > 0
    start = np.divide(arc, touch, out=np.ones_like(arc), where=touching)
    contact = contact * np.where(touching, LIFT_FLOOR + (1.0 - LIFT_FLOOR) * _smoothstep(start), 1.0)
    return EndProfile(contact.astype(np.float32), relief.astype(np.float32))


def ridge_profile(across: np.ndarray, radius: float, ridge: float) -> np.ndarray:
    """(B,) float32 height factor of bristles at ``across`` px from the centre line of a brush ``radius`` px:
    1 in the middle, rising to 1 + ridge at the sides (paint pushed aside by the brush)."""
    t = np.abs(np.asarray(across, np.float64)) / max(radius, 1e-6)
    return (1.0 + ridge * _smoothstep((t - 0.45) / 0.4)).astype(np.float32)


# ---------------------------------------------------------------------------
# solid strokes: Hertzmann 1998 and the "lines" ablation (ALGORITHM §8)


def line_distance(points: np.ndarray, radius: float, shape: tuple, with_segments: bool = False):
    """Distance from pixel centres to a polyline, on the part of its box that lies on the canvas.

    points: (K, 2) float (x, y), K >= 1 (one point is a round dab). Only pixels
    within radius + 1 px of a segment's box are looked at. Each segment is
    evaluated on its own window (all windows have one size, so the distances
    of every segment come out of one vectorised expression); the windows are
    folded into the stroke's box by an unbuffered minimum (``np.minimum.at``).

    Returns None when the stroke misses the canvas, else (y0, x0, distance
    (bh, bw) float32 px, segment (bh, bw) int index of the nearest segment or
    None). Pixels no segment window reached hold +inf.
    """
    h, w = shape[:2]
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    p0 = pts[:-1] if len(pts) > 1 else pts
    p1 = pts[1:] if len(pts) > 1 else pts
    reach = float(radius) + 1.0
    lo_x = np.maximum(np.floor(np.minimum(p0[:, 0], p1[:, 0]) - reach), 0).astype(np.int64)
    hi_x = np.minimum(np.ceil(np.maximum(p0[:, 0], p1[:, 0]) + reach), w - 1).astype(np.int64)
    lo_y = np.maximum(np.floor(np.minimum(p0[:, 1], p1[:, 1]) - reach), 0).astype(np.int64)
    hi_y = np.minimum(np.ceil(np.maximum(p0[:, 1], p1[:, 1]) + reach), h - 1).astype(np.int64)
    live = (lo_x <= hi_x) & (lo_y <= hi_y)
    if not live.all():
        if not live.any():
            return None
        p0, p1, lo_x, hi_x, lo_y, hi_y = p0[live], p1[live], lo_x[live], hi_x[live], lo_y[live], hi_y[live]
    bx0, bx1, by0, by1 = int(lo_x.min()), int(hi_x.max()), int(lo_y.min()), int(hi_y.max())
    wx = int((hi_x - lo_x).max()) + 1
    wy = int((hi_y - lo_y).max()) + 1
    ox = np.minimum(lo_x, bx1 - wx + 1)           # every window keeps inside the box
    oy = np.minimum(lo_y, by1 - wy + 1)
    dx = (p1[:, 0] - p0[:, 0]).astype(np.float32)
    dy = (p1[:, 1] - p0[:, 1]).astype(np.float32)
    len2 = dx * dx + dy * dy
    inv = np.where(len2 > 0, 1.0 / np.maximum(len2, 1e-12), 0.0).astype(np.float32)
    ax = ((ox - bx0)[:, None] + np.arange(wx)[None, :] + (bx0 - p0[:, 0:1])).astype(np.float32)  # (S, wx)
    ay = ((oy - by0)[:, None] + np.arange(wy)[None, :] + (by0 - p0[:, 1:2])).astype(np.float32)  # (S, wy)
    t = ax[:, None, :] * (dx * inv)[:, None, None] + ay[:, :, None] * (dy * inv)[:, None, None]
    np.clip(t, 0.0, 1.0, out=t)
    ex = ax[:, None, :] - t * dx[:, None, None]
    ey = ay[:, :, None] - t * dy[:, None, None]
    d2 = ex * ex + ey * ey                                                   # (S, wy, wx)
    bh, bw = by1 - by0 + 1, bx1 - bx0 + 1
    segment = None
    if len(d2) == 1 and wy == bh and wx == bw:
        best = d2[0]
        if with_segments:
            segment = np.zeros((bh, bw), np.int64)
    else:
        best = np.full(bh * bw, np.inf, np.float32)
        flat = (((oy - by0)[:, None, None] + np.arange(wy)[None, :, None]) * bw
                + ((ox - bx0)[:, None, None] + np.arange(wx)[None, None, :])).ravel()
        values = d2.ravel()
        np.minimum.at(best, flat, values)
        if with_segments:
            segment = np.zeros(bh * bw, np.int64)
            hit = np.flatnonzero(values == best[flat])
            segment[flat[hit]] = hit // (wy * wx)
            segment = segment.reshape(bh, bw)
        best = best.reshape(bh, bw)
    if with_segments and not live.all():
        segment = np.flatnonzero(live)[segment]
    return by0, bx0, np.sqrt(best), segment


def solid_stroke(canvas: Canvas, points: np.ndarray, radius: float, colour: np.ndarray, alpha: float,
                 height_mode: str, build: float, orientation: np.ndarray = None) -> None:
    """Lay a solid anti-aliased, round-capped line of ``radius`` px along (K, 2) ``points`` on ``canvas``.

    Line coverage o = clip(radius + 0.5 - d, 0, 1) with d the distance to the
    polyline (a 1 px ramp centred on the edge). With a = alpha o:
    colour C = a C_stroke + (1 - a) C; coverage 1 - (1 - cov)(1 - a);
    stroke height h = alpha sqrt(1 - (d / radius)^2) (a rounded profile across
    the stroke); height H + o h - o f k H with f = o and k = 1 ('over') or
    1 - build ('accumulate'), as core/strokes/canvas.py; opacity A = a + (1 - a) A (a stroke of
    opacity alpha lets the canvas show through). When ``orientation`` (H, W)
    is given, pixels with a >= 0.5 take the direction (mod pi) of their
    nearest segment.
    """
    found = line_distance(points, radius, canvas.height.shape, with_segments=orientation is not None)
    if found is None:
        return
    y0, x0, d, segment = found
    bh, bw = d.shape
    rows, cols = slice(y0, y0 + bh), slice(x0, x0 + bw)
    o = np.clip(np.float32(radius + 0.5) - d, 0.0, 1.0)
    a = o * np.float32(alpha) if alpha != 1.0 else o
    c = canvas.colour[rows, cols]
    c += a[..., None] * (np.asarray(colour, np.float32) - c)
    cov = canvas.coverage[rows, cols]
    cov += a * (1.0 - cov)
    r2 = d * d
    r2 *= np.float32(1.0 / (radius * radius))
    np.subtract(1.0, r2, out=r2)
    np.maximum(r2, 0.0, out=r2)
    profile = np.sqrt(r2, out=r2)
    if alpha != 1.0:
        profile *= np.float32(alpha)
    hgt = canvas.height[rows, cols]
    loss = np.float32(1.0 - build if height_mode == "accumulate" else 1.0)
    hgt += o * profile - o * o * loss * hgt
    op = canvas.opacity[rows, cols]
    op += a * (1.0 - op)
    if orientation is not None:
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        if len(pts) > 1:
            step = pts[1:] - pts[:-1]
            angles = np.mod(np.arctan2(step[:, 1], step[:, 0]), np.pi).astype(np.float32)
            top = a >= 0.5
            orientation[rows, cols][top] = angles[segment[top]]
