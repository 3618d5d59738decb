"""A polygon of a mesh cut into triangles that stay inside it: a fan where it is convex, ears clipped where not.

A concave n-gon cut as a fan from its first corner gives triangles that
reach past its notch, so paint would land on texels no face covers. Its
corners are projected onto the plane of the polygon (Newell's normal) and
ears are clipped, each the first corner, in order, whose triangle with its
neighbours turns the polygon's way and holds no other corner; a convex
polygon gets the fan, which is what ear clipping from its second corner
gives too.
"""

from __future__ import annotations

from typing import List, Tuple

import numpy as np


def polygon_plane(points: np.ndarray) -> np.ndarray:
    """(n, 2) float64: the (n, 3) ``points`` of a polygon in a 2-D frame of its plane (Newell's normal), turning
    counter-clockwise; its own coordinates when the polygon has no area."""
    shifted = np.roll(points, -1, axis=0)
    normal = np.array([np.sum((points[:, 1] - shifted[:, 1]) * (points[:, 2] + shifted[:, 2])),
                       np.sum((points[:, 2] - shifted[:, 2]) * (points[:, 0] + shifted[:, 0])),
                       np.sum((points[:, 0] - shifted[:, 0]) * (points[:, 1] + shifted[:, 1]))])
    length = np.linalg.norm(normal)
    if length == 0.0:
        return points[:, :2].astype(np.float64)
    normal /= length
    helper = np.eye(3)[int(np.argmin(np.abs(normal)))]
    first = np.cross(normal, helper)
    first /= np.linalg.norm(first)
    return np.stack([points @ first, points @ np.cross(normal, first)], axis=1)


def cross(o: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    """The z of (a - o) x (b - o) for 2-D points: > 0 when o, a, b turn counter-clockwise."""
    return float((a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]))


def triangles(points: np.ndarray) -> List[Tuple[int, int, int]]:
    """The corners (indices into ``points`` (n, 3), n >= 3) of the triangles a polygon is cut into (module
    docstring); n - 2 of them, in the polygon's own turning."""
    n = len(points)
    fan = [(0, k, k + 1) for k in range(1, n - 1)]
    if n == 3:
        return fan
    flat = polygon_plane(np.asarray(points, np.float64))
    turns = [cross(flat[k - 1], flat[k], flat[(k + 1) % n]) for k in range(n)]
    if min(turns) >= 0.0:
        return fan
    left = list(range(n))
    cut: List[Tuple[int, int, int]] = []
    while len(left) > 3:
        for position in range(len(left)):
            a, b, c = left[position - 1], left[position], left[(position + 1) % len(left)]
            if is_ear(flat, a, b, c, left):
                cut.append((a, b, c))
                left.pop(position)
                break
        else:                                   # no ear (self-crossing or degenerate corners): the fan of the rest
            cut.extend((left[0], left[k], left[k + 1]) for k in range(1, len(left) - 1))
            return cut
    cut.append((left[0], left[1], left[2]))
    return cut


def is_ear(flat: np.ndarray, a: int, b: int, c: int, left: List[int]) -> bool:
    """Whether corner ``b`` between ``a`` and ``c`` of the (n, 2) counter-clockwise ``flat`` polygon is an ear:
    the triangle turns counter-clockwise and no other corner still ``left`` lies in it or on its border."""
    if cross(flat[a], flat[b], flat[c]) <= 0.0:
        return False
    for k in left:
        if k in (a, b, c):
            continue
        p = flat[k]
        if cross(flat[a], flat[b], p) >= 0.0 and cross(flat[b], flat[c], p) >= 0.0 and cross(flat[c], flat[a], p) >= 0.0:
            return False
    return True
