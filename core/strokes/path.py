"""Curved stroke paths (ALGORITHM §5, "The path").

Points are float (x, y) pixel coordinates, x = column, y = row, pixel
centres at integers. Angles are radians from +x towards +y, axial where
they come from the orientation field.
"""

from __future__ import annotations

import math

import numpy as np


def axial_difference(a: np.ndarray, b: float) -> np.ndarray:
    """Smallest angle in [0, pi/2] between axial directions ``a`` (array) and ``b``."""
    d = np.mod(np.asarray(a, dtype=np.float64) - b, math.pi)
    return np.minimum(d, math.pi - d)


MAX_TURN_PER_STEP = math.radians(20.0)


def trace_control_points(anchor: tuple, orientation: np.ndarray, step: float, forward: int, backward: int,
                         max_turn: float = MAX_TURN_PER_STEP, margin: float = 0.0) -> tuple:
    """Control points from ``anchor`` following the orientation field both ways.

    anchor: (x, y) integer pixel. orientation: (H, W) axial angles. step:
    distance between control points in px (the brush radius). forward,
    backward: control points besides the anchor at most on each side; each
    side stops where it would go more than ``margin`` px past the canvas's
    border (a painter's stroke runs off the edge; the field is read at the
    nearest pixel on the canvas). At every point the field's
    axial direction is turned to agree with the previous step, so the path
    turns as little as it can (Hertzmann 1998), and each step turns at most
    ``max_turn`` radians from the one before: the path's radius of curvature
    stays above step / max_turn (about three brush radii at 20 degrees), so
    the inner side of a turning brush never folds back over itself and piles
    paint up.

    Returns (points (K, 2) float64 ordered backward end -> forward end,
    index of the anchor in them).
    """
    h, w = orientation.shape
    x0, y0 = float(anchor[0]), float(anchor[1])
    theta0 = float(orientation[int(y0), int(x0)])
    sides = []
    for sign, count in ((1.0, forward), (-1.0, backward)):
        dx, dy = sign * math.cos(theta0), sign * math.sin(theta0)
        x, y = x0, y0
        side = []
        for _ in range(count):
            theta = float(orientation[min(max(int(round(y)), 0), h - 1), min(max(int(round(x)), 0), w - 1)])
            cx, cy = math.cos(theta), math.sin(theta)
            if cx * dx + cy * dy < 0.0:
                cx, cy = -cx, -cy
            turn = math.atan2(dx * cy - dy * cx, dx * cx + dy * cy)
            if abs(turn) > max_turn:
                limited = math.copysign(max_turn, turn)
                cx = dx * math.cos(limited) - dy * math.sin(limited)
                cy = dx * math.sin(limited) + dy * math.cos(limited)
            nx, ny = x + step * cx, y + step * cy
            if not (-margin <= nx <= w - 1 + margin and -margin <= ny <= h - 1 + margin):
                break
            x, y, dx, dy = nx, ny, cx, cy
            side.append((x, y))
        sides.append(side)
    forward_points, backward_points = sides
    points = backward_points[::-1] + [(x0, y0)] + forward_points
    return np.array(points, dtype=np.float64), len(backward_points)


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


def catmull_rom(points: np.ndarray, spacing: float = 1.0) -> tuple:
    """Sample a uniform Catmull-Rom curve through ``points`` about every ``spacing`` px.

    points: (K, 2) float. Every segment gets the same number of samples,
    enough for its longest one (control points from trace_control_points are
    equally spaced). Returns (samples (N, 2) float64, index of each control
    point among the samples (K,) int). Every control point is a sample; a
    single point gives a single sample.
    """
    k = len(points)
    if k == 1:
        return points.copy(), np.zeros(1, dtype=np.int64)
    padded = np.concatenate(([2 * points[0] - points[1]], points, [2 * points[-1] - points[-2]]))
    step = points[1:] - points[:-1]
    longest = float(np.sqrt(np.max(step[:, 0] ** 2 + step[:, 1] ** 2)))
    n = max(1, int(math.ceil(longest / spacing)))
    windows = np.stack([padded[0:k - 1], padded[1:k], padded[2:k + 1], padded[3:k + 2]], axis=1)  # (K-1, 4, 2)
    samples = np.einsum("nj,kjd->knd", catmull_rom_basis(n), windows).reshape(-1, 2)   # no BLAS
    samples = np.concatenate((samples, points[-1:]))
    control_index = np.arange(k, dtype=np.int64) * n
    return samples, control_index


def tangent_angles(samples: np.ndarray, fallback: float) -> np.ndarray:
    """(N,) direction of travel (radians) at each of (N, 2) samples; ``fallback`` for a single point."""
    if len(samples) < 2:
        return np.full(len(samples), fallback, dtype=np.float64)
    d = np.empty_like(samples)
    d[1:-1] = samples[2:] - samples[:-2]
    d[0] = samples[1] - samples[0]
    d[-1] = samples[-1] - samples[-2]
    return np.arctan2(d[:, 1], d[:, 0])


def first_failure(ok: np.ndarray) -> int:
    """Index of the first False in boolean ``ok`` (len(ok) if none)."""
    bad = np.flatnonzero(~ok)
    return int(bad[0]) if bad.size else len(ok)


def clip_path(samples: np.ndarray, anchor_index: int, keep: np.ndarray) -> tuple:
    """Keep the run of samples around the anchor up to the first sample where ``keep`` is False.

    samples: (N, 2); keep: (N,) bool (its value at the anchor is ignored).
    Walks outward from the anchor both ways and drops each side from its
    first failing sample on. Returns (samples (M, 2), new anchor index).
    """
    forward = first_failure(keep[anchor_index + 1:])
    backward = first_failure(keep[:anchor_index][::-1])
    start, stop = anchor_index - backward, anchor_index + 1 + forward
    return samples[start:stop], anchor_index - start


def resample_by_length(points: np.ndarray, spacing: float = 1.0) -> tuple:
    """Points every ``spacing`` px of arc length along the polyline through (N, 2) ``points``.

    Returns (samples (M, 2) float64 starting at points[0], arc length of each
    (M,) float64 px); the last sample is the polyline's end when the length is
    not a whole multiple of ``spacing``. A single point (or a polyline of
    zero length) gives itself.
    """
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if len(pts) < 2:
        return pts.copy(), np.zeros(len(pts))
    seg = np.hypot(*np.diff(pts, axis=0).T)
    arc = np.concatenate(([0.0], np.cumsum(seg)))
    total = float(arc[-1])
    if total <= 0.0:
        return pts[:1].copy(), np.zeros(1)
    at = np.arange(0.0, total, spacing)
    if total - at[-1] > 1e-6:
        at = np.append(at, total)
    out = np.stack([np.interp(at, arc, pts[:, 0]), np.interp(at, arc, pts[:, 1])], axis=1)
    return out, at
