"""Reference image and importance map (ALGORITHM §1, Eq. 1).

The reference is an edge-preserving (bilateral) smoothing of the input; the
importance is its normalised Sobel gradient magnitude, optionally raised by a
user mask.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import ndimage

from .. import tuning
from ..colour import luminance
from ..workers import run_all, worker_count


def bilateral_filter(image: np.ndarray, sigma_spatial: float, sigma_range: float) -> np.ndarray:
    """Edge-preserving smoothing of each channel, guided by that channel's own values.

    image: float32 (H, W) or (H, W, C) in [0, 1]. sigma_spatial in pixels,
    sigma_range in intensity units. Returns float32 of the same shape.

    Computed on a bilateral grid (Paris and Durand 2006): values and weights
    are splatted into a grid sampled every sigma_spatial pixels and every
    sigma_range intensity units, blurred there by a unit Gaussian, and read
    back by trilinear interpolation. Cost is linear in pixels. Blocks of
    rows of every channel are splatted (one per worker at a time) and read
    back side by side on the worker threads; each channel's blocks are
    summed in order.
    """
    img = np.asarray(image, dtype=np.float32)
    if img.ndim == 2:
        return bilateral_filter(img[..., None], sigma_spatial, sigma_range)[..., 0]
    h, w, channels = img.shape
    if sigma_spatial < 0.5 or h * w == 0:
        return img.copy()
    grid = BilateralGrid(h, w, sigma_spatial, sigma_range)
    rows = max(1, tuning.BILATERAL_SPLAT_PIXELS // w)   # row blocks keep the temporaries small on large images
    tasks = [(c, top) for c in range(channels) for top in range(0, h, rows)]
    sums = [grid.empty() for _ in range(channels)]
    workers = worker_count()
    for first in range(0, len(tasks), workers):    # a splat per worker at a time, each added in order
        wave = tasks[first:first + workers]
        for (c, _), (values, weights) in zip(wave, run_all(
                lambda task: grid.splat(img[task[1]:task[1] + rows, :, task[0]], task[1]), wave), strict=True):
            sums[c][0] += values
            sums[c][1] += weights
    blurred = run_all(grid.blur, sums)
    out = np.empty_like(img)

    def read(task: tuple) -> None:
        c, top = task
        out[top:top + rows, :, c] = grid.read(blurred[c], img[top:top + rows, :, c], top)

    run_all(read, tasks)
    return out


class BilateralGrid:
    """The bilateral grid of an (H, W) channel for a filter of ``sigma_spatial`` px and ``sigma_range`` intensity
    units: (gh, gw, gr) cells, max(1, sigma_spatial) px and sigma_range apart, PAD cells beyond each end."""

    PAD = 2

    def __init__(self, h: int, w: int, sigma_spatial: float, sigma_range: float):
        step, pad = max(1.0, float(sigma_spatial)), self.PAD
        self.sigma_range = sigma_range
        self.gh = int(math.ceil((h - 1) / step)) + 1 + 2 * pad
        self.gw = int(math.ceil((w - 1) / step)) + 1 + 2 * pad
        self.gr = int(math.ceil(1.0 / sigma_range)) + 1 + 2 * pad
        self.ys = np.arange(h, dtype=np.float32) / step + pad
        self.xs = np.arange(w, dtype=np.float32) / step + pad
        self.ix = np.rint(self.xs).astype(np.int64)

    def splat(self, block: np.ndarray, top: int) -> tuple:
        """(values, weights), float64 (gh gw gr,): rows ``top`` onwards of a channel, (R, W) in [0, 1], splatted."""
        size = self.gh * self.gw * self.gr
        ir = np.rint(np.clip(block, 0.0, 1.0) / self.sigma_range + self.PAD).astype(np.int64)
        iy = np.rint(self.ys[top:top + len(block)]).astype(np.int64)
        flat = ((iy[:, None] * self.gw + self.ix[None, :]) * self.gr + ir).ravel()
        return (np.bincount(flat, weights=block.ravel().astype(np.float64), minlength=size),
                np.bincount(flat, minlength=size))

    def empty(self) -> np.ndarray:
        """(2, gh gw gr) float64 zeros: a channel's (values, weights) sums."""
        return np.zeros((2, self.gh * self.gw * self.gr))

    def blur(self, sums: np.ndarray) -> np.ndarray:
        """(2, gh, gw, gr) float64: a channel's splatted (values, weights) ``sums`` (``empty``'s shape), blurred."""
        grid = sums.reshape(2, self.gh, self.gw, self.gr)
        return ndimage.gaussian_filter(grid, sigma=(0, 1.0, 1.0, 1.0), mode="constant", truncate=3.0)

    def read(self, grid: np.ndarray, block: np.ndarray, top: int) -> np.ndarray:
        """(R, W) float32: the blurred ``grid`` read back at rows ``top`` onwards of a channel, ``block`` (R, W)."""
        rs = np.clip(block, 0.0, 1.0) / self.sigma_range + self.PAD
        return _slice(grid, self.ys[top:top + len(block)], self.xs, rs)


