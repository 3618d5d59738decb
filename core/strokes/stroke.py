"""One paint stroke: bristle colours (Eq. 5), its path, and laying it on the canvas (Eq. 4, §6)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, Iterable

import numpy as np

from ..colour import lab_to_srgb, srgb_to_lab
from ..params import Params
from .brush import BrushTip
from .canvas import Canvas
from .compositing import track_footprint
from .path import resample_by_length, tangent_angles
from .planning import plan_path
from .smoothing import SmoothedImage, smooth

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
    bristle_smoothing x width (equal sigmas share one smoothed image)."""
    levels: Dict[float, SmoothedImage] = {}

    def level(sigma: float) -> SmoothedImage:
        if sigma not in levels:
            levels[sigma] = smooth(reference, sigma)
        return levels[sigma]

    return {int(s): ColourSources(reference, level(params.edge_smoothing * s), level(params.anchor_smoothing * s),
                                  level(params.bristle_smoothing * s)) for s in sizes}


def detail_sources(reference: np.ndarray) -> ColourSources:
    """ColourSources of the detail pass: the reference itself, one colour per stroke, so a dotted
    highlight keeps its full colour."""
    exact = smooth(reference, 0.0)
    return ColourSources(reference, exact, exact, exact, deviation=0.0)


def colour_jitter(rng: np.random.Generator, lightness: float, hue: float) -> tuple:
    """One stroke's random colour change of Eq. 5: (L* offset (), RGB offset (3,) float32).

    The lightness offset is 100 U(-lightness, lightness) CIELAB L* units (a*
    and b* are kept, so hue and chroma stay); when ``hue`` > 0 the RGB offset
    adds U(-hue, hue) to each channel (hue jitter), else it is 0.
    """
    shift = 100.0 * rng.uniform(-lightness, lightness)
    offset = rng.uniform(-hue, hue, 3).astype(np.float32) if hue > 0 else np.zeros(3, np.float32)
    return shift, offset


def bristle_colours(sources: ColourSources, anchor: tuple, angle: float, tip: BrushTip, alpha: float,
                    deviation: float, jitter: tuple = (0.0, 0.0)) -> tuple:
    """Eq. 5: ((B, 3) sRGB colour of every bristle of ``tip``, (3,) anchor colour).

    The brush is centred on ``anchor`` (x, y) and turned to ``angle`` (its
    along axis). C_anchor is ``sources.anchor`` at the anchor; each bristle
    samples ``sources.bristles`` under it (bilinear) and
    C = C_anchor + d, with d = alpha (C_bristle - C_anchor) shortened to at
    most ``deviation`` (Euclidean RGB), then changed by the stroke's
    ``jitter`` (``colour_jitter``: an L* offset, then an RGB offset), clipped to [0, 1]. So an anchor on
    a star or a glint neither tints the stroke nor drags it along as a scratch.
    """
    c, s = np.cos(angle), np.sin(angle)
    x = anchor[0] + tip.along * c - tip.across * s
    y = anchor[1] + tip.along * s + tip.across * c
    at_anchor = sources.anchor.at(float(anchor[0]), float(anchor[1]))
    d = np.float32(alpha) * (sources.bristles.sample(x, y) - at_anchor)
    norm = np.sqrt(np.sum(d * d, axis=1, keepdims=True))
    d *= np.minimum(np.float32(1.0), np.float32(deviation) / np.maximum(norm, np.float32(1e-12)))
    shift, offset = jitter
    mixed = at_anchor + d
    if shift:
        lab = srgb_to_lab(mixed)
        lab[:, 0] += shift
        mixed = lab_to_srgb(lab)
    mixed = mixed + offset
    return np.clip(mixed, 0.0, 1.0).astype(np.float32), at_anchor


