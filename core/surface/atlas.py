"""Several source images of one mesh, UDIM tiles and several materials, as one square texture: the atlas
(ALGORITHM §10, objects of several textures).

A mesh's triangle is painted from source k (``SurfaceMesh.source``). A plain
source is one image over the UV square 0..1 and repeats beyond it (Blender's
REPEAT extension): a triangle lying in another unit square is moved back by
the whole-number part of its UV centroid. A tiled source (a path holding
``UDIM_TOKEN``, Blender's UDIM) is one image per unit square: the triangle's
tile is 1001 + floor(u) + 10 floor(v) of its UV centroid, for u in 0..10 and
v >= 0, and its UV within the tile is wrapped alike.

Each (source, tile) the mesh uses is a cell of the atlas, ordered by source
then tile (a plain source's tile is None). The atlas is a square grid of
G x G cells, G = ceil(sqrt(cells)), cell i at column i mod G and row i div G
(row 0 at the top, as the painter's pictures are stored), each cell an N x N
texture: the painted texture is (G N) x (G N). A triangle's atlas UV is its
wrapped UV scaled by 1 / G and moved to its cell. One cell, a plain source 0,
is the UV square itself: the atlas UV is the mesh's UV wherever it lies in
0..1.
"""

from __future__ import annotations

import math
from typing import Dict, List, NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np

from ..errors import InputError

UDIM_TOKEN = "<UDIM>"
"""The token of a tiled source's path that stands for the tile's number, as Blender writes it."""

FIRST_TILE = 1001
"""The UDIM number of the tile over UV 0..1 x 0..1; u steps by 1 up to 10 tiles, v by 10."""


class Cell(NamedTuple):
    """One (source, tile) of the atlas and where it lies in the grid."""

    source: int                 # the index of the source image (0 ..)
    tile: Optional[int]         # the UDIM tile (1001 ..) of a tiled source, None for a plain one
    column: int                 # 0 .. columns - 1, left to right
    row: int                    # 0 .. rows - 1, top to bottom


class Atlas(NamedTuple):
    """The cells a mesh's triangles are painted in and each triangle's place among them."""

    cells: Tuple[Cell, ...]     # ordered by source, then tile
    columns: int
    rows: int
    cell: np.ndarray            # (T,) int64: the cell 0 .. len(cells) - 1 of each triangle
    uv: np.ndarray              # (T, 3, 2) float64: the triangles' corners in the atlas square 0..1


def is_tiled(path) -> bool:
    """Whether the source ``path`` is a tiled (UDIM) image: its name holds ``UDIM_TOKEN``."""
    return UDIM_TOKEN in str(path)


def tile_path(path, tile: Optional[int]) -> str:
    """The file of ``tile`` of the source ``path`` (``UDIM_TOKEN`` replaced by its number); ``path`` for None."""
    return str(path) if tile is None else str(path).replace(UDIM_TOKEN, str(int(tile)))


def cell_file_suffix(cell: Cell) -> str:
    """The part of a cell's map names between the map and ".exr": ".s{source}" or ".s{source}.{tile}"."""
    return f".s{cell.source}" if cell.tile is None else f".s{cell.source}.{cell.tile}"


