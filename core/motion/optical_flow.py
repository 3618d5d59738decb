"""Optical flow: the forward motion between two frames that carry no Vector pass (ALGORITHM §9, "Motion").

``optical_flow(first, second)`` returns w with ``first(x) ≈ second(x + w(x))``:
a float32 (H, W, 2) field in pixels, image axes ([..., 0] = x to the right,
[..., 1] = y down), from two float32 (H, W, 3) sRGB frames in [0, 1].

The method is TV-L1 (Zach, Pock and Bischof 2007; the form and the constants
of Sánchez, Meinhardt-Llopis and Facciolo, IPOL 2013): on the luminance of
the frames it minimises

    Σ |∇u| + |∇v| + λ |I₂(x + w(x)) − I₁(x)|

coarse to fine on a pyramid of halved frames. At each level the second frame
is warped by the current motion (bilinear), the data term is linearised around
it and the problem is split in two halves coupled by θ: a pointwise threshold
step on the data term and Chambolle's projection for the total variation. The
total variation carries motion across flat regions (a plain wall, the inside of
a brick) from the edges around them; patch and window methods find none there.

Chosen by bench/flow.py on a Blender render whose Vector pass gives the true
motion (sample_scenes/sequence_scene.py at 640 x 360: a camera panning 4 px a
frame over a brick wall and a tiled floor, a ball rolling 35 to 110 px a
frame). Where the true motion is under 10 px, the mean end-point error is
1.5 px, against 4.4 to 5.4 px for OpenCV's DIS flow and Farneback (4.7 px for
no motion at all) and 1.4 px for scikit-image's TV-L1, which takes 3.5 times
as long; the warping error is 0.7 times that of the true motion; 1.4 s per
megapixel on one core. OpenCV's wheels would also add 37 to 57 MB to each
platform's package, scikit-image's with its dependencies about 45 MB. No method measured there follows the ball once it
moves further than about its own radius in a frame. Everything is NumPy and
SciPy on one thread, so the result is the same bytes on every run.
"""

from __future__ import annotations

from typing import List

import numpy as np
from scipy import ndimage

from ..colour import luminance

DATA_WEIGHT = 38.0
"""λ, the weight of the data term for luminance in [0, 1] (0.15 for 0–255 in IPOL 2013, times 255):
larger follows the frames more closely, smaller gives smoother motion."""
COUPLING = 0.3
"""θ, how tightly the data half and the total-variation half of the split problem are held together."""
DUAL_STEP = 0.25
"""τ, the step of Chambolle's projection: 1/4 is the largest for which it converges on a 2-D grid."""
WARPS = 5
"""How many times per pyramid level the second frame is warped by the current motion."""
ITERATIONS = 10
"""Alternations of the threshold step and the projection per warp."""
COARSEST_SIDE = 16
"""The pyramid stops before a level whose shorter side would be under this many pixels."""
PYRAMID_BLUR = 0.8
"""Gaussian sigma, in pixels of the finer level, applied before a level is halved (against aliasing)."""
SEQUENCE_MEGAPIXELS = 0.35
"""The finest pyramid level a sequence's flow is refined on (``optical_flow``'s ``max_megapixels``). On three
pairs of the render bench/flow.py measures (640 x 360), stopping one level short (0.06 MP) gives the same mean
end-point error against the true motion (2.0, 3.6 and 4.3 px; 1.1, 1.6 and 1.6 px where it is under 10 px) in
0.10 s instead of 0.37 s; a 1080p frame's flow then costs about what a 0.35 MP frame's does."""
_TINY = np.float32(1e-8)


def optical_flow(first: np.ndarray, second: np.ndarray, max_megapixels: float = float("inf")) -> np.ndarray:
    """Forward motion from ``first`` to ``second``: float32 (H, W, 2) in pixels, x right and y down.

    ``first`` and ``second`` are float32 (H, W, 3) sRGB frames in [0, 1] of
    the same size, at least 2 × 2 pixels. The motion of pixel x of ``first``
    is w(x), so that ``first(x)`` matches ``second(x + w(x))``; it is defined
    everywhere, also where the pixel is hidden in ``second`` (there it is
    carried over from the neighbourhood). The pyramid is refined down to its
    finest level of at most ``max_megapixels`` and the motion found there is
    resampled to the frames' size (``SEQUENCE_MEGAPIXELS``). Deterministic: the
    same frames give the same bytes on every run and whatever the number of
    threads.
    """
    first = np.asarray(first, dtype=np.float32)
    second = np.asarray(second, dtype=np.float32)
    if first.shape != second.shape or first.ndim != 3 or first.shape[2] != 3:
        raise ValueError("optical_flow needs two (H, W, 3) frames of one size, got {} and {}".format(
            first.shape, second.shape))
    if min(first.shape[:2]) < 2:
        raise ValueError("optical_flow needs frames of at least 2 x 2 pixels, got {}".format(first.shape[:2]))
    firsts = _pyramid(luminance(first))
    seconds = _pyramid(luminance(second))
    finest = next((i for i, level in enumerate(firsts) if level.size <= max_megapixels * 1e6), len(firsts) - 1)
    flow = np.zeros(firsts[-1].shape + (2,), np.float32)
    for level_first, level_second in zip(reversed(firsts[finest:]), reversed(seconds[finest:]), strict=True):
        flow = _tv_l1(level_first, level_second, _resized_flow(flow, level_first.shape))
    return _resized_flow(flow, first.shape[:2])


