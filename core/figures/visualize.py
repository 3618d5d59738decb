"""Pictures of the analysis: partition overlay and orientation field (line-integral convolution)."""

from __future__ import annotations

import colorsys

import numpy as np
from scipy import ndimage


def size_colours(count: int) -> np.ndarray:
    """(count, 3) float32 sRGB colours from blue (index 0, largest size) to red (last, smallest)."""
    if count <= 1:
        return np.array([[0.1, 0.3, 1.0]] * max(count, 1), dtype=np.float32)
    hues = np.linspace(240.0, 0.0, count) / 360.0
    return np.array([colorsys.hsv_to_rgb(h, 0.85, 1.0) for h in hues], dtype=np.float32)


def grid_index_map(grids: np.ndarray, shape: tuple) -> np.ndarray:
    """int32 (H, W): the index of the grid covering each pixel (grids (N, 4) as x0, y0, x1, y1)."""
    index = np.full(shape, -1, dtype=np.int32)
    for i, (x0, y0, x1, y1) in enumerate(grids.tolist()):
        index[y0:y1, x0:x1] = i
    return index


def partition_overlay(image: np.ndarray, grids: np.ndarray, grid_sizes: np.ndarray, sizes) -> np.ndarray:
    """(H, W, 3) sRGB picture of the partition over the image.

    Each grid is tinted by its stroke size (blue large ... red small) and
    outlined in dark grey.
    """
    h, w = image.shape[:2]
    rank = {s: i for i, s in enumerate(sorted(sizes, reverse=True))}
    palette = size_colours(len(rank))
    index = grid_index_map(grids, (h, w))
    grid_colour = palette[np.array([rank[int(s)] for s in grid_sizes], dtype=np.int64)]
    out = 0.45 * np.asarray(image, dtype=np.float32) + 0.55 * grid_colour[index]
    border = np.zeros((h, w), dtype=bool)
    border[:, :-1] |= index[:, :-1] != index[:, 1:]
    border[:-1, :] |= index[:-1, :] != index[1:, :]
    out[border] = 0.15
    return np.clip(out, 0.0, 1.0).astype(np.float32)


def line_integral_convolution(orientation: np.ndarray, length: int = 10, seed: int = 0) -> np.ndarray:
    """(H, W) float32 [0, 1] picture of an axial direction field by line-integral convolution.

    White noise is averaged along streamlines traced ``length`` one-pixel steps
    each way through ``orientation`` (radians, axial); the result shows the
    field as fine streaks.
    """
    h, w = orientation.shape
    noise = np.random.default_rng(seed).random((h, w), dtype=np.float32)
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    total = noise.copy()
    dx0 = np.cos(orientation).astype(np.float32)
    dy0 = np.sin(orientation).astype(np.float32)
    for sign in (1.0, -1.0):
        x, y = xx.copy(), yy.copy()
        px, py = sign * dx0, sign * dy0
        for _ in range(length):
            iy = np.clip(np.rint(y), 0, h - 1).astype(np.intp)
            ix = np.clip(np.rint(x), 0, w - 1).astype(np.intp)
            dx, dy = dx0[iy, ix], dy0[iy, ix]
            flip = np.where(dx * px + dy * py < 0, -1.0, 1.0).astype(np.float32)
            px, py = dx * flip, dy * flip
            x = np.clip(x + px, 0, w - 1)
            y = np.clip(y + py, 0, h - 1)
            total += ndimage.map_coordinates(noise, [y, x], order=1, mode="nearest")
    lic = total / (2 * length + 1)
    lo, hi = np.percentile(lic, [1, 99])
    return np.clip((lic - lo) / max(hi - lo, 1e-6), 0.0, 1.0).astype(np.float32)


def orientation_picture(orientation: np.ndarray, image: np.ndarray, seed: int = 0) -> np.ndarray:
    """(H, W, 3) sRGB: the orientation field's LIC texture, tinted by the image colours."""
    lic = line_integral_convolution(orientation, seed=seed)[..., None]
    return np.clip(0.35 + 0.65 * lic * (0.4 + 0.6 * np.asarray(image, dtype=np.float32)), 0.0, 1.0).astype(np.float32)
