"""Several source images of one mesh, UDIM tiles and several materials, as one square texture: the atlas
(ALGORITHM §10, objects of several textures).

A mesh's triangle is painted from source k (``SurfaceMesh.source``). A plain
source is one image over the UV square 0..1; beyond it the source's
extension rule (``EXTENSIONS``, the ``extension`` of Blender's Image Texture
node) says what a renderer shows, and so where the triangle is painted:

- REPEAT (the default): the image repeats; a triangle lying in another unit
  square is moved back by the whole-number part of its UV centroid.
- MIRROR: the image repeats mirrored, every other unit square flipped; a
  triangle is moved back as under REPEAT and, in a square of odd floor u
  (floor v), mirrored in u (v) within it: u - s becomes 1 - (u - s).
- CLIP: nothing is shown outside the square 0..1, so a triangle stays where
  it lies: only its part inside 0..1 is painted, and one wholly outside
  covers no texel.
- EXTEND: the renderer clamps the UV into 0..1, so the parts outside show
  the border texels stretched; painting them would only smear strokes along
  the border, so they are left as under CLIP: only the part of a triangle
  inside 0..1 is painted.

A tiled source (a path holding
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

from ..errors import InputError, ParameterError

UDIM_TOKEN = "<UDIM>"
"""The token of a tiled source's path that stands for the tile's number, as Blender writes it."""

FIRST_TILE = 1001
"""The UDIM number of the tile over UV 0..1 x 0..1; u steps by 1 up to 10 tiles, v by 10."""

REPEAT, EXTEND, CLIP, MIRROR = "REPEAT", "EXTEND", "CLIP", "MIRROR"
EXTENSIONS = (REPEAT, EXTEND, CLIP, MIRROR)
"""A plain source's rules beyond the UV square 0..1, named as Blender's Image Texture node names its
``extension`` (module docstring)."""


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
    extensions: Tuple[str, ...] = ()    # one per source: its rule beyond 0..1 (``EXTENSIONS``); () all REPEAT
    repeats: Optional[np.ndarray] = None    # (T,) int8: 1 where a triangle's image repeats past its cell (REPEAT of
    #                                         a plain source), 2 mirrored (MIRROR), 0 where it does not; None: all 0


def is_tiled(path) -> bool:
    """Whether the source ``path`` is a tiled (UDIM) image: its name holds ``UDIM_TOKEN``."""
    return UDIM_TOKEN in str(path)


def tile_path(path, tile: Optional[int]) -> str:
    """The file of ``tile`` of the source ``path`` (``UDIM_TOKEN`` replaced by its number); ``path`` for None."""
    return str(path) if tile is None else str(path).replace(UDIM_TOKEN, str(int(tile)))


def cell_file_suffix(cell: Cell) -> str:
    """The part of a cell's map names between the map and ".exr": ".s{source}" or ".s{source}.{tile}"."""
    return f".s{cell.source}" if cell.tile is None else f".s{cell.source}.{cell.tile}"


def checked_extensions(extensions: Optional[Sequence[str]], count: int) -> Tuple[str, ...]:
    """The rules (``EXTENSIONS``, upper case) of ``count`` sources from ``extensions`` (None: all REPEAT; one rule
    stands for every source); ParameterError in one sentence for an unknown rule or a list of another length."""
    if extensions is None:
        return (REPEAT,) * count
    if isinstance(extensions, str):
        extensions = [extensions] * count
    rules = tuple(str(rule).upper() for rule in extensions)
    unknown = [rule for rule in rules if rule not in EXTENSIONS]
    if unknown:
        raise ParameterError(f"A texture's extension must be one of {', '.join(EXTENSIONS)}, got {unknown[0]!r}.")
    if len(rules) == 1 and count > 1:
        rules = rules * count
    if len(rules) != count:
        raise ParameterError(f"Give one extension for each of the {count} texture{'s' if count != 1 else ''} or "
                             f"one for all, got {len(rules)}.")
    return rules


