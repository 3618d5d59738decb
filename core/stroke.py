"""One paint stroke: bristle colours (Eq. 5), its path, and laying it on the canvas (Eq. 4)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .brush import BrushTip
from .canvas import Canvas
from .compositing import stamp_stride, stroke_footprint
from .params import Params
from .path import axial_difference, catmull_rom, clip_path, tangent_angles, trace_control_points


@dataclass
class Stroke:
    """A painted stroke as recorded in ``strokes.json``.

    layer: 0-based layer. anchor: (x, y) pixel. size: brush width (px).
    path: (K, 2) float32 (x, y) points of the kept path: its ends and the
    control points between them. colour: sRGB anchor colour (3,).
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


def nearest_pixels(shape: tuple, x: np.ndarray, y: np.ndarray) -> tuple:
    """(rows, columns) int arrays of the pixels nearest float positions x, y, clamped to an (H, W) canvas."""
    h, w = shape[:2]
    ix = np.minimum(np.maximum(np.floor(x + 0.5), 0), w - 1).astype(np.intp)
    iy = np.minimum(np.maximum(np.floor(y + 0.5), 0), h - 1).astype(np.intp)
    return iy, ix


def bristle_colours(reference: np.ndarray, anchor: tuple, angle: float, tip: BrushTip, alpha: float,
                    perturbation: np.ndarray) -> np.ndarray:
    """Eq. 5: (B, 3) sRGB colour of every bristle of ``tip``.

    The brush is centred on ``anchor`` (x, y) and turned to ``angle`` (its
    along axis); each bristle samples the reference under it:
    C = alpha C_bristle + (1 - alpha) C_anchor + perturbation, clipped to [0, 1].
    """
    c, s = np.cos(angle), np.sin(angle)
    x = anchor[0] + tip.along * c - tip.across * s
    y = anchor[1] + tip.along * s + tip.across * c
    under = reference[nearest_pixels(reference.shape, x, y)]
    at_anchor = reference[anchor[1], anchor[0]]
    mixed = alpha * under + ((1.0 - alpha) * at_anchor + perturbation)
    return np.minimum(np.maximum(mixed, 0.0), 1.0).astype(np.float32)


def keep_mask(samples: np.ndarray, reference: np.ndarray, canvas_colour: np.ndarray, orientation: np.ndarray,
              brush_colour: np.ndarray, anchor_angle: float, max_turn: float) -> np.ndarray:
    """(N,) bool: where a path may go on (ALGORITHM §5 stopping rules).

    A sample fails where (a) the canvas already matches the reference better
    than the brush colour would, |ref - canvas| < |ref - brush|, or (b) the
    orientation field turns more than ``max_turn`` from the anchor's angle.
    """
    at = nearest_pixels(reference.shape, samples[:, 0], samples[:, 1])
    ref = reference[at]
    can = canvas_colour[at]
    theta = orientation[at]
    closer = np.sum((ref - can) ** 2, axis=1) < np.sum((ref - brush_colour) ** 2, axis=1)
    turned = axial_difference(theta, anchor_angle) > max_turn
    return ~(closer | turned)


def paint_stroke(canvas: Canvas, reference: np.ndarray, orientation: np.ndarray, anchor: tuple, size: int,
                 layer: int, tip: BrushTip, rng: np.random.Generator, params: Params) -> Stroke:
    """Plan one stroke from ``anchor`` (x, y) with a brush ``size`` px wide, lay it on ``canvas``, return it.

    With params.renderer == 'lines' the stroke is a solid line instead (``paint_line_stroke``).
    """
    if params.renderer == "lines":
        return paint_line_stroke(canvas, reference, orientation, anchor, size, layer, params)
    angle = float(orientation[anchor[1], anchor[0]])
    perturbation = rng.uniform(-params.perturbation, params.perturbation, 3).astype(np.float32)
    colours = bristle_colours(reference, anchor, angle, tip, params.bristle_alpha, perturbation)
    brush_colour = (tip.intensity @ colours) / tip.intensity.sum()

    control, anchor_index = trace_control_points(anchor, orientation, max(1.0, 0.5 * size), params.max_length)
    samples, control_index = catmull_rom(control)
    keep = keep_mask(samples, reference, canvas.colour, orientation, brush_colour, angle,
                     params.orientation_threshold)
    start_index = control_index[anchor_index]
    kept, kept_anchor = clip_path(samples, start_index, keep)
    angles = tangent_angles(kept, angle)
    stride = stamp_stride(tip.length)
    stamps = np.unique(np.append(np.arange(0, len(kept), stride), len(kept) - 1))
    footprint = stroke_footprint(kept[stamps], angles[stamps], tip.along, tip.across, tip.intensity, colours,
                                 canvas.height.shape, repeat=stride)
    canvas.apply(footprint, params.opacity_width * size, params.height_mode, params.height_build)

    first = start_index - kept_anchor
    inner = control_index[(control_index > first) & (control_index < first + len(kept) - 1)] - first
    path = kept[np.unique(np.concatenate(([0], inner, [len(kept) - 1])))].astype(np.float32)
    return Stroke(layer, (int(anchor[0]), int(anchor[1])), int(size), path, reference[anchor[1], anchor[0]].copy())


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
    the stroke); height H = o h + (1 - o) H ('over') or H + o h build
    ('accumulate'), as core/canvas.py; opacity A = a + (1 - a) A (a stroke of
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
    if height_mode == "accumulate":
        hgt += o * profile * np.float32(build)
    else:
        hgt += o * (profile - hgt)
    op = canvas.opacity[rows, cols]
    op += a * (1.0 - op)
    if orientation is not None:
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        if len(pts) > 1:
            step = pts[1:] - pts[:-1]
            angles = np.mod(np.arctan2(step[:, 1], step[:, 0]), np.pi).astype(np.float32)
            top = a >= 0.5
            orientation[rows, cols][top] = angles[segment[top]]


def paint_line_stroke(canvas: Canvas, reference: np.ndarray, orientation: np.ndarray, anchor: tuple, size: int,
                      layer: int, params: Params) -> Stroke:
    """The Fig. 8c ablation: the paper's path, painted as one solid anti-aliased line of the anchor colour.

    The path is planned exactly as for the bristle brush (control points,
    Catmull-Rom curve, stopping rules) with the anchor colour as the brush
    colour; the kept curve, thinned to a point every max(1, size / 4) samples
    (about a quarter of the width apart) plus its end, is drawn by
    ``solid_stroke`` with radius size / 2 and opacity 1.
    """
    angle = float(orientation[anchor[1], anchor[0]])
    colour = reference[anchor[1], anchor[0]].astype(np.float32)
    control, anchor_index = trace_control_points(anchor, orientation, max(1.0, 0.5 * size), params.max_length)
    samples, control_index = catmull_rom(control)
    keep = keep_mask(samples, reference, canvas.colour, orientation, colour, angle, params.orientation_threshold)
    start_index = control_index[anchor_index]
    kept, kept_anchor = clip_path(samples, start_index, keep)
    every = max(1, int(size) // 4)
    line = kept[np.unique(np.append(np.arange(0, len(kept), every), len(kept) - 1))]
    solid_stroke(canvas, line, 0.5 * size, colour, 1.0, params.height_mode, params.height_build)

    first = start_index - kept_anchor
    inner = control_index[(control_index > first) & (control_index < first + len(kept) - 1)] - first
    path = kept[np.unique(np.concatenate(([0], inner, [len(kept) - 1])))].astype(np.float32)
    return Stroke(layer, (int(anchor[0]), int(anchor[1])), int(size), path, colour.copy())
