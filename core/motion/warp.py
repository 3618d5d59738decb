"""Bilinear sampling of an image at positions, and warping frame t+1 back onto frame t (ALGORITHM §9).

Pixel (row i, column j) has its centre at position (x, y) = (j, i): x right,
y down, in pixels. A position is *in the frame* when it lies within the
pixel centres, 0 <= x <= W - 1 and 0 <= y <= H - 1, where bilinear
interpolation needs no value from outside the image, give or take
EDGE_TOLERANCE (a motion read from a file is rounded to float32: a pixel
moved exactly onto the edge must not fall out by 1e-6 px). A position
outside the frame (or not finite) is not visible: its sample is the nearest
edge's value and the mask returned with it says False. A motion longer than
the frame's width plus its height (``reach``) takes every pixel out of the
frame; ``within_reach`` clips such motions (1e30 px, infinities, NaN) to that
length, so they leave the frame in numbers whose squares stay finite.
"""

from __future__ import annotations

from typing import Tuple

import numpy as np

from ..workers import run_all

BLOCK_POSITIONS = 1 << 16
"""Positions sampled at a time by ``bilinear``: a block's temporaries (a few MiB) stay in the processor's cache."""

EDGE_TOLERANCE = 1e-3  # px: how far outside the pixel centres a position still counts as in the frame


def reach(height: int, width: int) -> float:
    """px: the frame's width plus its height, further than any pixel of a (height, width) frame can move and stay
    in it."""
    return float(height + width)


def within_reach(motion: np.ndarray) -> np.ndarray:
    """(H, W, 2) ``motion`` (float32, px) with each component clipped to +-``reach`` of its frame, NaN set to
    +``reach``: a motion that leaves the frame still leaves it, in numbers whose squares are finite. A motion
    within reach (every motion a pixel that stays in the frame can have) is returned unchanged, the same array."""
    motion = np.asarray(motion, dtype=np.float32)
    limit = np.float32(reach(*motion.shape[:2]))
    if np.all(np.abs(motion) <= limit):
        return motion
    return np.clip(np.nan_to_num(motion, nan=limit, posinf=limit, neginf=-limit), -limit, limit)


def pixel_positions(height: int, width: int) -> np.ndarray:
    """The centres of an image's pixels: float32 (height, width, 2), [..., 0] = x = column, [..., 1] = y = row."""
    rows, columns = np.mgrid[0:height, 0:width].astype(np.float32)
    return np.stack([columns, rows], axis=-1)


def inside_frame(positions: np.ndarray, height: int, width: int) -> np.ndarray:
    """Which positions lie in a (height, width) frame.

    positions: (..., 2) x, y in pixels. Returns bool (...): finite and within
    0 <= x <= width - 1, 0 <= y <= height - 1, up to EDGE_TOLERANCE.
    """
    p = np.asarray(positions)
    x, y = p[..., 0], p[..., 1]
    low, right, bottom = -EDGE_TOLERANCE, width - 1 + EDGE_TOLERANCE, height - 1 + EDGE_TOLERANCE
    return (x >= low) & (x <= right) & (y >= low) & (y <= bottom)


def bilinear(image: np.ndarray, positions: np.ndarray) -> np.ndarray:
    """An image's values at sub-pixel positions, by bilinear interpolation of its four nearest pixels.

    image: (H, W) or (H, W, C), any real values.
    positions: (..., 2) x, y in pixels (pixel centres at whole numbers).
    Returns float32 (...) or (..., C). A position outside the frame takes
    the value at the nearest point of the frame (see ``inside_frame``); a
    non-finite one the value of pixel (0, 0). The positions are taken
    ``BLOCK_POSITIONS`` at a time on the worker threads: every value is its
    own four pixels' and none other's, so the bytes are those of one block.
    """
    values = np.asarray(image, dtype=np.float32)
    places = np.asarray(positions).reshape(-1, 2)
    out = np.empty((len(places),) + values.shape[2:], np.float32)
    flat = values.reshape((values.shape[0] * values.shape[1],) + values.shape[2:])

    def block(first: int) -> None:
        out[first:first + BLOCK_POSITIONS] = bilinear_block(flat, values.shape[:2],
                                                            places[first:first + BLOCK_POSITIONS])

    run_all(block, range(0, len(places), BLOCK_POSITIONS))
    return out.reshape(np.shape(positions)[:-1] + values.shape[2:])


def bilinear_block(flat: np.ndarray, shape: Tuple[int, int], places: np.ndarray) -> np.ndarray:
    """``bilinear`` of (N, 2) ``places`` in an (H, W) ``shape`` image flattened to (H * W, ...) float32 ``flat``."""
    height, width = shape
    p = np.nan_to_num(np.asarray(places, dtype=np.float32), nan=0.0)
    x = np.clip(p[..., 0], 0.0, width - 1)
    y = np.clip(p[..., 1], 0.0, height - 1)
    x0 = np.floor(x).astype(np.intp)
    y0 = np.floor(y).astype(np.intp)
    x1 = np.minimum(x0 + 1, width - 1)
    y1 = np.minimum(y0 + 1, height - 1)
    fx = x - x0
    fy = y - y0
    row0, row1 = y0 * width, y1 * width
    if flat.ndim == 2:
        fx, fy = fx[..., None], fy[..., None]
    top = (1.0 - fx) * np.take(flat, row0 + x0, axis=0) + fx * np.take(flat, row0 + x1, axis=0)
    bottom = (1.0 - fx) * np.take(flat, row1 + x0, axis=0) + fx * np.take(flat, row1 + x1, axis=0)
    return ((1.0 - fy) * top + fy * bottom).astype(np.float32, copy=False)


def warp_back(next_frame: np.ndarray, forward: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Frame t+1 seen from frame t: V_{t+1}(x + w_f(x)) at every pixel x of frame t.

    next_frame: (H, W) or (H, W, C) values of frame t+1.
    forward: float32 (H, W, 2) motion of frame t to frame t+1, pixels, x right, y down.
    Returns (warped, inside): float32 values shaped as ``next_frame``, and bool
    (H, W), False where x + w_f(x) leaves frame t+1 (there the value is the
    nearest edge's and is not visible).
    """
    values = np.asarray(next_frame)
    motion = np.asarray(forward, dtype=np.float32)
    height, width = values.shape[:2]
    if motion.shape != (height, width, 2):
        raise ValueError(f"a motion for a {height} x {width} frame is ({height}, {width}, 2); got {motion.shape}")
    targets = pixel_positions(height, width) + motion
    return bilinear(values, targets), inside_frame(targets, height, width)