def wrapped(uv: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """((T, 3, 2) float64, (T, 2) int64): the triangles ``uv`` (T, 3, 2) moved by the whole-number part of their
    UV centroids, and that part (floor u, floor v)."""
    uv = np.asarray(uv, np.float64)
    shift = np.floor(uv.mean(axis=1)).astype(np.int64)
    if not shift.any():
        return uv, shift
    return uv - shift[:, None, :], shift


def triangle_tiles(shift: np.ndarray, source: np.ndarray, tiled: Sequence[bool]) -> np.ndarray:
    """(T,) int64: the UDIM tile of each triangle of a tiled source (its centroid's unit square ``shift`` (T, 2)),
    0 for one of a plain source; InputError in one sentence for a tiled triangle outside the tiles (u beyond
    0..10 or v below 0)."""
    tiled_of = np.asarray(tiled, bool)[source]
    tile = np.where(tiled_of, FIRST_TILE + shift[:, 0] + 10 * shift[:, 1], 0)
    wrong = tiled_of & ((shift[:, 0] < 0) | (shift[:, 0] > 9) | (shift[:, 1] < 0))
    if wrong.any():
        u, v = shift[int(np.flatnonzero(wrong)[0])]
        raise InputError(f"A face of the mesh lies in the UV square ({u}, {v}), which no UDIM tile holds: UDIM "
                         f"tiles lie at u 0..10 and v 0 and above.")
    return tile


def grid_side(count: int) -> int:
    """The side G of the square grid that holds ``count`` cells: ceil(sqrt(count)), at least 1."""
    return max(1, math.isqrt(max(count, 1) - 1) + 1)


def build_atlas(uv: np.ndarray, source: Optional[np.ndarray], tiled: Sequence[bool]) -> Atlas:
    """The atlas (module docstring) of triangles ``uv`` (T, 3, 2) painted from the sources ``source`` (T,) int
    (None: all 0), of which ``tiled[k]`` says whether source k is tiled."""
    source = np.zeros(len(uv), np.int64) if source is None else np.asarray(source, np.int64)
    moved, shift = wrapped(uv)
    tile = triangle_tiles(shift, source, tiled)
    keys, cell = np.unique(np.stack([source, tile], axis=1), axis=0, return_inverse=True)
    side = grid_side(len(keys))
    cells = tuple(Cell(int(k), None if not tiled[int(k)] else int(t), i % side, i // side)
                  for i, (k, t) in enumerate(keys))
    cell = cell.reshape(-1).astype(np.int64)
    return Atlas(cells, side, side, cell, placed_uv(moved, cell, cells, side, side))


def placed_uv(moved: np.ndarray, cell: np.ndarray, cells: Sequence[Cell], columns: int, rows: int) -> np.ndarray:
    """(T, 3, 2) float64: the wrapped triangles ``moved`` (T, 3, 2) (UV 0..1 of their cell) in the atlas square:
    scaled by 1 / columns, 1 / rows and moved to their ``cell`` (T,)'s place (row 0 at the top, v up)."""
    if columns == 1 and rows == 1:
        return moved
    where = np.array([[c.column, rows - 1 - c.row] for c in cells], np.float64)[cell]
    return (moved + where[:, None, :]) / np.array([columns, rows], np.float64)


def triangle_atlas_uv(mesh_uv: np.ndarray, source: Optional[np.ndarray], tiled: Optional[Sequence[bool]],
                      atlas: Union[Atlas, dict]) -> np.ndarray:
    """(T, 3, 2) float64: the atlas UV of triangles ``mesh_uv`` (T, 3, 2) painted from ``source`` (T,) int (None:
    all 0), ``tiled[k]`` whether source k is tiled (None: as the atlas's cells say, a source with a tile numbered
    being tiled), in the atlas ``atlas``: an ``Atlas`` or report.json's "atlas" ({"columns", "rows", "cells":
    [{"source", "tile", "column", "row"}, ...]}), as the Blender side reads it to write the atlas UV layer its
    Displace modifier uses. InputError in one sentence for a triangle whose (source, tile) the atlas has no cell
    of."""
    if isinstance(atlas, Atlas):
        cells, columns, rows = atlas.cells, atlas.columns, atlas.rows
    else:
        cells = tuple(Cell(int(c["source"]), None if c["tile"] is None else int(c["tile"]), int(c["column"]),
                           int(c["row"])) for c in atlas["cells"])
        columns, rows = int(atlas["columns"]), int(atlas["rows"])
    source = np.zeros(len(mesh_uv), np.int64) if source is None else np.asarray(source, np.int64)
    if tiled is None:
        tiled = [False] * (int(max([c.source for c in cells] + [int(source.max(initial=0))])) + 1)
        for c in cells:
            tiled[c.source] = tiled[c.source] or c.tile is not None
    moved, shift = wrapped(mesh_uv)
    tile = triangle_tiles(shift, source, tiled)
    index: Dict[Tuple[int, int], int] = {(c.source, 0 if c.tile is None else c.tile): i for i, c in enumerate(cells)}
    keys, inverse = np.unique(np.stack([source, tile], axis=1), axis=0, return_inverse=True)
    missing = [tuple(int(v) for v in key) for key in keys if (int(key[0]), int(key[1])) not in index]
    if missing:
        k, t = missing[0]
        raise InputError(f"The atlas has no cell of source {k}" + (f" tile {t}" if t else "") +
                         " that a face of the mesh is painted from.")
    cell = np.array([index[(int(k), int(t))] for k, t in keys], np.int64)[inverse.reshape(-1)]
    return placed_uv(moved, cell, cells, columns, rows)


def cell_box(atlas: Atlas, index: int, size: int) -> Tuple[slice, slice]:
    """The rows and columns of cell ``index``'s ``size`` x ``size`` texels in the atlas texture."""
    cell = atlas.cells[index]
    return slice(cell.row * size, (cell.row + 1) * size), slice(cell.column * size, (cell.column + 1) * size)


def composed(atlas: Atlas, pictures: List[np.ndarray], size: int, fill: Sequence[float]) -> np.ndarray:
    """(G size, G size, 3) float32: the atlas texture, cell i's texels the (size, size, 3) ``pictures[i]``, the
    texels of no cell ``fill`` (3,)."""
    out = np.empty((atlas.rows * size, atlas.columns * size, 3), np.float32)
    out[...] = np.asarray(fill, np.float32)
    for index, picture in enumerate(pictures):
        rows, cols = cell_box(atlas, index, size)
        out[rows, cols] = picture
    return out


def atlas_figures(atlas: Atlas, paths: Sequence, size: int, files: List[Dict[str, str]]) -> dict:
    """The report's "atlas": the grid, the texels of a cell's side, and each cell's source, file, tile, place and
    map files ``files[i]`` ({"color": name, "height": name, "opacity": name, ...})."""
    return {"columns": atlas.columns, "rows": atlas.rows, "tile_texels": int(size),
            "cells": [{"source": c.source, "path": tile_path(paths[c.source], c.tile), "tile": c.tile,
                       "column": c.column, "row": c.row, "files": files[i]} for i, c in enumerate(atlas.cells)]}
