"""Image comparison figures: PSNR, SSIM, edge fidelity and correlation.

Images are float arrays in [0, 1], (H, W) or (H, W, 3); colour images are
compared on their Rec.709 luminance where a single channel is needed.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import ndimage

from ..colour import luminance


def psnr(a: np.ndarray, b: np.ndarray) -> float:
    """Peak signal-to-noise ratio (dB) of two [0, 1] images of one shape; inf when they are equal.

    The squared differences are summed in float64 a block of about 2^20
    values at a time, so a large image needs no full-size temporaries.
    """
    a, b = np.atleast_1d(np.asarray(a)), np.atleast_1d(np.asarray(b))
    if a.shape != b.shape:
        raise ValueError(f"PSNR of images of different shapes {a.shape} and {b.shape}.")
    step = max(1, (1 << 20) // max(1, a[0].size))
    total = 0.0
    for start in range(0, len(a), step):
        d = (a[start:start + step].astype(np.float64) - b[start:start + step]).ravel()
        total += float(np.einsum("i,i->", d, d))
    mse = total / a.size
    return math.inf if mse == 0.0 else 10.0 * math.log10(1.0 / mse)


def _gray(image: np.ndarray) -> np.ndarray:
    a = np.asarray(image, dtype=np.float64)
    return luminance(a).astype(np.float64) if a.ndim == 3 else a


def ssim(a: np.ndarray, b: np.ndarray, sigma: float = 1.5) -> float:
    """Mean structural similarity (Wang et al. 2004) of the luminance of two [0, 1] images.

    Gaussian window of ``sigma`` px, K1 = 0.01, K2 = 0.03, data range 1.
    Returns a value in [-1, 1]; 1 for identical images.
    """
    x, y = _gray(a), _gray(b)
    c1, c2 = 0.01 ** 2, 0.03 ** 2
    blur = lambda v: ndimage.gaussian_filter(v, sigma, mode="reflect", truncate=3.5)  # noqa: E731
    mx, my = blur(x), blur(y)
    vx = blur(x * x) - mx * mx
    vy = blur(y * y) - my * my
    cxy = blur(x * y) - mx * my
    s = ((2 * mx * my + c1) * (2 * cxy + c2)) / ((mx * mx + my * my + c1) * (vx + vy + c2))
    return float(np.mean(s))


def pearson(a: np.ndarray, b: np.ndarray) -> float:
    """Pearson correlation of two arrays of the same size; 0 when either is constant."""
    x = np.asarray(a, np.float64).ravel()
    y = np.asarray(b, np.float64).ravel()
    x = x - x.mean()
    y = y - y.mean()
    den = math.sqrt(float(x @ x) * float(y @ y))
    return 0.0 if den == 0.0 else float(x @ y) / den


def gradient_magnitude(image: np.ndarray) -> np.ndarray:
    """Sobel gradient magnitude (per pixel) of an image's luminance, (H, W) float64."""
    g = _gray(image)
    return np.hypot(ndimage.sobel(g, axis=1, mode="nearest"), ndimage.sobel(g, axis=0, mode="nearest")) / 8.0


def edge_fidelity(painting: np.ndarray, reference: np.ndarray) -> float:
    """Correlation of the gradient magnitudes of a painting and its input: how well edges survive."""
    return pearson(gradient_magnitude(painting), gradient_magnitude(reference))
