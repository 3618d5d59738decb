"""The results the stages hand on: an image's Analysis and a finished Painting.

They sit below every stage that makes or reads them, so a writer or an
experiment needs no painter to know what a painting is. A Painting's strokes
are ``core.strokes.Stroke`` records, made by the strokes stage.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Dict, List, Tuple

import numpy as np

from .params import Params


@dataclass
class Analysis:
    """Everything the stroke layout needs to know about an (H, W) image.

    reference:   float32 (H, W, 3) sRGB [0, 1], bilateral-filtered input.
    importance:  float32 (H, W) [0, 1], normalised Sobel energy Ẽ (Eq. 1).
    grids:       int32 (N, 4) rows (x0, y0, x1, y1), half-open, tiling the canvas.
    grid_sizes:  int32 (N,) standard stroke size (px) of each grid.
    orientation: float32 (H, W) [0, pi), stroke direction (Eq. 3).
    sizes:       standard stroke sizes (px) scaled to this image, descending.
    seconds:     wall-clock seconds of each stage.
    """

    reference: np.ndarray
    importance: np.ndarray
    grids: np.ndarray
    grid_sizes: np.ndarray
    orientation: np.ndarray
    sizes: Tuple[int, ...]
    seconds: Dict[str, float] = field(default_factory=dict)

    def summary(self) -> dict:
        """JSON-ready figures: grid count, histogram of grid sizes, seconds per stage."""
        counts = {int(s): int(np.count_nonzero(self.grid_sizes == s)) for s in self.sizes}
        areas = (self.grids[:, 2] - self.grids[:, 0]) * (self.grids[:, 3] - self.grids[:, 1])
        h, w = self.importance.shape
        return {
            "width": int(w),
            "height": int(h),
            "grids": int(len(self.grids)),
            "stroke_sizes_px": list(self.sizes),
            "grids_per_stroke_size": counts,
            "grid_area_px": {
                "min": int(areas.min()), "median": float(np.median(areas)), "max": int(areas.max()),
            },
            "seconds": {k: round(v, 4) for k, v in self.seconds.items()},
        }


@dataclass
class Painting:
    """A finished painting of an (H, W) image.

    colour (H, W, 3) sRGB [0, 1]; height (H, W) >= 0 (1 = one full bristle's
    contact); opacity and coverage (H, W) [0, 1]; orientation (H, W) radians
    [0, pi); strokes the ``core.strokes.Stroke`` records in painting order; analysis the maps it was built on;
    statistics the figures of ``report.json``; stroke_list the ``core.strokes.stroke_list.StrokeList`` of the
    laid strokes when the painter was asked to record it, else None.
    """

    colour: np.ndarray
    height: np.ndarray
    opacity: np.ndarray
    coverage: np.ndarray
    orientation: np.ndarray
    strokes: List
    analysis: Analysis
    params: Params
    statistics: Dict = field(default_factory=dict)
    stroke_list: object = None
