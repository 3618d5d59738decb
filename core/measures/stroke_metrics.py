"""Figures of a painting's brushwork (ALGORITHM §5, §6), defined once so they compare across versions.

Every function takes what a painted folder holds: the strokes (each with
``path`` (K, 2) px, ``size`` px and ``layer``), the height map, the painting
and the photograph (sRGB [0, 1]).
"""

from __future__ import annotations

from typing import Sequence

import numpy as np
from scipy import ndimage

from ..colour import srgb_to_lab


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


def area_share_elongated(strokes: Sequence, ratio: float = 1.5) -> float:
    """Share of the painted area in strokes with L / w >= ``ratio``, a stroke's area taken as w max(L, 1 px)."""
    length = stroke_lengths([s.path for s in strokes])
    width = np.array([float(s.size) for s in strokes])
    area = width * np.maximum(length, 1.0)
    return float(area[length / width >= ratio].sum() / area.sum()) if len(area) else 0.0


def crack_share(height: np.ndarray) -> float:
    """Share of painted pixels (7 x 7 median height > 0.1) whose height is below half that median: grooves."""
    median = ndimage.median_filter(height, size=7)
    painted = median > 0.1
    return float(np.mean((height < 0.5 * median) & painted) / max(np.mean(painted), 1e-9))


def height_spread(height: np.ndarray) -> dict:
    """Height percentiles of painted pixels (> 0.01) over their median: p95 and max."""
    painted = height[height > 0.01]
    if painted.size == 0:
        return {"height_p95_over_median": 0.0, "height_max_over_median": 0.0}
    median = float(np.median(painted))
    return {"height_p95_over_median": float(np.percentile(painted, 95)) / median,
            "height_max_over_median": float(painted.max()) / median}


def smooth_pixels(photo: np.ndarray, share: float = 0.3) -> np.ndarray:
    """(H, W) bool: the photograph's smoothest ``share`` of pixels (lowest gradient after a Gaussian of 2 px)."""
    gray = ndimage.gaussian_filter(photo.mean(axis=2), 2)
    gradient = np.hypot(ndimage.sobel(gray, 0), ndimage.sobel(gray, 1))
    return gradient <= np.percentile(gradient, 100 * share)


def smooth_colour_error(painting: np.ndarray, photo: np.ndarray) -> float:
    """RMS over the smooth pixels of the CIELAB (a*, b*) difference painting - photo (Gaussian of 1 px)."""
    smooth = smooth_pixels(photo)
    lp, li = srgb_to_lab(painting), srgb_to_lab(photo)
    da = ndimage.gaussian_filter(lp[..., 1] - li[..., 1], 1)
    db = ndimage.gaussian_filter(lp[..., 2] - li[..., 2], 1)
    return float(np.sqrt(np.mean((da * da + db * db)[smooth])))


def highlights_kept(painting: np.ndarray, photo: np.ndarray) -> tuple:
    """(count, share kept) of the photograph's small bright features.

    A feature is a 3 x 3 brightness maximum 0.2 above its 15 x 15 median; it
    is kept where the painting stands 0.08 above its own 15 x 15 median within 2 px.
    """
    yi, yp = photo.mean(axis=2), painting.mean(axis=2)
    peaks = (yi == ndimage.maximum_filter(yi, 3)) & (yi - ndimage.median_filter(yi, 15) > 0.2)
    lifted = ndimage.maximum_filter(yp - ndimage.median_filter(yp, 15), 5) > 0.08
    count = int(peaks.sum())
    return count, (float(lifted[peaks].mean()) if count else float("nan"))
