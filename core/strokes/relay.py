"""A canvas laid again only where its strokes changed: the same bytes as laying every stroke anew (ALGORITHM §9).

A pixel's paint is its strokes' contributions composited in laying order,
and nothing else (``Canvas.lay``). A canvas that some list of strokes was
laid on therefore already holds, at every pixel no changed stroke reaches,
what laying the changed list gives there. ``relaid`` cuts the canvas into
square tiles, marks the tiles that the changed strokes' boxes
(``segment_boxes``) touch, makes the marked tiles blank and lays on them,
and on them only (``Canvas.only``), every stroke of the new list that
reaches one. When most tiles are marked it lays the new list anew
(``tuning.RELAY_MOST_MARKED``).
"""

from __future__ import annotations

from typing import Dict, Tuple

import numpy as np

from .. import tuning
from ..params import Params
from .brush import BrushTip
from .canvas import Canvas
from .stroke_list import StrokeList, lay_strokes, segment_boxes


def relaid(laid: Canvas, changed: np.ndarray, strokes: StrokeList, tips: Dict[Tuple[int, int], BrushTip],
           params: Params) -> Canvas:
    """A new (H, W) canvas holding ``strokes`` laid in order on a blank canvas, made from ``laid``, a canvas on
    which another list of strokes was laid that differs from ``strokes`` only within ``changed`` (K, 4) boxes
    (``segment_boxes`` of every stroke laid on one canvas and not the other, or laid at another contact or in
    another order). ``laid`` is left as it was; tips and params as ``lay_strokes`` takes them."""
    shape = laid.height.shape
    canvas = Canvas(*(values.copy() for values in (laid.colour, laid.coverage, laid.height, laid.opacity)))
    marked = tiles_touched(changed, shape, tuning.RELAY_TILE)
    if not marked.any():
        return canvas
    boxes, owner = segment_boxes(strokes)
    reaching = np.zeros(len(strokes), bool)
    reaching[owner[touching(marked, boxes, shape, tuning.RELAY_TILE)]] = True
    if marked.mean() > tuning.RELAY_MOST_MARKED:
        canvas = Canvas.blank(shape, params.canvas_colour)
        lay_strokes(canvas, strokes, tips, params)
        return canvas
    pixels = np.repeat(np.repeat(marked, tuning.RELAY_TILE, axis=0), tuning.RELAY_TILE, axis=1)[:shape[0], :shape[1]]
    if params.renderer == "lines":              # solid lines are drawn on every pixel: on a blank canvas, copied
        patch = Canvas.blank(shape, params.canvas_colour)
        lay_strokes(patch, strokes.subset(reaching), tips, params)
        for name in ("colour", "coverage", "height", "opacity"):
            getattr(canvas, name)[pixels] = getattr(patch, name)[pixels]
        return canvas
    canvas.colour[pixels] = np.asarray(params.canvas_colour, np.float32)
    for values in (canvas.coverage, canvas.height, canvas.opacity):
        values[pixels] = 0.0
    canvas.only = pixels
    lay_strokes(canvas, strokes.subset(reaching), tips, params)
    canvas.only = None
    return canvas


def tile_ranges(boxes: np.ndarray, shape: tuple, tile: int) -> Tuple[np.ndarray, ...]:
    """(first row, last row, first column, last column) (K,) int64 each, inclusive: the ``tile`` px square tiles of
    an (H, W) ``shape`` canvas that (K, 4) px ``boxes`` (x0, x1, y0, y1) touch, a box beyond the canvas clamped to
    its edge tiles."""
    rows, columns = -(-shape[0] // tile), -(-shape[1] // tile)
    cut = lambda values, count: np.clip(np.floor(values / tile), 0, count - 1).astype(np.int64)  # noqa: E731
    return cut(boxes[:, 2], rows), cut(boxes[:, 3], rows), cut(boxes[:, 0], columns), cut(boxes[:, 1], columns)


def tiles_touched(boxes: np.ndarray, shape: tuple, tile: int) -> np.ndarray:
    """(ceil(H / tile), ceil(W / tile)) bool: the tiles of an (H, W) ``shape`` canvas that any of the (K, 4)
    ``boxes`` touches (``tile_ranges``)."""
    rows, columns = -(-shape[0] // tile), -(-shape[1] // tile)
    top, bottom, left, right = tile_ranges(boxes, shape, tile)
    corners = np.zeros((rows + 1, columns + 1), np.int64)
    for r, c, sign in ((top, left, 1), (top, right + 1, -1), (bottom + 1, left, -1), (bottom + 1, right + 1, 1)):
        np.add.at(corners, (r, c), sign)
    return np.cumsum(np.cumsum(corners, axis=0), axis=1)[:rows, :columns] > 0


def touching(marked: np.ndarray, boxes: np.ndarray, shape: tuple, tile: int) -> np.ndarray:
    """(N,) bool: which of N (N, 4) ``boxes`` touch a tile where ``marked`` (``tiles_touched``'s shape) holds."""
    table = np.zeros((marked.shape[0] + 1, marked.shape[1] + 1), np.int64)
    table[1:, 1:] = np.cumsum(np.cumsum(marked, axis=0), axis=1)
    top, bottom, left, right = tile_ranges(boxes, shape, tile)
    return (table[bottom + 1, right + 1] - table[top, right + 1] - table[bottom + 1, left] + table[top, left]) > 0
