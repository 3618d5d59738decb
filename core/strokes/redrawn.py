"""Strokes edited in a drawing program back to a stroke list that ``core lay`` lays: the round trip's way home.

``redrawn_document`` takes the painting's strokes.json document and the
strokes as the program holds them now (``DrawnStrokes``, in their order,
which is the laying order) and gives a strokes.json document of format 2:

- a stroke kept from the painting (its ``index`` names a stroke of the
  document) keeps its recorded "lay" entry: brush, width, bristles, angle.
  Its points moved: each control point of its curve and its anchor move
  with the path points around them (the path's displacement, interpolated
  along the curve; a path resampled by the program to another point count
  is compared at the same fractions of its length). Its colour changed: every
  bristle's colour and the anchor colour move by the change of the stroke's
  mean colour (clipped to [0, 1]), so the bristles keep their spread. A
  change of its width is not laid (its bristles are those of its brush
  width); a move under 0.01 px or a colour change under 1/1024 is none, so
  an unedited stroke is laid as painted, to the bit.
- a stroke drawn anew (``NEW_STROKE``, or an index the document does not
  hold) gets the painting's brush at its width (rounded, at least 1 px),
  every bristle its colour, control points one brush radius apart along
  its points, its anchor at the middle control point, the angle of the
  path there, contact its opacity, and the last layer of the painting.
"""

from __future__ import annotations

import base64
import copy
import math
from typing import List

import numpy as np

from ..files.stroke_file import lay_record
from ..params import Params
from .brush import brush_tip, load_brush
from .drawn import NEW_STROKE, DrawnStrokes, stroke_colour
from .planning import samples_per_segment
from .stroke_list import PAINTING_BRUSH, StrokeList

MOVE_TOLERANCE = 0.01
"""px: a kept stroke whose points moved less than this is laid as painted (strokes.json rounds paths to 0.01 px)."""
COLOUR_TOLERANCE = 1.0 / 1024.0
"""sRGB: a kept stroke whose colour changed less than this in every channel keeps its bristles as laid."""


def arc_fractions(points: np.ndarray) -> np.ndarray:
    """(K,) float64 in [0, 1]: where each of (K, 2) ``points`` lies along the polyline through them, as a fraction
    of its length (evenly spread by index when its length is 0)."""
    steps = np.hypot(*np.diff(points, axis=0).T) if len(points) > 1 else np.zeros(0)
    arc = np.concatenate(([0.0], np.cumsum(steps)))
    if arc[-1] <= 0.0:
        return np.linspace(0.0, 1.0, len(points)) if len(points) > 1 else np.zeros(1)
    return arc / arc[-1]


def at_fractions(points: np.ndarray, fractions: np.ndarray) -> np.ndarray:
    """(F, 2): the points at ``fractions`` (F,) of the length of the polyline through (K, 2) ``points``."""
    along = arc_fractions(points)
    return np.stack([np.interp(fractions, along, points[:, 0]), np.interp(fractions, along, points[:, 1])], axis=1)