def _smoothstep(t: np.ndarray) -> np.ndarray:
    """0 below 0, 1 above 1, 3t^2 - 2t^3 between."""
    t = np.clip(t, 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def end_profile(arc: np.ndarray, width: float, taper: float, buildup: float) -> tuple:
    """Per-stamp (contact, relief) (each (S,) float32) of a stroke whose stamps sit at arc lengths ``arc`` (px).

    The brush lifts off over the last taper x width px (at most half the
    stroke) and touches down over the first half of that (at most a quarter
    of the stroke): the contact falls from 1 to LIFT_FLOOR at the very ends.
    Paint gathers where the brush starts to lift: relief 1 + buildup at one
    taper length before the end, fading to 1 within half a taper length.
    """
    arc = np.asarray(arc, np.float64)
    total = float(arc[-1]) if len(arc) else 0.0
    lift = min(taper * width, 0.5 * total)
    touch = min(0.5 * taper * width, 0.25 * total)
    contact = np.ones(len(arc))
    relief = np.ones(len(arc))
    if lift > 0:
        to_end = total - arc
        contact *= LIFT_FLOOR + (1.0 - LIFT_FLOOR) * _smoothstep(to_end / lift)
        relief += buildup * np.exp(-((to_end / lift - 1.0) / 0.5) ** 2)
    if touch > 0:
        contact *= LIFT_FLOOR + (1.0 - LIFT_FLOOR) * _smoothstep(arc / touch)
    return contact.astype(np.float32), relief.astype(np.float32)


def ridge_profile(across: np.ndarray, radius: float, ridge: float) -> np.ndarray:
    """(B,) float32 height factor of bristles at ``across`` px from the centre line of a brush ``radius`` px:
    1 in the middle, rising to 1 + ridge at the sides (paint pushed aside by the brush)."""
    t = np.abs(np.asarray(across, np.float64)) / max(radius, 1e-6)
    return (1.0 + ridge * _smoothstep((t - 0.45) / 0.4)).astype(np.float32)


def paint_stroke(canvas: Canvas, sources: ColourSources, orientation: np.ndarray, anchor: tuple, size: int,
                 layer: int, tip: BrushTip, rng: np.random.Generator, params: Params) -> Stroke:
    """Plan one stroke from ``anchor`` (x, y) with a brush ``size`` px wide, lay it on ``canvas``, return it.

    With params.renderer == 'lines' the stroke is a solid line instead (``paint_line_stroke``).
    """
    if params.renderer == "lines":
        return paint_line_stroke(canvas, sources, orientation, anchor, size, layer, params)
    angle = float(orientation[anchor[1], anchor[0]])
    jitter = colour_jitter(rng, params.perturbation, params.hue_perturbation)
    deviation = params.bristle_deviation if sources.deviation is None else sources.deviation
    colours, anchor_colour = bristle_colours(sources, anchor, angle, tip, params.bristle_alpha, deviation, jitter)
    brush_colour = np.einsum("b,bc->c", tip.intensity, colours) / tip.intensity.sum()
    plan = plan_path(anchor, size, orientation, canvas.colour, brush_colour, sources.reference, sources.edges,
                     params)
    samples, arc = resample_by_length(plan.samples, 1.0)
    angles = tangent_angles(samples, angle)
    rows = max(1.0, tip.length)
    contact, relief = end_profile(arc, size, params.taper, params.lift_buildup)
    footprint = track_footprint(samples, angles, tip.along, tip.across, tip.intensity, colours, canvas.height.shape,
                                passes=max(1.0, MIN_ROWS / rows), contact=contact, stamp_relief=relief,
                                bristle_relief=ridge_profile(tip.across, tip.radius, params.ridge_height), rows=rows)
    canvas.apply(footprint, params.height_mode, params.height_build)
    return Stroke(layer, (int(anchor[0]), int(anchor[1])), int(size), plan.polyline(), anchor_colour)


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


def paint_line_stroke(canvas: Canvas, sources: ColourSources, orientation: np.ndarray, anchor: tuple, size: int,
                      layer: int, params: Params) -> Stroke:
    """The Fig. 8c ablation: the paper's path, painted as one solid anti-aliased line of the anchor colour.

    The path is planned exactly as for the bristle brush (``plan_path``) with
    the anchor colour as the brush colour; the kept curve, thinned to a point
    every max(1, size / 4) samples (about a quarter of the width apart) plus
    its end, is drawn by ``solid_stroke`` with radius size / 2 and opacity 1.
    """
    colour = sources.anchor.at(float(anchor[0]), float(anchor[1]))
    plan = plan_path(anchor, size, orientation, canvas.colour, colour, sources.reference, sources.edges, params)
    kept = plan.samples
    every = max(1, int(size) // 4)
    line = kept[np.unique(np.append(np.arange(0, len(kept), every), len(kept) - 1))]
    solid_stroke(canvas, line, 0.5 * size, colour, 1.0, params.height_mode, params.height_build)
    return Stroke(layer, (int(anchor[0]), int(anchor[1])), int(size), plan.polyline(), colour.copy())
