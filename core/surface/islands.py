"""A mesh's UV islands as a texture sees them: which island each texel shows, each island's texel density, and
paint bled past the islands' borders (ALGORITHM §10, islands and one stroke size in the world).

A mesh is given as T triangles, each with its three corners' UV coordinates
and 3-D positions, as a renderer's loop triangles give them. An island is a
connected set of triangles that share UV edges: two triangles share one when
an edge of each has the same two UV points, so a seam (an edge split in UV)
parts islands even where the triangles meet in 3-D. Texture texel (r, c) of
an N x N texture has its centre at u = (c + 0.5) / N, v = 1 - (r + 0.5) / N:
row 0 is the top of the image, as the painter's pictures are stored.
"""

from __future__ import annotations

from typing import NamedTuple, Optional

import numpy as np
from scipy import ndimage
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

NO_ISLAND = 0
"""The island map's value of a texel no triangle covers."""

RASTER_CHUNK = 1 << 22
"""Texels tested at once while triangles are rasterised: bounds the memory of ``island_map``."""


def uv_islands(uv: np.ndarray, cell: Optional[np.ndarray] = None) -> np.ndarray:
    """(T,) int32 in 1 .. K: the island of each of T triangles, ``uv`` (T, 3, 2) their corners' UV coordinates.

    Islands are the connected components of triangles sharing a UV edge (the same two UV points, in either order),
    numbered 1 .. K in the order of their first triangle. With ``cell`` (T,) int (the atlas cell of each triangle,
    ``atlas.Atlas.cell``), triangles of two cells share no edge, so an island never spans cells."""
    count = len(uv)
    if count == 0:
        return np.zeros(0, np.int32)
    corners = uv.reshape(-1, 2)
    if cell is not None:
        corners = np.concatenate([corners, np.repeat(np.asarray(cell, np.float64), 3)[:, None]], axis=1)
    _, point = np.unique(corners, axis=0, return_inverse=True)
    point = point.reshape(count, 3)
    edges = np.concatenate([point[:, [0, 1]], point[:, [1, 2]], point[:, [2, 0]]])
    edges = np.sort(edges, axis=1)
    owner = np.tile(np.arange(count), 3)
    _, edge = np.unique(edges, axis=0, return_inverse=True)
    edge = edge.reshape(-1)
    links = coo_matrix((np.ones(len(owner)), (owner, edge)), shape=(count, edge.max() + 1)).tocsr()
    _, component = connected_components(links @ links.T, directed=False)
    _, first = np.unique(component, return_index=True)
    numbering = np.empty(len(first), np.int32)
    numbering[np.argsort(np.argsort(first))] = np.arange(1, len(first) + 1)
    return numbering[component]


def island_map(uv: np.ndarray, islands: np.ndarray, size: int, limits: Optional[np.ndarray] = None) -> np.ndarray:
    """(size, size) int32: the island (``uv_islands``) of the triangle covering each texel's centre, NO_ISLAND
    where none does. uv: (T, 3, 2) corners. A centre on an edge shared by two triangles is covered; where
    triangles overlap in UV the later one's island is kept. ``limits`` (T, 2, 2) int: each triangle's texels kept
    within the box from texel (x, y) ``limits[t, 0]`` to ``limits[t, 1]`` inclusive (its atlas cell)."""
    out = np.full((size, size), NO_ISLAND, np.int32)
    corners = np.stack([uv[..., 0] * size - 0.5, (1.0 - uv[..., 1]) * size - 0.5], axis=-1)   # texel (x, y)
    low = np.clip(np.ceil(corners.min(axis=1) - 1e-9), 0, size - 1).astype(np.int64)
    high = np.clip(np.floor(corners.max(axis=1) + 1e-9), 0, size - 1).astype(np.int64)
    if limits is not None:
        low, high = np.maximum(low, limits[:, 0]), np.minimum(high, limits[:, 1])
    for triangle, x, y in box_texels(low, high, RASTER_CHUNK):
        inside = covers(corners[triangle], x.astype(np.float64), y.astype(np.float64))
        out[y[inside], x[inside]] = islands[triangle[inside]]      # later triangles written last: they win
    return out