def wrapped(uv: np.ndarray, rule: Optional[np.ndarray] = None) -> Tuple[np.ndarray, np.ndarray]:
    """((T, 3, 2) float64, (T, 2) int64): the triangles ``uv`` (T, 3, 2) moved into the unit square where their
    source's image shows them, and the whole-number part (floor u, floor v) of their UV centroids. ``rule`` (T,)
    of ``EXTENSIONS`` (None: all REPEAT): REPEAT moves a triangle back by that part, MIRROR too and mirrors it
    within the square where that part is odd, CLIP and EXTEND leave it where it lies (module docstring)."""
    uv = np.asarray(uv, np.float64)
    shift = np.floor(uv.mean(axis=1)).astype(np.int64)
    if rule is None:
        if not shift.any():
            return uv, shift
        return uv - shift[:, None, :], shift
    rule = np.asarray(rule)
    kept = (rule == CLIP) | (rule == EXTEND)
    moved = uv - np.where(kept[:, None], 0, shift)[:, None, :]
    flip = (rule == MIRROR)[:, None] & (shift % 2 == 1)             # (T, 2): mirrored in u, in v
    moved = np.where(flip[:, None, :], 1.0 - moved, moved)
    return moved, shift


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


def triangle_rules(source: np.ndarray, tiled: Sequence[bool], extensions: Optional[Sequence[str]]):
    """(T,) str or None: the rule (``EXTENSIONS``) each triangle of ``source`` (T,) is wrapped by: its source's
    ``extensions[k]``, REPEAT for a tiled source (its tiles are wrapped alike); None when every rule is REPEAT."""
    if extensions is None or all(rule == REPEAT for rule in extensions):
        return None
    rules = np.array([REPEAT if tiled[k] else extensions[k] for k in range(len(extensions))])
    return rules[source]