def _slice(grid: np.ndarray, ys: np.ndarray, xs: np.ndarray, rs: np.ndarray) -> np.ndarray:
    """Trilinear read of a (2, gh, gw, gr) value/weight grid at every pixel; returns value/weight."""
    _, gh, gw, gr = grid.shape
    y0 = np.floor(ys).astype(np.int64)
    x0 = np.floor(xs).astype(np.int64)
    r0 = np.minimum(np.floor(rs).astype(np.int64), gr - 2)
    fy = (ys - y0)[:, None]
    fx = (xs - x0)[None, :]
    fr = (rs - r0).astype(np.float32)
    num = np.zeros(rs.shape, dtype=np.float32)
    den = np.zeros(rs.shape, dtype=np.float32)
    flat = grid.reshape(2, -1).astype(np.float32)
    for dy in (0, 1):
        wy = fy if dy else 1.0 - fy
        for dx in (0, 1):
            wx = fx if dx else 1.0 - fx
            base = ((y0 + dy)[:, None] * gw + (x0 + dx)[None, :]) * gr + r0
            wyx = (wy * wx).astype(np.float32)
            lo_w = wyx * (1.0 - fr)
            hi_w = wyx * fr
            num += np.take(flat[0], base) * lo_w + np.take(flat[0], base + 1) * hi_w
            den += np.take(flat[1], base) * lo_w + np.take(flat[1], base + 1) * hi_w
    return (num / np.maximum(den, 1e-12)).astype(np.float32)


def reference_image(image: np.ndarray, sigma_spatial_fraction: float, sigma_range: float) -> np.ndarray:
    """The painter's reference: bilateral filter of (H, W, 3) sRGB [0, 1] input.

    sigma_spatial_fraction is the spatial sigma as a fraction of the image diagonal.
    """
    h, w = image.shape[:2]
    sigma_spatial = sigma_spatial_fraction * math.hypot(h, w)
    return np.clip(bilateral_filter(image, sigma_spatial, sigma_range), 0.0, 1.0)


def sobel_energy(intensity: np.ndarray) -> np.ndarray:
    """Eq. 1: gradient magnitude of (H, W) intensity, Sobel derivatives in units per pixel.

    Returns float32 (H, W) >= 0; a constant image gives exactly zero.
    """
    i = np.asarray(intensity, dtype=np.float32)
    gx = ndimage.sobel(i, axis=1, mode="nearest") / 8.0
    gy = ndimage.sobel(i, axis=0, mode="nearest") / 8.0
    return np.hypot(gx, gy).astype(np.float32)


def normalise_energy(energy: np.ndarray, percentile: float) -> np.ndarray:
    """Divide (H, W) energy by its ``percentile``-th percentile and clip to [0, 1].

    A map whose percentile is zero (constant or nearly constant images) is
    divided by its maximum instead; an all-zero map stays zero.
    """
    e = np.asarray(energy, dtype=np.float32)
    if e.size == 0:
        return e.copy()
    scale = float(np.percentile(e, percentile))
    if scale <= 0.0:
        scale = float(e.max())
    if scale <= 0.0:
        return np.zeros_like(e)
    return np.clip(e / scale, 0.0, 1.0).astype(np.float32)


def resize_mask(mask: np.ndarray, shape: tuple) -> np.ndarray:
    """Bilinear resize of an (h, w) mask in [0, 1] to ``shape`` = (H, W)."""
    m = np.asarray(mask, dtype=np.float32)
    if m.shape == tuple(shape):
        return m
    ys = (np.arange(shape[0], dtype=np.float32) + 0.5) * (m.shape[0] / shape[0]) - 0.5
    xs = (np.arange(shape[1], dtype=np.float32) + 0.5) * (m.shape[1] / shape[1]) - 0.5
    yy, xx = np.meshgrid(ys, xs, indexing="ij")
    return ndimage.map_coordinates(m, [yy, xx], order=1, mode="nearest").astype(np.float32)


def importance_map(reference: np.ndarray, percentile: float, mask: np.ndarray | None = None,
                   mask_strength: float = 1.0) -> np.ndarray:
    """Normalised importance Ẽ, float32 (H, W) in [0, 1], of an (H, W, 3) reference.

    With a mask (any size, values in [0, 1], resized to the image), the raw
    energy becomes E' = E (1 + k mask) before normalisation, so masked areas
    (e.g. faces) get finer grids and smaller strokes.
    """
    energy = sobel_energy(luminance(reference))
    if mask is not None:
        energy = energy * (1.0 + mask_strength * resize_mask(mask, energy.shape))
    return normalise_energy(energy, percentile)
