"""strokes.json: a painting's strokes as a file, written by ``core paint`` and read by ``core svg`` and ``core lay``.

Format 2 (``"format": 2``) is what this module writes::

    {"version": "<software version>", "format": 2, "width": W, "height": H, "params": {...},
     "strokes": [{"layer", "anchor", "size", "path", "colour", "lay": {...}}, ...]}

Each stroke's first five keys are the record of format 1 (``Stroke.to_dict``:
layer, anchor pixel, brush width px, path points rounded to 0.01 px, sRGB
anchor colour rounded to 4 decimals). "lay" holds what laying the stroke again
needs, exactly (a ``StrokeList`` entry): brush (0 the painting's, 1 the round
brush), anchor (x, y) px, control points, first and last curve samples kept,
angle (radians), anchor_colour (sRGB, full float32 precision), contact, and
bristles, every bristle's sRGB colour as float32 little-endian (B, 3) in
base64. A method that keeps no stroke list (Hertzmann 1998) writes strokes
without "lay". A file without "format" is format 1: the records alone.
"""

from __future__ import annotations

import base64
import json
from pathlib import Path
from typing import Optional

import numpy as np

from ..errors import InputError, reading_error

STROKES_FILE = "strokes.json"
FORMAT = 2
"""The format of strokes.json this code writes."""
READABLE_FORMATS = (1, 2)
"""The formats ``read_stroke_file`` accepts (1: a file without "format", the records alone)."""


def lay_record(strokes, i: int) -> dict:
    """The "lay" entry of stroke ``i`` of a ``StrokeList`` ``strokes`` (module docstring)."""
    count = int(strokes.control_count[i])
    bristles = np.ascontiguousarray(strokes.bristles[strokes.bristle_starts[i]:strokes.bristle_starts[i + 1]],
                                    dtype="<f4")
    return {"brush": int(strokes.brush[i]), "anchor": [float(v) for v in strokes.anchor[i]],
            "control": strokes.control[i, :count].tolist(), "first": int(strokes.first[i]),
            "last": int(strokes.last[i]), "angle": float(strokes.angle[i]),
            "anchor_colour": [float(v) for v in strokes.anchor_colour[i]], "contact": float(strokes.contact[i]),
            "bristles": base64.b64encode(bristles.tobytes()).decode("ascii")}


def stroke_document(records: list, stroke_list, params: dict, width: int, height: int, version: str) -> dict:
    """The JSON document of strokes.json: ``records`` the strokes' ``Stroke.to_dict`` forms in painting order,
    ``stroke_list`` their ``StrokeList`` (one entry per record, or None: no "lay" entries), ``params`` the
    painting's ``Params.to_dict``, the painting's size ``width`` x ``height`` px and the software ``version``."""
    if stroke_list is not None and len(stroke_list) != len(records):
        raise ValueError(f"{len(stroke_list)} laid strokes for {len(records)} stroke records")
    strokes = records if stroke_list is None else [dict(record, lay=lay_record(stroke_list, i))
                                                   for i, record in enumerate(records)]
    return {"version": version, "format": FORMAT, "width": int(width), "height": int(height), "params": params,
            "strokes": strokes}


def _is_point(value) -> bool:
    return (isinstance(value, list) and len(value) == 2
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value))


def _is_record(stroke) -> bool:
    """Whether ``stroke`` has a format 1 record's keys, of the right kinds."""
    return (isinstance(stroke, dict) and isinstance(stroke.get("layer"), int) and _is_point(stroke.get("anchor"))
            and isinstance(stroke.get("size"), int) and stroke["size"] > 0 and isinstance(stroke.get("path"), list)
            and len(stroke["path"]) > 0 and all(_is_point(p) for p in stroke["path"])
            and isinstance(stroke.get("colour"), list) and len(stroke["colour"]) == 3
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in stroke["colour"]))


def read_stroke_file(path) -> dict:
    """The document of the strokes.json at ``path``, checked: strict JSON, an object whose "format" (1 when
    absent) is one of READABLE_FORMATS and whose "strokes" is a list of stroke records. InputError in one
    sentence naming the file otherwise."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise InputError(f"The stroke list {path} is not a text file.") from None
    except OSError as exc:
        raise reading_error(f"The stroke list {path}", exc, "a strokes.json file") from None
    try:
        document = json.loads(text, parse_constant=_no_constant)
    except ValueError:
        raise InputError(f"The stroke list {path} is not valid JSON.") from None
    if not isinstance(document, dict) or not isinstance(document.get("strokes"), list):
        raise InputError(f"{path} is no stroke list of Paint Relief: it has no list of strokes.")
    fmt = document.get("format", 1)
    if fmt not in READABLE_FORMATS or isinstance(fmt, bool):
        raise InputError(f"The stroke list {path} is of format {json.dumps(fmt)[:20]}, which this version does not "
                         f"read (it reads {' and '.join(map(str, READABLE_FORMATS))}).")
    bad = next((i for i, stroke in enumerate(document["strokes"]) if not _is_record(stroke)), None)
    if bad is not None:
        raise InputError(f"Stroke {bad} of the stroke list {path} is not a stroke record "
                         f"(layer, anchor, size, path, colour).")
    return document


def _no_constant(name: str):
    raise ValueError(f"{name} is not strict JSON")


def painting_size(document: dict, folder: Optional[Path] = None) -> Optional[tuple]:
    """(width, height) px of the painting a stroke list belongs to: its own "width" and "height" (format 2), else
    those of report.json in ``folder``; None when neither says."""
    pairs = [document]
    if folder is not None and (Path(folder) / "report.json").is_file():
        try:
            pairs.append(json.loads((Path(folder) / "report.json").read_text(encoding="utf-8")))
        except (OSError, ValueError):
            pass
    for source in pairs:
        w, h = source.get("width") if isinstance(source, dict) else None, \
            source.get("height") if isinstance(source, dict) else None
        if isinstance(w, int) and isinstance(h, int) and w > 0 and h > 0:
            return w, h
    return None


def stroke_opacity(stroke: dict) -> float:
    """A stroke's opacity in [0, 1]: its contact factor (1 for a still's strokes; format 1: 1)."""
    lay = stroke.get("lay")
    contact = lay.get("contact", 1.0) if isinstance(lay, dict) else 1.0
    return float(min(max(contact, 0.0), 1.0)) if isinstance(contact, (int, float)) else 1.0


def bristle_colours(stroke: dict) -> Optional[np.ndarray]:
    """(B, 3) float32 sRGB: the colours of a stroke's bristles as laid, or None when the record holds none."""
    lay = stroke.get("lay")
    if not isinstance(lay, dict) or not isinstance(lay.get("bristles"), str):
        return None
    try:
        data = base64.b64decode(lay["bristles"], validate=True)
    except ValueError:
        return None
    if len(data) == 0 or len(data) % 12:
        return None
    return np.frombuffer(data, "<f4").reshape(-1, 3)
