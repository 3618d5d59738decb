"""A painting's strokes as an SVG picture: one ``<path>`` per stroke of strokes.json, in painting order.

Each stroke is a path through its kept path points (x right, y down, px of
the painting), ``stroke-width`` its brush width in px, round caps and joins,
``stroke`` its colour as sRGB hex and ``stroke-opacity`` its opacity. The
colour is the mean of its bristles' colours as laid when strokes.json holds
them (format 2), else its anchor colour; the opacity is its contact factor
(1 for a still's strokes). The picture's viewBox is the painting's size.
"""

from __future__ import annotations

from pathlib import Path
from typing import Iterable, List

import numpy as np

from ..errors import InputError
from . import writing
from .stroke_file import STROKES_FILE, bristle_colours, painting_size, read_stroke_file, stroke_opacity


def hex_colour(rgb) -> str:
    """'#rrggbb' of an sRGB colour (3,) in [0, 1] (clipped), each channel rounded to 8 bits."""
    r, g, b = (int(v) for v in np.round(np.clip(np.asarray(rgb, np.float64), 0.0, 1.0) * 255.0))
    return f"#{r:02x}{g:02x}{b:02x}"


def _number(value: float) -> str:
    """A coordinate in px as short text, to 0.01 px."""
    text = f"{value:.2f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def path_data(points) -> str:
    """SVG path data through (K, 2) (x, y) px points: "M x y L x y ..."; a single point is "M x y L x y",
    which round caps draw as a dot."""
    points = list(points)
    if len(points) == 1:
        points = points * 2
    words = [f"{_number(x)} {_number(y)}" for x, y in points]
    return "M" + words[0] + "".join(" L" + word for word in words[1:])


def stroke_colour(stroke: dict) -> str:
    """A stroke record's colour as hex: the mean of its bristles' colours when it holds them, else its
    anchor colour ("colour")."""
    bristles = bristle_colours(stroke)
    return hex_colour(stroke["colour"] if bristles is None else bristles.mean(axis=0, dtype=np.float64))


def stroke_element(stroke: dict) -> str:
    """The ``<path>`` element of one stroke record (``stroke_file`` format 1 or 2)."""
    opacity = stroke_opacity(stroke)
    fade = "" if opacity >= 1.0 else f' stroke-opacity="{opacity:.4g}"'
    return (f'<path d="{path_data(stroke["path"])}" stroke="{stroke_colour(stroke)}" '
            f'stroke-width="{int(stroke["size"])}"{fade}/>')


def svg_text(strokes: Iterable[dict], width: int, height: int) -> str:
    """The SVG document of stroke records in painting order on a ``width`` x ``height`` px painting."""
    lines: List[str] = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{width}" height="{height}" '
        f'viewBox="0 0 {width} {height}">',
        '<g fill="none" stroke-linecap="round" stroke-linejoin="round" stroke-opacity="1">',
    ]
    lines += [stroke_element(stroke) for stroke in strokes]
    lines += ["</g>", "</svg>"]
    return "\n".join(lines) + "\n"


def write_svg(painted_dir, output) -> int:
    """Write PAINTED_DIR/strokes.json's strokes as the SVG file ``output`` (atomically: a temporary name beside it,
    then renamed, so a failure leaves no file); returns the number of strokes. InputError in one sentence when
    the folder has no strokes.json, it is no stroke list this version reads, or the painting's size is unknown
    (neither strokes.json nor report.json says it)."""
    folder = Path(painted_dir)
    path = folder / STROKES_FILE
    if not folder.is_dir():
        raise InputError(f"The folder {folder} does not exist: give a folder painted by `python -m core paint`.")
    if not path.is_file():
        raise InputError(f"{path} does not exist: give a folder painted by `python -m core paint`.")
    document = read_stroke_file(path)
    size = painting_size(document, folder)
    if size is None:
        raise InputError(f"The stroke list {path} does not say the painting's size, nor does a report.json "
                         f"beside it.")
    writing.write_text(output, svg_text(document["strokes"], *size))
    return len(document["strokes"])
