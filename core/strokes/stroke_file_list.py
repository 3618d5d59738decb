"""A ``StrokeList`` and its ``Stroke`` records read back from a strokes.json document (``files.stroke_file``).

Only format 2 holds what laying strokes again needs (each stroke's "lay"
entry); the document is one ``files.stroke_file.read_stroke_file`` checked.
"""

from __future__ import annotations

import base64
from pathlib import Path
from typing import List, Tuple

import numpy as np

from ..errors import InputError
from .stroke import Stroke
from .stroke_list import PAINTING_BRUSH, ROUND_BRUSH, StrokeList


def _lay_entry(stroke: dict) -> tuple:
    """(brush, anchor (2,), control (P, 2), first, last, angle, anchor_colour (3,), contact, bristles (B, 3)) of
    one stroke's "lay" entry; ValueError when it is missing or malformed."""
    lay = stroke.get("lay")
    if not isinstance(lay, dict):
        raise ValueError("it has no laying data (paint with --strokes-to-lay to record it)")
    brush = lay["brush"]
    if brush not in (PAINTING_BRUSH, ROUND_BRUSH) or isinstance(brush, bool):
        raise ValueError(f"its brush {brush!r} is neither 0 nor 1")
    anchor = np.asarray(lay["anchor"], np.float64)
    control = np.asarray(lay["control"], np.float64)
    colour = np.asarray(lay["anchor_colour"], np.float32)
    data = base64.b64decode(lay["bristles"], validate=True)
    if anchor.shape != (2,) or control.ndim != 2 or control.shape[1] != 2 or len(control) < 1 \
            or colour.shape != (3,) or len(data) == 0 or len(data) % 12:
        raise ValueError("its laying data has the wrong shapes")
    first, last = lay["first"], lay["last"]
    if not (isinstance(first, int) and isinstance(last, int) and 0 <= first <= last):
        raise ValueError("its kept curve samples are not 0 <= first <= last")
    values = np.concatenate([anchor, control.ravel(), colour, [lay["angle"], lay["contact"]]])
    if not np.all(np.isfinite(values)):
        raise ValueError("its laying data holds a value that is not a finite number")
    bristles = np.frombuffer(data, "<f4").reshape(-1, 3).astype(np.float32)
    return (int(brush), anchor, control, first, last, float(lay["angle"]), colour, float(lay["contact"]), bristles)


def strokes_from_document(document: dict, path: Path) -> Tuple[StrokeList, List[Stroke]]:
    """(the ``StrokeList`` to lay, the ``Stroke`` records) of a checked strokes.json ``document`` read from
    ``path``; InputError in one sentence naming the file and the first stroke whose laying data is missing or
    malformed (a format 1 file, a Hertzmann 1998 painting's list)."""
    entries = []
    for i, stroke in enumerate(document["strokes"]):
        try:
            entries.append(_lay_entry(stroke))
        except (KeyError, TypeError, ValueError) as exc:
            why = str(exc) if isinstance(exc, ValueError) and str(exc).startswith("its") else \
                "its laying data is malformed"
            raise InputError(f"Stroke {i} of the stroke list {path} cannot be laid: {why}.") from None
    n = len(entries)
    if n == 0:
        return StrokeList.empty(), []
    width = max(len(entry[2]) for entry in entries)
    control = np.full((n, width, 2), np.nan)
    for i, entry in enumerate(entries):
        control[i, :len(entry[2])] = entry[2]
    counts = np.array([len(entry[8]) for entry in entries], np.int64)
    starts = np.zeros(n + 1, np.int64)
    np.cumsum(counts, out=starts[1:])
    strokes = StrokeList(
        np.array([s["layer"] for s in document["strokes"]], np.int32),
        np.array([s["size"] for s in document["strokes"]], np.int32),
        np.array([entry[0] for entry in entries], np.int8),
        np.array([entry[1] for entry in entries], np.float64).reshape(n, 2), control,
        np.array([len(entry[2]) for entry in entries], np.int32),
        np.array([entry[3] for entry in entries], np.int64), np.array([entry[4] for entry in entries], np.int64),
        np.array([entry[5] for entry in entries], np.float64),
        np.concatenate([entry[8] for entry in entries]).astype(np.float32), starts,
        np.array([entry[6] for entry in entries], np.float32).reshape(n, 3),
        np.array([entry[7] for entry in entries], np.float32))
    try:
        paths = kept_paths(strokes)
    except (ValueError, IndexError):
        raise InputError(f"The stroke list {path} cannot be laid: a stroke's kept curve samples lie beyond its "
                         f"control points.") from None
    records = [Stroke(s["layer"], tuple(s["anchor"]), s["size"], kept, np.asarray(s["colour"], np.float32))
               for s, kept in zip(document["strokes"], paths, strict=True)]
    return strokes, records


def kept_paths(strokes: StrokeList) -> List[np.ndarray]:
    """Each stroke's path as its ``Stroke`` record holds it, (K, 2) float32 (x, y) px: the ends and control points
    of the kept part of its curve re-sampled from its control points (``PlannedPaths.polyline``), the painter's
    own to the bit. IndexError when a stroke's kept samples lie beyond its curve."""
    paths: List[np.ndarray] = []
    for first, stop in strokes.runs():
        plan = strokes.round_plan(first, stop).paths
        if np.any(plan.last >= plan.samples.shape[1]):
            raise IndexError("kept samples beyond the curve")
        paths += [plan.polyline(i) for i in range(stop - first)]
    return paths
