"""The reference smoothed at a brush's scale, sampled anywhere (ALGORITHM §5).

Strokes take their anchor colour and test for edges on the reference blurred
by a Gaussian of sigma = 0.25 x the brush width, and sample bristle colours
from it blurred by 0.1 x the width. Large sigmas are computed on a block-mean
copy of the reference, ``factor`` px per block, so each level costs and holds
about H W / factor^2 pixels and the whole set stays linear in the image.
Samples come back by bilinear interpolation at sub-pixel positions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

# A level is sampled at full resolution up to this sigma (px); above it, blocks of sigma / 2 px.
FULL_RESOLUTION_SIGMA = 2.0


@dataclass(frozen=True)
class SmoothedImage:
    """An (H, W, C) image blurred by a Gaussian of ``sigma`` px, stored on blocks of ``factor`` px.

    pixels: float32 (ceil(H / factor), ceil(W / factor), C); pixel (i, j) stands
    for the full-resolution position (j f + (f - 1) / 2, i f + (f - 1) / 2).
    """

    pixels: np.ndarray
    factor: int
    sigma: float

    def sample(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """(..., C) float32 bilinear samples at full-resolution positions x, y (any equal shapes, px).

        Positions outside the image take the nearest border value.
        """
        f = self.factor
        h, w, channels = self.pixels.shape
        shift, f = np.float32((f - 1) / 2.0), np.float32(f)
        u = np.clip((np.asarray(x, np.float32) - shift) / f, 0, w - 1)
        v = np.clip((np.asarray(y, np.float32) - shift) / f, 0, h - 1)
        u0 = np.minimum(u.astype(np.intp), max(w - 2, 0))
        v0 = np.minimum(v.astype(np.intp), max(h - 2, 0))
        fu = (u - u0)[..., None]                                  # float64, as are the blends below
        fv = (v - v0)[..., None]
        flat = self.pixels.reshape(-1, channels)
        i00 = v0 * w + u0
        right = 1 if w > 1 else 0
        down = w if h > 1 else 0
        p00 = np.take(flat, i00, axis=0)
        top = np.take(flat, i00 + right, axis=0) - p00            # p00 + fu (p01 - p00)
        top = np.multiply(top, fu)
        top += p00
        i00 += down
        p10 = np.take(flat, i00, axis=0)
        bottom = np.take(flat, i00 + right, axis=0) - p10
        bottom = np.multiply(bottom, fu)
        bottom += p10
        bottom -= top                                             # top + fv (bottom - top)
        bottom *= fv
        bottom += top
        return bottom.astype(np.float32)


def block_mean(image: np.ndarray, factor: int) -> np.ndarray:
    """(ceil(H / f), ceil(W / f), C) float32 means of f x f blocks of an (H, W, C) image (partial edge blocks
    padded with their edge pixels).

    Each block is summed in float32 in row-major order, one pixel after
    another, then divided by f^2: one whole-image add per block position,
    along rows of blocks (the order a NumPy mean over the two block axes
    takes for three channels, at a fraction of its time).
    """
    h, w = image.shape[:2]
    ny, nx = -(-h // factor), -(-w // factor)
    image = np.asarray(image, np.float32)
    if ny * factor != h or nx * factor != w:
        image = np.pad(image, ((0, ny * factor - h), (0, nx * factor - w), (0, 0)), mode="edge")
    blocks = np.ascontiguousarray(image).reshape(ny, factor, nx, factor, -1).transpose(0, 4, 2, 1, 3)
    total = blocks[..., 0, 0].copy()                             # (ny, C, nx): long runs along a row of blocks
    for a in range(factor):
        for b in range(factor):
            if a or b:
                total += blocks[..., a, b]
    total /= np.float32(factor * factor)
    return np.ascontiguousarray(total.transpose(0, 2, 1))


def block_factor(sigma: float) -> int:
    """The block size (px) ``smooth`` works on for a blur of ``sigma`` px: 1 (full resolution) up to
    FULL_RESOLUTION_SIGMA, floor(sigma / FULL_RESOLUTION_SIGMA) above."""
    return 1 if sigma <= FULL_RESOLUTION_SIGMA else max(1, int(sigma // FULL_RESOLUTION_SIGMA))


def smoothing_cost(sigma: float) -> float:
    """About how long ``smooth`` takes at ``sigma`` px, relative to one pass over the image: the separable
    Gaussian's taps on the blocks, plus the block means."""
    factor = block_factor(sigma)
    return (1.0 + 2.0 * sigma / factor) / (factor * factor) + (1.0 if factor > 1 else 0.0)


def smooth(image: np.ndarray, sigma: float) -> SmoothedImage:
    """The (H, W, C) float32 ``image`` blurred by a Gaussian of ``sigma`` px (edges reflected).

    Up to FULL_RESOLUTION_SIGMA the blur is exact at full resolution; above it
    the image is first averaged over blocks of f = floor(sigma / 2) px (which
    blurs by a variance of (f^2 - 1) / 12 px^2) and the rest of the variance
    is blurred on the blocks.
    """
    image = np.asarray(image, np.float32)
    if sigma <= 0:
        return SmoothedImage(image, 1, 0.0)
    factor = block_factor(sigma)
    if factor == 1:
        pixels = ndimage.gaussian_filter(image, sigma=(sigma, sigma, 0), mode="reflect")
        return SmoothedImage(pixels.astype(np.float32, copy=False), 1, float(sigma))
    rest = math.sqrt(max(sigma * sigma - (factor * factor - 1) / 12.0, 0.0)) / factor
    pixels = ndimage.gaussian_filter(block_mean(image, factor), sigma=(rest, rest, 0), mode="reflect")
    return SmoothedImage(pixels.astype(np.float32, copy=False), factor, float(sigma))