def build_atlas(uv: np.ndarray, source: Optional[np.ndarray], tiled: Sequence[bool],
                extensions: Optional[Sequence[str]] = None) -> Atlas:
    """The atlas (module docstring) of triangles ``uv`` (T, 3, 2) painted from the sources ``source`` (T,) int
    (None: all 0), of which ``tiled[k]`` says whether source k is tiled and ``extensions[k]`` (``EXTENSIONS``;
    None: all REPEAT) what its image shows beyond the UV square 0..1."""
    source = np.zeros(len(uv), np.int64) if source is None else np.asarray(source, np.int64)
    extensions = checked_extensions(extensions, len(tiled))
    moved, shift = wrapped(uv, triangle_rules(source, tiled, extensions))
    tile = triangle_tiles(shift, source, tiled)
    keys, cell = np.unique(np.stack([source, tile], axis=1), axis=0, return_inverse=True)
    side = grid_side(len(keys))
    cells = tuple(Cell(int(k), None if not tiled[int(k)] else int(t), i % side, i // side)
                  for i, (k, t) in enumerate(keys))
    cell = cell.reshape(-1).astype(np.int64)
    repeats = np.array([0 if tiled[k] else {REPEAT: 1, MIRROR: 2}.get(extensions[k], 0)
                        for k in range(len(tiled))], np.int8)[source]
    return Atlas(cells, side, side, cell, placed_uv(moved, cell, cells, side, side), extensions, repeats)


MOST_REPEATS = 3
"""The unit squares a side a triangle may reach over and still be painted in each (``repeated_parts``): one that
reaches over more (a face spanning many repeats of a tiling image) is painted in its centroid's square alone."""


def repeated_parts(atlas: Atlas) -> Tuple[np.ndarray, np.ndarray]:
    """(triangle (C,) int64, uv (C, 3, 2) float64): the parts of the atlas's triangles that reach past their unit
    square under a repeating image, each as a copy of its triangle placed where the image shows it in the cell.

    A triangle of a plain REPEAT source that crosses its square's border (its centroid's, the cell) shows its
    part in the unit square (i, j) beside it from the image moved by (i, j): the copy is the triangle moved back
    by (i, j), and its texels within the cell are that part's. Under MIRROR the part in square i shows the image
    mirrored where i is odd: u becomes i + 1 - u (alike in v). The copies are rasterised with their triangle's
    island, within its cell, so each texel of the cell shows the surface Blender shows there. A triangle reaching
    over more than ``MOST_REPEATS`` squares a side, a tiled source's and a CLIP or EXTEND source's have none."""
    none = np.zeros(0, np.int64), np.zeros((0, 3, 2), np.float64)
    if atlas.repeats is None or not atlas.repeats.any():
        return none
    scale = np.array([atlas.columns, atlas.rows], np.float64)
    where = np.array([[c.column, atlas.rows - 1 - c.row] for c in atlas.cells], np.float64)[atlas.cell]
    local = atlas.uv * scale - where[:, None, :]                    # the cell's square 0..1
    low = np.floor(local.min(axis=1) + 1e-9).astype(np.int64)
    high = np.ceil(local.max(axis=1) - 1e-9).astype(np.int64) - 1
    span = high - low + 1
    crossing = np.flatnonzero((atlas.repeats > 0) & (span > 1).any(axis=1) & (span <= MOST_REPEATS).all(axis=1))
    triangles, parts = [], []
    mirror = atlas.repeats[crossing] == 2
    for step_u in range(MOST_REPEATS):
        for step_v in range(MOST_REPEATS):
            square = low[crossing] + [step_u, step_v]                       # (C, 2) the unit square (i, j)
            picked = (square <= high[crossing]).all(axis=1) & (square != 0).any(axis=1)
            odd = mirror[:, None] & (square % 2 == 1)
            here, square, odd = crossing[picked], square[picked].astype(np.float64), odd[picked]
            part = np.where(odd[:, None, :], square[:, None, :] + 1.0 - local[here], local[here] - square[:, None, :])
            triangles.append(here)
            parts.append((part + where[here][:, None, :]) / scale)
    triangles, parts = np.concatenate(triangles), np.concatenate(parts)
    order = np.argsort(triangles, kind="stable")
    return triangles[order].astype(np.int64), parts[order]


def placed_uv(moved: np.ndarray, cell: np.ndarray, cells: Sequence[Cell], columns: int, rows: int) -> np.ndarray:
    """(T, 3, 2) float64: the wrapped triangles ``moved`` (T, 3, 2) (UV 0..1 of their cell) in the atlas square:
    scaled by 1 / columns, 1 / rows and moved to their ``cell`` (T,)'s place (row 0 at the top, v up)."""
    if columns == 1 and rows == 1:
        return moved
    where = np.array([[c.column, rows - 1 - c.row] for c in cells], np.float64)[cell]
    return (moved + where[:, None, :]) / np.array([columns, rows], np.float64)


def triangle_atlas_uv(mesh_uv: np.ndarray, source: Optional[np.ndarray], tiled: Optional[Sequence[bool]],
                      atlas: Union[Atlas, dict], extensions: Optional[Sequence[str]] = None) -> np.ndarray:
    """(T, 3, 2) float64: the atlas UV of triangles ``mesh_uv`` (T, 3, 2) painted from ``source`` (T,) int (None:
    all 0), ``tiled[k]`` whether source k is tiled (None: as the atlas's cells say, a source with a tile numbered
    being tiled), in the atlas ``atlas``: an ``Atlas`` or report.json's "atlas" ({"columns", "rows", "cells":
    [{"source", "tile", "column", "row", "extension"}, ...]}), as the Blender side reads it to write the atlas UV
    layer its Displace modifier uses. ``extensions[k]``: source k's rule beyond 0..1 (None: as the atlas says, a
    cell without "extension" REPEAT). InputError in one sentence for a triangle whose (source, tile) the atlas
    has no cell of."""
    if isinstance(atlas, Atlas):
        cells, columns, rows = atlas.cells, atlas.columns, atlas.rows
        named = dict(enumerate(atlas.extensions))
    else:
        cells = tuple(Cell(int(c["source"]), None if c["tile"] is None else int(c["tile"]), int(c["column"]),
                           int(c["row"])) for c in atlas["cells"])
        columns, rows = int(atlas["columns"]), int(atlas["rows"])
        named = {int(c["source"]): str(c.get("extension", REPEAT)) for c in atlas["cells"]}
    source = np.zeros(len(mesh_uv), np.int64) if source is None else np.asarray(source, np.int64)
    if tiled is None:
        tiled = [False] * (int(max([c.source for c in cells] + [int(source.max(initial=0))])) + 1)
        for c in cells:
            tiled[c.source] = tiled[c.source] or c.tile is not None
    if extensions is None:
        extensions = [named.get(k, REPEAT) for k in range(len(tiled))]
    extensions = checked_extensions(extensions, len(tiled))
    moved, shift = wrapped(mesh_uv, triangle_rules(source, tiled, extensions))
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
    """The report's "atlas": the grid, the texels of a cell's side, and each cell's source, file, tile, place, rule
    beyond the UV square 0..1 ("extension", ``EXTENSIONS``: REPEAT for a tile) and map files ``files[i]``
    ({"color": name, "height": name, "opacity": name, ...})."""
    rules = atlas.extensions or (REPEAT,) * (max(c.source for c in atlas.cells) + 1)
    return {"columns": atlas.columns, "rows": atlas.rows, "tile_texels": int(size),
            "cells": [{"source": c.source, "path": tile_path(paths[c.source], c.tile), "tile": c.tile,
                       "column": c.column, "row": c.row,
                       "extension": REPEAT if c.tile is not None else rules[c.source], "files": files[i]}
                      for i, c in enumerate(atlas.cells)]}