def _pyramid(gray: np.ndarray) -> List[np.ndarray]:
    """Levels of (h, w) float32 ``gray``, finest first, each half the size of the one before (rounded up)."""
    levels = [np.ascontiguousarray(gray, dtype=np.float32)]
    while True:
        h, w = levels[-1].shape
        shape = ((h + 1) // 2, (w + 1) // 2)
        if min(shape) < COARSEST_SIDE:
            return levels
        blurred = ndimage.gaussian_filter(levels[-1], PYRAMID_BLUR, mode="nearest")
        levels.append(_resized(blurred, shape))


def _resized(values: np.ndarray, shape) -> np.ndarray:
    """(h, w) ``values`` resampled bilinearly to ``shape``, pixel edges aligned (float32)."""
    h, w = values.shape
    factors = (shape[0] / h, shape[1] / w)
    return ndimage.zoom(values, factors, order=1, mode="nearest", grid_mode=True, output=np.float32)


def _resized_flow(flow: np.ndarray, shape) -> np.ndarray:
    """(h, w, 2) motion resampled to ``shape`` and rescaled to that level's pixels."""
    h, w = flow.shape[:2]
    if (h, w) == tuple(shape):
        return flow
    x = _resized(flow[..., 0], shape) * np.float32(shape[1] / w)
    y = _resized(flow[..., 1], shape) * np.float32(shape[0] / h)
    return np.stack([x, y], axis=-1)


def _tv_l1(first: np.ndarray, second: np.ndarray, flow: np.ndarray) -> np.ndarray:
    """The motion from (h, w) ``first`` to ``second`` refined by TV-L1 from ``flow`` (h, w, 2), float32."""
    rows, columns = np.indices(first.shape, dtype=np.float32)
    gradient_y, gradient_x = np.gradient(second)
    u = np.array(flow[..., 0], dtype=np.float32)
    v = np.array(flow[..., 1], dtype=np.float32)
    dual = np.zeros((4,) + first.shape, np.float32)
    threshold = np.float32(DATA_WEIGHT * COUPLING)
    for _ in range(WARPS):
        where = [rows + v, columns + u]
        warped, gx, gy = (ndimage.map_coordinates(image, where, order=1, mode="nearest", output=np.float32)
                          for image in (second, gradient_x, gradient_y))
        squared = gx * gx + gy * gy + _TINY
        residual_at_zero = warped - first - gx * u - gy * v
        for _ in range(ITERATIONS):
            step = np.clip(-(residual_at_zero + gx * u + gy * v) / squared, -threshold, threshold)
            u = u + step * gx + np.float32(COUPLING) * _divergence(dual[0], dual[1])
            v = v + step * gy + np.float32(COUPLING) * _divergence(dual[2], dual[3])
            _project(dual[0], dual[1], u)
            _project(dual[2], dual[3], v)
    return np.stack([u, v], axis=-1)


def _project(dual_x: np.ndarray, dual_y: np.ndarray, component: np.ndarray) -> None:
    """One step of Chambolle's projection of the dual field of ``component``, in place."""
    gx, gy = _forward_differences(component)
    rate = np.float32(DUAL_STEP / COUPLING)
    norm = 1.0 + rate * np.sqrt(gx * gx + gy * gy)
    dual_x += rate * gx
    dual_x /= norm
    dual_y += rate * gy
    dual_y /= norm


def _forward_differences(values: np.ndarray):
    """(d/dx, d/dy) of (h, w) ``values`` by forward differences, 0 on the last column and row."""
    gx = np.zeros_like(values)
    gy = np.zeros_like(values)
    gx[:, :-1] = values[:, 1:] - values[:, :-1]
    gy[:-1, :] = values[1:, :] - values[:-1, :]
    return gx, gy


def _divergence(dual_x: np.ndarray, dual_y: np.ndarray) -> np.ndarray:
    """Divergence of a dual field by backward differences (the negative adjoint of ``_forward_differences``).

    The dual field is 0 on the last column (x) and the last row (y), as
    ``_project`` keeps it, so plain backward differences with 0 before the
    first column and row are the whole rule.
    """
    out = dual_x + dual_y
    out[:, 1:] -= dual_x[:, :-1]
    out[1:, :] -= dual_y[:-1, :]
    return out
