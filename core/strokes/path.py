"""Curved stroke paths for many strokes at once (ALGORITHM §5, "The path").

Points are float (x, y) pixel coordinates, x = column, y = row, pixel
centres at integers. Angles are radians from +x towards +y, axial where
they come from the orientation field. A round's strokes are traced
together: control points and curve samples as (strokes x points) arrays,
stamps as one flat array with every stroke's run marked by ``starts``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np


def axial_difference(a: np.ndarray, b) -> np.ndarray:
    """Smallest angle in [0, pi/2] between axial directions ``a`` and ``b`` (broadcasting arrays)."""
    d = np.mod(np.asarray(a, dtype=np.float64) - b, math.pi)
    return np.minimum(d, math.pi - d)


MAX_TURN_PER_STEP = math.radians(20.0)


def nearest_pixels(shape: tuple, x: np.ndarray, y: np.ndarray) -> tuple:
    """(rows, columns) int arrays of the pixels nearest float positions x, y, clamped to an (H, W) canvas."""
    h, w = shape[:2]
    ix = np.minimum(np.maximum(np.floor(x + 0.5), 0), w - 1).astype(np.intp)
    iy = np.minimum(np.maximum(np.floor(y + 0.5), 0), h - 1).astype(np.intp)
    return iy, ix


class ControlPoints(NamedTuple):
    """Control points of N strokes, K = backward + 1 + forward each, ordered backward end -> forward end."""

    points: np.ndarray          # float64 (N, K, 2) (x, y) px, the anchor at index ``backward``
    counts: np.ndarray          # int64 (N, 2) the control points traced forward and backward


def trace_control_points(anchors: np.ndarray, orientation: np.ndarray, step: float, forward: int, backward: int,
                         max_turn: float = MAX_TURN_PER_STEP, margin: float = 0.0) -> ControlPoints:
    """Control points of N strokes from their ``anchors`` following the orientation field both ways.

    anchors: (N, 2) int (x, y) pixels. orientation: (H, W) axial angles.
    step: distance between control points (px, the brush radius). forward,
    backward: control points besides the anchor at most on each side; a side
    stops where it would go more than ``margin`` px past the canvas's border
    (a painter's stroke runs off the edge; the field is read at the nearest
    pixel on the canvas). At every point the field's axial direction is
    turned to agree with the previous step, so the path turns as little as it
    can (Hertzmann 1998), and each step turns at most ``max_turn`` radians
    from the one before: the path's radius of curvature stays above
    step / max_turn, so the inner side of a turning brush never folds back
    over itself and piles paint up.

    Returns (points (N, backward + 1 + forward, 2) float64 ordered backward
    end -> forward end, the anchor at index ``backward``; counts (N, 2) int,
    the control points traced forward and backward). Beyond a side's last
    traced point the array goes on straight, one step at a time, so a
    Catmull-Rom curve through the array ends with the usual mirrored end
    tangent inside the traced part.
    """
    anchors = np.asarray(anchors, np.int64).reshape(-1, 2)
    h, w = orientation.shape
    n = len(anchors)
    x0, y0 = anchors[:, 0].astype(np.float64), anchors[:, 1].astype(np.float64)
    theta0 = orientation[anchors[:, 1], anchors[:, 0]].astype(np.float64)
    points = np.empty((n, backward + 1 + forward, 2), np.float64)
    points[:, backward, 0], points[:, backward, 1] = x0, y0
    counts = np.zeros((n, 2), np.int64)
    for side, (sign, count) in enumerate(((1.0, forward), (-1.0, backward))):
        dx, dy = sign * np.cos(theta0), sign * np.sin(theta0)
        x, y = x0.copy(), y0.copy()
        alive = np.ones(n, bool)
        for i in range(count):
            iy, ix = nearest_pixels((h, w), x, y)
            theta = orientation[iy, ix].astype(np.float64)
            cx, cy = np.cos(theta), np.sin(theta)
            flip = cx * dx + cy * dy < 0.0
            cx, cy = np.where(flip, -cx, cx), np.where(flip, -cy, cy)
            turn = np.arctan2(dx * cy - dy * cx, dx * cx + dy * cy)
            over = np.abs(turn) > max_turn
            if over.any():
                limited = np.clip(turn, -max_turn, max_turn)
                cl, sl = np.cos(limited), np.sin(limited)
                cx, cy = np.where(over, dx * cl - dy * sl, cx), np.where(over, dx * sl + dy * cl, cy)
            nx, ny = x + step * cx, y + step * cy
            alive &= (nx >= -margin) & (nx <= w - 1 + margin) & (ny >= -margin) & (ny <= h - 1 + margin)
            x, y = np.where(alive, nx, x + step * dx), np.where(alive, ny, y + step * dy)
            dx, dy = np.where(alive, cx, dx), np.where(alive, cy, dy)
            counts[:, side] += alive
            at = backward + 1 + i if sign > 0 else backward - 1 - i
            points[:, at, 0], points[:, at, 1] = x, y
    return ControlPoints(points, counts)


_BASIS_CACHE: dict = {}


def catmull_rom_basis(n: int) -> np.ndarray:
    """(n, 4) uniform Catmull-Rom weights of P0..P3 at t = 0, 1/n, ..., (n-1)/n."""
    basis = _BASIS_CACHE.get(n)
    if basis is None:
        t = np.arange(n, dtype=np.float64)[:, None] / n
        t2, t3 = t * t, t * t * t
        basis = 0.5 * np.hstack([-t + 2 * t2 - t3, 2 - 5 * t2 + 3 * t3, t + 4 * t2 - 3 * t3, -t2 + t3])
        _BASIS_CACHE[n] = basis
    return basis


def catmull_rom(points: np.ndarray, per_segment: int) -> np.ndarray:
    """Samples of uniform Catmull-Rom curves through N rows of K control points.

    points: (N, K, 2) float64; per_segment: samples per segment (>= 1).
    Returns (N, (K - 1) per_segment + 1, 2) float64; control point k is
    sample k per_segment. The curve's end tangents mirror the neighbouring
    point (a point 2 P_0 - P_1 before the first, likewise after the last).
    """
    n, k = points.shape[:2]
    if k == 1:
        return points.copy()
    padded = np.concatenate((2 * points[:, :1] - points[:, 1:2], points, 2 * points[:, -1:] - points[:, -2:-1]),
                            axis=1)
    basis = catmull_rom_basis(per_segment)[None, None, :, :, None]                        # (1, 1, T, 4, 1)
    samples = np.empty((n, k - 1, per_segment, 2))
    np.multiply(basis[..., 0, :], padded[:, 0:k - 1, None, :], out=samples)
    for j in range(1, 4):                                                 # P0 .. P3 summed in order, no BLAS
        samples += basis[..., j, :] * padded[:, j:k - 1 + j, None, :]
    return np.concatenate((samples.reshape(n, -1, 2), points[:, -1:]), axis=1)


class Resampled(NamedTuple):
    """M stamps along N curves; curve i's stamps are [starts[i], starts[i + 1])."""

    stamps: np.ndarray          # float64 (M, 2) (x, y) px
    arc: np.ndarray             # float64 (M,) px from the curve's start
    starts: np.ndarray          # int64 (N + 1,)


