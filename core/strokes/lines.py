"""Solid strokes: Hertzmann 1998's renderer and the "lines" ablation (ALGORITHM §8).

A solid stroke is an anti-aliased, round-capped line of one colour along a
polyline, laid on the canvas directly (no brush, no bristles).
"""

from __future__ import annotations

import numpy as np

from .canvas import Canvas


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
        if canvas.snapshots is not None:
            canvas.snapshots.laid(canvas, 1)
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
    if canvas.snapshots is not None:
        canvas.snapshots.laid(canvas, 1, box=(rows, cols))
