"""A painting's strokes as a drawing program holds them: polylines with a width, a colour and an opacity.

``DrawnStrokes`` is what a Grease Pencil object of the painting holds
(``addon/strokes/grease_pencil.py``), as flat arrays a program sets and reads
in bulk. ``drawn_from_document`` makes it from a strokes.json document (one
polyline per stroke, in painting order); ``plane_points`` and
``from_plane`` carry it to and from a plane of real size (metres), the
canvas's. ``strokes.redrawn`` turns an edited one back into a stroke list to lay.

Pixel coordinates are the painter's: x right, y down, the centre of pixel
(i, j) at (i, j). On the plane, x is right and y up, the plane centred on its
origin, ``width_m`` x ``height_m`` metres; pixel centre (x, y) lies at
((x + 0.5) / W - 0.5) width_m, (0.5 - (y + 0.5) / H) height_m.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Tuple

import numpy as np

from ..colour import linear_to_srgb, srgb_to_linear
from ..files.stroke_file import bristle_colours, stroke_opacity

NEW_STROKE = -1
"""The index of a stroke drawn anew: it is no stroke of the painting's list."""


@dataclass(frozen=True)
class DrawnStrokes:
    """N strokes as polylines, in laying order.

    counts: int64 (N,) points of each stroke, >= 1; stroke i's points are points[starts[i]:starts[i + 1]].
    points: float64 (P, 2) (x, y) px of the painting, P = counts.sum().
    width: float64 (N,) stroke width px, > 0.
    colour: float32 (N, 3) sRGB [0, 1].
    opacity: float32 (N,) in [0, 1].
    index: int64 (N,) the stroke's index in the painting's strokes.json, NEW_STROKE for a stroke drawn anew.
    size: (W, H) px, the painting's size.
    """

    counts: np.ndarray
    points: np.ndarray
    width: np.ndarray
    colour: np.ndarray
    opacity: np.ndarray
    index: np.ndarray
    size: Tuple[int, int]

    def __len__(self) -> int:
        """The number of strokes N."""
        return len(self.counts)

    @property
    def starts(self) -> np.ndarray:
        """int64 (N + 1,) where each stroke's points begin in ``points``."""
        starts = np.zeros(len(self.counts) + 1, np.int64)
        np.cumsum(self.counts, out=starts[1:])
        return starts

    def stroke_points(self, i: int) -> np.ndarray:
        """(K, 2) float64 (x, y) px: stroke i's points."""
        starts = self.starts
        return self.points[starts[i]:starts[i + 1]]

    def metres_per_pixel(self, width_m: float) -> float:
        """Metres per pixel on a plane ``width_m`` metres wide."""
        return float(width_m) / self.size[0]

    def plane_points(self, width_m: float, height_m: float, lift_m: float = 0.0) -> np.ndarray:
        """float32 (P, 3): the points on a plane of ``width_m`` x ``height_m`` metres centred on its origin (x
        right, y up), ``lift_m`` metres above it (z)."""
        w, h = self.size
        out = np.empty((len(self.points), 3), np.float64)
        out[:, 0] = ((self.points[:, 0] + 0.5) / w - 0.5) * width_m
        out[:, 1] = (0.5 - (self.points[:, 1] + 0.5) / h) * height_m
        out[:, 2] = lift_m
        return out.astype(np.float32)

    def linear_colour(self) -> np.ndarray:
        """float32 (N, 3): the colours in scene-linear Rec.709 (as Blender holds vertex colours)."""
        return srgb_to_linear(np.clip(self.colour, 0.0, 1.0)).astype(np.float32)

    @classmethod
    def from_plane(cls, counts, points_m, radius_m, linear_colour, opacity, index, size: Tuple[int, int],
                   width_m: float, height_m: float) -> "DrawnStrokes":
        """The strokes of polylines on a plane of ``width_m`` x ``height_m`` metres (``plane_points``' inverse):
        ``counts`` (N,) points per stroke, ``points_m`` (P, 2 or 3) metres (z ignored), ``radius_m`` (N,) half
        each stroke's width in metres, ``linear_colour`` (N, 3) scene-linear, ``opacity`` (N,), ``index`` (N,)
        (NEW_STROKE for a stroke drawn anew), ``size`` the painting's (W, H) px. ValueError when the shapes
        disagree or a value is not finite."""
        w, h = size
        counts = np.asarray(counts, np.int64).reshape(-1)
        n = len(counts)
        points_m = np.asarray(points_m, np.float64)
        arrays = [np.asarray(a, np.float64) for a in (radius_m, linear_colour, opacity)]
        if np.any(counts < 1) or points_m.ndim != 2 or len(points_m) != counts.sum() or points_m.shape[1] < 2 \
                or arrays[0].shape != (n,) or arrays[1].shape != (n, 3) \
                or arrays[2].shape != (n,) or np.asarray(index).shape != (n,):
            raise ValueError("the drawn strokes' arrays do not agree in shape")
        if not all(np.all(np.isfinite(a)) for a in (points_m[:, :2], *arrays)):
            raise ValueError("a drawn stroke holds a value that is not a finite number")
        px = np.empty((len(points_m), 2))
        px[:, 0] = (points_m[:, 0] / width_m + 0.5) * w - 0.5
        px[:, 1] = (0.5 - points_m[:, 1] / height_m) * h - 0.5
        colour = linear_to_srgb(np.clip(arrays[1], 0.0, None)).astype(np.float32)
        return cls(counts, px, 2.0 * arrays[0] * w / width_m, np.clip(colour, 0.0, 1.0),
                   np.clip(arrays[2], 0.0, 1.0).astype(np.float32), np.asarray(index, np.int64), (int(w), int(h)))


def stroke_colour(stroke: dict) -> np.ndarray:
    """(3,) float64 sRGB: a stroke record's colour as seen from afar, the mean of its bristles' colours as laid
    when it holds them, else its anchor colour (as ``core svg`` paints it)."""
    bristles = bristle_colours(stroke)
    return np.asarray(stroke["colour"], np.float64) if bristles is None else bristles.mean(axis=0, dtype=np.float64)


def drawn_from_document(document: dict, size: Tuple[int, int]) -> DrawnStrokes:
    """The strokes of a checked strokes.json ``document`` (``read_stroke_file``, format 1 or 2) of a painting of
    ``size`` (W, H) px, one per stroke in painting order: its path points (a path of one point, a dab, twice, so
    every stroke has two points at least), its brush width, ``stroke_colour`` and its opacity (contact);
    index i for stroke i."""
    strokes = document["strokes"]
    paths = [stroke["path"] if len(stroke["path"]) > 1 else stroke["path"] * 2 for stroke in strokes]
    counts = np.array([len(path) for path in paths], np.int64)
    points = np.array([point for path in paths for point in path], np.float64).reshape(-1, 2)
    return DrawnStrokes(counts, points, np.array([stroke["size"] for stroke in strokes], np.float64),
                        np.array([stroke_colour(stroke) for stroke in strokes], np.float32).reshape(-1, 3),
                        np.array([stroke_opacity(stroke) for stroke in strokes], np.float32),
                        np.arange(len(strokes), dtype=np.int64), (int(size[0]), int(size[1])))