def resample_by_length(samples: np.ndarray, first: np.ndarray, last: np.ndarray,
                       spacing: float = 1.0) -> Resampled:
    """Stamps every ``spacing`` px of arc length along the kept part of each of N sampled curves.

    samples: (N, S, 2) float64; stroke i keeps samples first[i] .. last[i]
    (inclusive). A stroke of length L gets stamps at arc lengths 0, spacing,
    ... below L and one at L itself (unless the one before is within 1e-6
    px); a stroke of length 0 is one stamp. Returns (stamps (M, 2) float64,
    arc (M,) float64 px from the stroke's start, starts (N + 1,) int: stroke
    i's stamps are [starts[i], starts[i + 1])).
    """
    n, s = samples.shape[:2]
    rows = np.arange(n)
    step = np.diff(samples, axis=1)
    seg = np.hypot(step[..., 0], step[..., 1])
    index = np.arange(s - 1)
    seg[(index[None, :] < first[:, None]) | (index[None, :] >= last[:, None])] = 0.0
    arc = np.zeros((n, s), np.float64)
    np.cumsum(seg, axis=1, out=arc[:, 1:])
    total = arc[rows, last]
    whole = np.ceil(total / spacing).astype(np.int64)
    tail = (total > 0) & (total - (whole - 1) * spacing > 1e-6)
    count = np.where(total > 0, whole + tail, 1)
    starts = np.zeros(n + 1, np.int64)
    np.cumsum(count, out=starts[1:])
    owner = np.repeat(rows, count)
    local = np.arange(starts[-1]) - starts[owner]
    t = np.where(local >= whole[owner], total[owner], local * spacing)
    # the sample segment [j, j + 1] holding each stamp: the last j in [first, last - 1] with arc[j] <= t
    lo = first[owner].copy()
    hi = np.maximum(last[owner] - 1, lo)
    for _ in range(max(1, int(s).bit_length())):
        mid = (lo + hi + 1) // 2
        below = arc[owner, mid] <= t
        lo = np.where(below, mid, lo)
        hi = np.where(below, hi, mid - 1)
    nxt = np.minimum(lo + 1, last[owner])
    length = arc[owner, nxt] - arc[owner, lo]
    frac = np.clip(np.divide(t - arc[owner, lo], length, out=np.zeros_like(t), where=length > 0), 0.0, 1.0)
    a, b = samples[owner, lo], samples[owner, nxt]
    stamps = a + frac[:, None] * (b - a)
    return Resampled(stamps, t, starts)


def tangent_angles(points: np.ndarray, starts: np.ndarray, fallback: np.ndarray) -> np.ndarray:
    """(M,) direction of travel (radians) at stamps (M, 2) of N strokes laid out by ``starts`` (N + 1,).

    Central differences inside a stroke, one-sided at its ends; a stroke of
    one stamp takes its ``fallback`` (N,) angle.
    """
    m = len(points)
    d = np.zeros_like(points)
    if m > 2:
        d[1:-1] = points[2:] - points[:-2]
    first, last = starts[:-1], starts[1:] - 1
    long = last > first
    f, e = first[long], last[long]
    d[f] = points[f + 1] - points[f]
    d[e] = points[e] - points[e - 1]
    angles = np.arctan2(d[:, 1], d[:, 0])
    single = ~long
    angles[first[single]] = np.asarray(fallback, np.float64)[single]
    return angles


def polygon_lengths(control: np.ndarray, count: np.ndarray) -> np.ndarray:
    """(N,) float64 px: the length of each of N control polygons, ``control`` (N, P, 2) NaN-padded past
    ``count`` (N,) points (0 for a stroke of one control point)."""
    if control.shape[1] < 2:
        return np.zeros(len(control))
    steps = np.hypot(*np.moveaxis(np.diff(control, axis=1), 2, 0))
    return np.nansum(np.where(np.arange(1, control.shape[1])[None, :] < count[:, None], steps, 0.0), axis=1)
