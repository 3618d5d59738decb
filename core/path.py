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


def trace_control_points(anchor: tuple, orientation: np.ndarray, step: float, max_points: int) -> tuple:
    """Control points from ``anchor`` following the orientation field both ways.

    anchor: (x, y) integer pixel. orientation: (H, W) axial angles. step:
    distance between control points in px (about the brush radius).
    max_points: control points besides the anchor at most, split between the
    forward (first half, rounded up) and backward directions; each side stops
    where it would leave the canvas. At every point the field's axial
    direction is turned to agree with the previous step (Hertzmann 1998).

    Returns (points (K, 2) float64 ordered backward end -> forward end,
    index of the anchor in them).
    """
    h, w = orientation.shape
    x0, y0 = float(anchor[0]), float(anchor[1])
    theta0 = float(orientation[int(y0), int(x0)])
    forward_count = (max_points + 1) // 2
    sides = []
    for sign, count in ((1.0, forward_count), (-1.0, max_points - forward_count)):
        dx, dy = sign * math.cos(theta0), sign * math.sin(theta0)
        x, y = x0, y0
        side = []
        for _ in range(count):
            theta = float(orientation[int(round(y)), int(round(x))])
            cx, cy = math.cos(theta), math.sin(theta)
            if cx * dx + cy * dy < 0.0:
                cx, cy = -cx, -cy
            nx, ny = x + step * cx, y + step * cy
            if not (0.0 <= nx <= w - 1 and 0.0 <= ny <= h - 1):
                break
            x, y, dx, dy = nx, ny, cx, cy
            side.append((x, y))
        sides.append(side)
    forward, backward = sides
    points = backward[::-1] + [(x0, y0)] + forward
    return np.array(points, dtype=np.float64), len(backward)


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
    samples = np.matmul(catmull_rom_basis(n)[None], windows).reshape(-1, 2)
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
