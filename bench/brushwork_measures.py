"""Measures of a painting's brushwork for the benchmarks (ALGORITHM §5, §6), defined once so they compare across
versions (``bench/strokes.py`` prints them).

Every function takes what a painted folder holds: the strokes (each with
``path`` (K, 2) px, ``size`` px, ``anchor`` (x, y) px and ``layer``), the
height map, the painting and the photograph (float (H, W, 3) sRGB [0, 1]).
L is a stroke's polyline length (``stroke_lengths``), w its brush width.
Where the detail pass matters, ``detail_strokes`` is the painting's
statistics["detail_strokes"] (report.json): when it is > 0 the strokes of the
last layer are the detail pass's, and the others are the "layer strokes".
"""

from __future__ import annotations

from typing import Sequence

import numpy as np
from scipy import ndimage

from common import ROOT  # noqa: F401  (puts the repository on sys.path)
from core.colour import REC709_LUMA, srgb_to_lab
from core.measures.metrics import pearson
from core.measures.stroke_metrics import stroke_lengths


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


def detail_map(photo: np.ndarray) -> np.ndarray:
    """(H, W) Sobel gradient magnitude (>= 0, per pixel, unnormalised) of the photograph's channel mean
    after a Gaussian of 2 px: how detailed the photograph is at each pixel."""
    gray = ndimage.gaussian_filter(photo.mean(axis=2), 2)
    return np.hypot(ndimage.sobel(gray, 0), ndimage.sobel(gray, 1))


def smooth_pixels(photo: np.ndarray, share: float = 0.3) -> np.ndarray:
    """(H, W) bool: the photograph's smoothest ``share`` of pixels (lowest gradient after a Gaussian of 2 px)."""
    gradient = detail_map(photo)
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


def layer_strokes(layers: np.ndarray, detail_strokes: int) -> np.ndarray:
    """(N,) bool: which strokes are layer strokes, given each stroke's ``layers`` (N,) int.

    All of them when ``detail_strokes`` is 0; otherwise every stroke but those
    of the last (highest) layer, which are the detail pass's.
    """
    layers = np.asarray(layers).reshape(-1)
    if detail_strokes and layers.size:
        return layers < layers.max()
    return np.ones(layers.size, bool)


def median_length_to_width_layers(strokes: Sequence, detail_strokes: int) -> float:
    """Median L / w (polyline length of the path over brush width, both px) over the layer strokes only,
    so the detail pass's highlight dots are left out; NaN when there are none."""
    keep = layer_strokes([s.layer for s in strokes], detail_strokes)
    if not keep.any():
        return float("nan")
    length = stroke_lengths([s.path for s in strokes])
    width = np.array([float(s.size) for s in strokes])
    return float(np.median((length / width)[keep]))


def detail_share(strokes: Sequence, detail_strokes: int) -> float:
    """Share in [0, 1] of the strokes that belong to the detail pass (0 without strokes)."""
    keep = layer_strokes([s.layer for s in strokes], detail_strokes)
    return float(1.0 - keep.mean()) if keep.size else 0.0


def _luminance64(image: np.ndarray) -> np.ndarray:
    """(H, W, 3) -> (H, W) float64 Rec.709 weighted sum of the channels."""
    return np.asarray(image, np.float64)[..., :3] @ REC709_LUMA.astype(np.float64)


def speckle_share(painting: np.ndarray, photo: np.ndarray) -> float:
    """Share in [0, 1] of the pixels that are speckle: dots and scratches the photograph does not have.

    painting, photo: (H, W, 3) sRGB [0, 1] of one shape. With Y the Rec.709
    luminance, a pixel is speckle where the painting's Y differs by more
    than 0.10 from the median of its 5 x 5 neighbourhood while the
    photograph's Y, after a Gaussian of 0.7 px, differs from its own 5 x 5
    median by less than 0.04.
    """
    yp = _luminance64(painting)
    yi = ndimage.gaussian_filter(_luminance64(photo), 0.7)
    contrast_painting = np.abs(yp - ndimage.median_filter(yp, 5))
    contrast_photo = np.abs(yi - ndimage.median_filter(yi, 5))
    return float(np.mean((contrast_painting > 0.10) & (contrast_photo < 0.04)))


def gradient_correlation(painting: np.ndarray, photo: np.ndarray) -> float:
    """Pearson correlation in [-1, 1] of the painting's and the photograph's gradient magnitudes.

    painting, photo: (H, W, 3) sRGB [0, 1] of one shape. The gradient
    magnitude is the Sobel one of the Rec.709 luminance after a Gaussian of
    1 px (scipy's default 'reflect' borders); 1 when the edges are where the
    photograph's are, in the same proportions; 0 when either image is flat.
    Unlike ``core.measures.metrics.edge_fidelity`` (no smoothing, 'nearest' borders) the
    luminance is smoothed first.
    """
    def magnitude(image: np.ndarray) -> np.ndarray:
        y = ndimage.gaussian_filter(_luminance64(image), 1)
        return np.hypot(ndimage.sobel(y, 0), ndimage.sobel(y, 1))

    return pearson(magnitude(painting), magnitude(photo))


def width_contrast(strokes: Sequence, photo: np.ndarray, detail_strokes: int) -> float:
    """Median brush width of the layer strokes anchored in the photograph's smoothest 30 % of pixels over the
    median width of those anchored in its most detailed 10 % (both by ``detail_map``): the contrast between
    large strokes in plain areas and small ones in detail, > 1 when plain areas get the larger brushes.

    photo: (H, W, 3) sRGB [0, 1]. Anchors (x, y) px off the image are clipped
    to its border. NaN when either group holds no layer stroke.
    """
    if not strokes:
        return float("nan")
    gradient = detail_map(photo)
    h, w = gradient.shape
    anchor = np.array([s.anchor for s in strokes], dtype=int).reshape(-1, 2)
    width = np.array([float(s.size) for s in strokes])
    keep = layer_strokes([s.layer for s in strokes], detail_strokes)
    at = gradient[np.clip(anchor[:, 1], 0, h - 1), np.clip(anchor[:, 0], 0, w - 1)]
    smooth = keep & (at <= np.percentile(gradient, 30))
    detailed = keep & (at >= np.percentile(gradient, 90))
    if not (smooth.any() and detailed.any()):
        return float("nan")
    return float(np.median(width[smooth]) / np.median(width[detailed]))
