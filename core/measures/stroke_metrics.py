"""Shape figures of a painting's strokes, which the painters record in their report (ALGORITHM §5, §6).

A stroke has a ``path`` (K, 2) px, a ``size`` (its brush width, px) and a ``layer``.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np


def stroke_shape(strokes: Sequence) -> dict:
    """Shape figures of a painting's strokes (L = polyline length of a stroke's path, w = its brush width).

    median_length_to_width: median L / w over all strokes; ..._first_layer:
    over the first layer's; dab_share: share of strokes with L < w / 4;
    dab_area_share: their share of the painted area, a stroke's area taken as
    w max(L, w).
    """
    if not strokes:
        return {"median_length_to_width": 0.0, "median_length_to_width_first_layer": 0.0,
                "dab_share": 0.0, "dab_area_share": 0.0}
    length = stroke_lengths([s.path for s in strokes])
    width = np.array([float(s.size) for s in strokes])
    layer = np.array([s.layer for s in strokes])
    ratio = length / width
    dab = length < 0.25 * width
    area = width * np.maximum(length, width)
    return {"median_length_to_width": round(float(np.median(ratio)), 3),
            "median_length_to_width_first_layer": round(float(np.median(ratio[layer == layer.min()])), 3),
            "dab_share": round(float(np.mean(dab)), 4),
            "dab_area_share": round(float(area[dab].sum() / area.sum()), 4)}


def stroke_lengths(paths: Sequence[np.ndarray]) -> np.ndarray:
    """(N,) float64 polyline length (px) of each (K, 2) path (0 for a single point)."""
    return np.array([float(np.sum(np.hypot(*np.diff(np.asarray(p, np.float64), axis=0).T))) if len(p) > 1 else 0.0
                     for p in paths])