def box_texels(low: np.ndarray, high: np.ndarray, chunk: int):
    """The texels of N boxes from ``low`` to ``high`` (N, 2) int64 texel (x, y), both inclusive (a box whose high is
    below its low holds none), in pieces of about ``chunk`` texels (a box is never split): yields (box (M,), x (M,),
    y (M,)) int64, the boxes in order and each box's texels row by row."""
    width, height = np.maximum(high[:, 0] - low[:, 0] + 1, 0), np.maximum(high[:, 1] - low[:, 1] + 1, 0)
    area = width * height
    start = 0
    while start < len(low):
        stop = start + max(1, int(np.searchsorted(np.cumsum(area[start:]), chunk)))
        picked = np.arange(start, min(stop, len(low)))
        counts = area[picked]
        box = np.repeat(picked, counts)
        offset = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
        yield (box, low[box, 0] + offset % np.maximum(width[box], 1),
               low[box, 1] + offset // np.maximum(width[box], 1))
        start = picked[-1] + 1


def covers(corners: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """(M,) bool: whether point (x, y) (M,) lies in triangle ``corners`` (M, 3, 2), edges included (a relative
    tolerance of 1e-9 of its area); a triangle of no area covers nothing."""
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
    twice_area = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    sign = np.sign(twice_area)
    tolerance = 1e-9 * np.abs(twice_area)
    inside = np.abs(twice_area) > 0
    for p, q in ((a, b), (b, c), (c, a)):
        side = (q[:, 0] - p[:, 0]) * (y - p[:, 1]) - (q[:, 1] - p[:, 1]) * (x - p[:, 0])
        inside &= side * sign >= -tolerance
    return inside


class TexelDensity(NamedTuple):
    """How large a texture's texels are on the surface, island by island."""

    island: np.ndarray          # (K,) float64 m per UV unit: sqrt(3-D area / UV area) of island k + 1
    face: np.ndarray            # (T,) float64 m per UV unit of each triangle (NaN for a triangle of no UV area)
    stray: np.ndarray           # (K,) float64: the largest |face / island - 1| over an island's triangles


def texel_density(uv: np.ndarray, position: np.ndarray, islands: np.ndarray) -> TexelDensity:
    """The density ρ of each island of ``islands`` (T,) 1 .. K, ``uv`` (T, 3, 2) and ``position`` (T, 3, 3) m the
    triangles' corners: one texel of an N-texel texture spans ρ / N metres of island k's surface."""
    first, second = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
    uv_area = 0.5 * np.abs(first[:, 0] * second[:, 1] - first[:, 1] * second[:, 0])
    world_area = 0.5 * np.linalg.norm(np.cross(position[:, 1] - position[:, 0], position[:, 2] - position[:, 0]),
                                      axis=1)
    count = int(islands.max(initial=0))
    summed_uv = np.bincount(islands, weights=uv_area, minlength=count + 1)[1:]
    summed_world = np.bincount(islands, weights=world_area, minlength=count + 1)[1:]
    with np.errstate(divide="ignore", invalid="ignore"):
        island = np.sqrt(summed_world / summed_uv)
        face = np.where(uv_area > 0, np.sqrt(world_area / uv_area), np.nan)
    ratio = np.abs(face / island[islands - 1] - 1.0)
    stray = np.zeros(count)
    np.maximum.at(stray, islands - 1, np.nan_to_num(ratio, nan=0.0))
    return TexelDensity(island, face, stray)


def bled(values: np.ndarray, islands: np.ndarray, texels: float) -> np.ndarray:
    """A copy of ``values`` (H, W, ...) whose texels outside every island (``islands`` (H, W) == NO_ISLAND) within
    ``texels`` of one take the values of the nearest island texel (by the exact Euclidean distance transform); the
    rest as they were."""
    outside = islands == NO_ISLAND
    if outside.all() or not outside.any():
        return values.copy()
    distance, (rows, cols) = ndimage.distance_transform_edt(outside, return_indices=True)
    near = outside & (distance <= texels)
    out = values.copy()
    out[near] = values[rows[near], cols[near]]
    return out


def bleed_texels(size: int) -> float:
    """Texels of bleed for a texture of ``size`` texels: 8 at 2048, in proportion, at least 2."""
    return max(2.0, 8.0 * size / 2048.0)
