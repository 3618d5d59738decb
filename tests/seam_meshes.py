"""Meshes whose sources run on across their UV seams, made in NumPy: a UV sphere (a meridian seam) and a cube of
six islands, each with a colour that is a smooth function of the 3-D position baked into its UV layout."""

from __future__ import annotations

import numpy as np

from core.surface.apron import texel_xy
from core.surface.islands import covers
from core.surface.mesh import SurfaceMesh


def uv_sphere(segments: int = 24, rings: int = 12, radius: float = 0.5) -> SurfaceMesh:
    """A UV sphere: ``segments`` around, ``rings`` from pole to pole, UV u = longitude over [0.02, 0.98] and v =
    latitude over [0.02, 0.98], so the meridian at longitude 0 is a seam (u 0.02 on one side, 0.98 on the other)."""
    def point(i, j):
        lon, lat = 2 * np.pi * (i % segments) / segments, np.pi * j / rings - np.pi / 2
        return (radius * np.array([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)]),
                np.array([0.02 + 0.96 * i / segments, 0.02 + 0.96 * j / rings]))
    uvs, positions = [], []
    for i in range(segments):
        for j in range(rings):
            corners = [point(i, j), point(i + 1, j), point(i + 1, j + 1), point(i, j + 1)]
            for triangle in ((0, 1, 2), (0, 2, 3)):
                picked = [corners[k] for k in triangle]
                if j == 0 and triangle == (0, 1, 2) or j == rings - 1 and triangle == (0, 2, 3):
                    continue                                      # the pole's triangle of no area
                positions.append([p for p, _ in picked])
                uvs.append([t for _, t in picked])
    return SurfaceMesh(np.array(uvs), np.array(positions))


def cube(half: float = 0.3, cells: int = 4) -> SurfaceMesh:
    """A cube of side 2 ``half`` m centred on the origin, each face ``cells`` x ``cells`` quads (two triangles
    each) and a UV island of its own: six squares of 0.3 UV in a 3 x 2 grid, each turned its own way."""
    faces = [(np.array([1, 0, 0]), np.array([0, 1, 0]), np.array([0, 0, 1])),
             (np.array([-1, 0, 0]), np.array([0, 0, 1]), np.array([0, 1, 0])),
             (np.array([0, 1, 0]), np.array([0, 0, 1]), np.array([1, 0, 0])),
             (np.array([0, -1, 0]), np.array([1, 0, 0]), np.array([0, 0, 1])),
             (np.array([0, 0, 1]), np.array([1, 0, 0]), np.array([0, 1, 0])),
             (np.array([0, 0, -1]), np.array([0, 1, 0]), np.array([1, 0, 0]))]
    uvs, positions = [], []
    for index, (normal, across, up) in enumerate(faces):
        origin = np.array([0.025 + 0.325 * (index % 3), 0.025 + 0.5 * (index // 3)])
        grid = np.linspace(-1, 1, cells + 1)
        for a in range(cells):
            for b in range(cells):
                quad = [(grid[a], grid[b]), (grid[a + 1], grid[b]), (grid[a + 1], grid[b + 1]),
                        (grid[a], grid[b + 1])]
                xyz = [half * (normal + s * across + t * up) for s, t in quad]
                uv = [origin + 0.15 * (np.array([s, t]) + 1) for s, t in quad]
                for triangle in ((0, 1, 2), (0, 2, 3)):
                    positions.append([xyz[k] for k in triangle])
                    uvs.append([uv[k] for k in triangle])
    return SurfaceMesh(np.array(uvs), np.array(positions))


def smooth_colour(points: np.ndarray) -> np.ndarray:
    """(M, 3) sRGB [0, 1]: a colour varying smoothly over 3-D ``points`` (M, 3) m, a few waves per metre."""
    x, y, z = points[:, 0], points[:, 1], points[:, 2]
    return np.clip(np.stack([0.5 + 0.35 * np.sin(9 * x + 4 * y), 0.5 + 0.35 * np.sin(7 * y - 5 * z + 1),
                             0.5 + 0.35 * np.cos(8 * z + 3 * x)], axis=1), 0, 1)


def baked(mesh: SurfaceMesh, size: int, colour=smooth_colour) -> np.ndarray:
    """(size, size, 3) float32: ``colour`` of the surface point each texel's centre shows (the triangle covering
    it, by its barycentric coordinates), the colour of the nearest such texel elsewhere."""
    out = np.zeros((size, size, 3), np.float32)
    hit = np.zeros((size, size), bool)
    corners = texel_xy(mesh.uv, size)
    for corner, position in zip(corners, mesh.position, strict=True):
        low = np.clip(np.floor(corner.min(axis=0)), 0, size - 1).astype(int)
        high = np.clip(np.ceil(corner.max(axis=0)), 0, size - 1).astype(int)
        ys, xs = np.mgrid[low[1]:high[1] + 1, low[0]:high[0] + 1]
        x, y = xs.ravel().astype(float), ys.ravel().astype(float)
        inside = covers(np.repeat(corner[None], len(x), axis=0), x, y)
        x, y = x[inside], y[inside]
        a, b, c = corner
        det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
        wb = ((x - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (y - a[1])) / det
        wc = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / det
        points = (1 - wb - wc)[:, None] * position[0] + wb[:, None] * position[1] + wc[:, None] * position[2]
        out[y.astype(int), x.astype(int)] = colour(points)
        hit[y.astype(int), x.astype(int)] = True
    from scipy import ndimage
    _, (rows, cols) = ndimage.distance_transform_edt(~hit, return_indices=True)
    return out[rows, cols]