def path_samples(lay: dict, size: int, count: int) -> np.ndarray:
    """(K,) float64: the curve sample index of each of the K = ``count`` points of a kept path (its first
    sample, the control points strictly inside, its last sample: ``PlannedPaths.polyline``)."""
    first, last, k = int(lay["first"]), int(lay["last"]), samples_per_segment(size)
    inner = np.arange((first // k + 1) * k, last, k)
    index = np.concatenate(([first], inner, [last])) if last > first else np.array([first])
    if len(index) != count:             # a record not made by the painter: spread the points evenly
        index = np.linspace(first, last, count)
    return index.astype(np.float64)


def moved_lay(stroke: dict, points: np.ndarray) -> dict:
    """A kept stroke's "lay" entry with its control points and anchor moved as its path moved to ``points``
    (K', 2) px (module docstring); the entry as recorded when nothing moved."""
    lay = stroke["lay"]
    path = np.asarray(stroke["path"], np.float64)
    if len(path) == 1:
        path = np.repeat(path, 2, axis=0)           # as ``drawn_from_document`` gave it
    moved = points if len(points) == len(path) else at_fractions(points, arc_fractions(path))
    shift = moved - path
    if np.abs(shift).max(initial=0.0) < MOVE_TOLERANCE:
        return lay
    if len(stroke["path"]) == 1:
        shift = shift.mean(axis=0, keepdims=True)
        path = path[:1]
    per_segment = samples_per_segment(int(stroke["size"]))
    control = np.asarray(lay["control"], np.float64)
    along = path_samples(lay, int(stroke["size"]), len(path))
    at = np.arange(len(control), dtype=np.float64) * per_segment
    control = control + np.stack([np.interp(at, along, shift[:, 0]), np.interp(at, along, shift[:, 1])], axis=1)
    anchor = np.asarray(lay["anchor"], np.float64)
    anchor = anchor + shift[int(np.argmin(np.hypot(*(path - anchor).T)))]
    return dict(lay, control=control.tolist(), anchor=anchor.tolist())


def recoloured_lay(stroke: dict, lay: dict, colour: np.ndarray) -> dict:
    """``lay`` with its bristles and anchor colour moved by ``colour`` (3,) sRGB minus the stroke's mean colour;
    ``lay`` itself when they differ by less than COLOUR_TOLERANCE."""
    change = np.asarray(colour, np.float64) - stroke_colour(stroke)
    if np.abs(change).max() < COLOUR_TOLERANCE:
        return lay
    bristles = np.frombuffer(base64.b64decode(lay["bristles"]), "<f4").reshape(-1, 3)
    bristles = np.clip(bristles + change, 0.0, 1.0).astype("<f4")
    anchor_colour = np.clip(np.asarray(lay["anchor_colour"], np.float64) + change, 0.0, 1.0).astype(np.float32)
    return dict(lay, bristles=base64.b64encode(bristles.tobytes()).decode("ascii"),
                anchor_colour=[float(v) for v in anchor_colour])


def control_points(points: np.ndarray, spacing: float) -> np.ndarray:
    """(C, 2): control points ``spacing`` px apart along the polyline through (K, 2) ``points``, both ends
    included (one point when it has no length)."""
    steps = np.hypot(*np.diff(points, axis=0).T) if len(points) > 1 else np.zeros(0)
    length = float(steps.sum())
    if length < 1e-6:
        return points[:1].astype(np.float64)
    count = max(2, int(math.ceil(length / spacing - 1e-9)) + 1)
    return at_fractions(points, np.linspace(0.0, 1.0, count))


def new_stroke(points: np.ndarray, width: float, colour: np.ndarray, opacity: float, layer: int,
               bristle_count) -> dict:
    """The strokes.json entry (record and "lay") of a stroke drawn anew through (K, 2) ``points`` px, ``width``
    px wide, of sRGB ``colour`` (3,) at ``opacity``, in ``layer``; ``bristle_count(size)`` is the number of
    bristles of the painting's brush ``size`` px wide."""
    size = max(1, int(round(float(width))))
    control = control_points(np.asarray(points, np.float64), max(1.0, 0.5 * size))
    middle = len(control) // 2
    if len(control) > 1:
        a, b = control[max(middle - 1, 0)], control[min(middle + 1, len(control) - 1)]
        angle = math.atan2(b[1] - a[1], b[0] - a[0]) % math.pi
    else:
        angle = 0.0
    colour = np.clip(np.asarray(colour, np.float32), 0.0, 1.0)
    n = int(bristle_count(size))
    strokes = StrokeList(
        np.array([layer], np.int32), np.array([size], np.int32), np.array([PAINTING_BRUSH], np.int8),
        control[middle][None].copy(), control[None], np.array([len(control)], np.int32), np.array([0], np.int64),
        np.array([(len(control) - 1) * samples_per_segment(size)], np.int64), np.array([angle]),
        np.repeat(colour[None], n, axis=0), np.array([0, n], np.int64), colour[None],
        np.array([min(max(float(opacity), 0.0), 1.0)], np.float32))
    record = {"layer": int(layer), "anchor": [int(v) for v in np.floor(control[middle] + 0.5)], "size": size,
              "path": np.round(control, 2).tolist(), "colour": [round(float(v), 4) for v in colour]}
    return dict(record, lay=lay_record(strokes, 0))


def redrawn_document(document: dict, drawn: DrawnStrokes, params: Params) -> dict:
    """A strokes.json document of format 2 holding ``drawn``'s strokes in their order, laid as the module
    docstring says, with ``document``'s version, size and parameters (``params``, the painting's, give the
    brush of new strokes). ValueError when a kept stroke of ``document`` holds no "lay" entry."""
    originals = document["strokes"]
    tip_sizes = {}
    brush = None

    def bristle_count(size: int) -> int:
        nonlocal brush
        if size not in tip_sizes:
            brush = load_brush(params.brush) if brush is None else brush
            tip_sizes[size] = len(brush_tip(brush, size, params.transparency))
        return tip_sizes[size]

    layer = max(0, int(params.layers) - 1)
    strokes: List[dict] = []
    starts = drawn.starts
    for i, index in enumerate(drawn.index.tolist()):
        points = drawn.points[starts[i]:starts[i + 1]]
        if index != NEW_STROKE and 0 <= index < len(originals):
            stroke = originals[index]
            if not isinstance(stroke.get("lay"), dict):
                raise ValueError(f"its stroke {index} has no laying data (paint with --strokes-to-lay to record it)")
            lay = recoloured_lay(stroke, moved_lay(stroke, points), drawn.colour[i])
            kept = copy.copy(stroke)
            kept["lay"] = lay
            strokes.append(kept)
        else:
            strokes.append(new_stroke(points, drawn.width[i], drawn.colour[i], drawn.opacity[i], layer,
                                      bristle_count))
    return dict(document, format=2, width=int(drawn.size[0]), height=int(drawn.size[1]), strokes=strokes)
