"""Pictures resampled to another size by area: each new pixel the mean of the old pixels under it."""

from __future__ import annotations

import numpy as np
from threadpoolctl import threadpool_limits


def area_weights(size_in: int, size_out: int) -> np.ndarray:
    """float32 (size_out, size_in): each output pixel the mean of the input pixels under its area (weights by
    overlap, rows summing to 1)."""
    edges = np.linspace(0.0, size_in, size_out + 1)
    left = np.arange(size_in, dtype=np.float64)
    overlap = np.clip(np.minimum(edges[1:, None], left[None, :] + 1) - np.maximum(edges[:-1, None], left[None, :]),
                      0.0, None)
    return (overlap / overlap.sum(axis=1, keepdims=True)).astype(np.float32)


def resize_area(values: np.ndarray, width: int, height: int) -> np.ndarray:
    """(H, W) or (H, W, C) float values resampled to (height, width[, C]) by area averaging (float32).

    The sums are matrix products, which BLAS adds up in another order on another number of threads: they run
    on one, so the values are the same on every machine."""
    data = np.asarray(values, dtype=np.float32)
    if data.shape[:2] == (height, width):
        return data
    rows, cols = area_weights(data.shape[0], height), area_weights(data.shape[1], width)
    flat = data.reshape(data.shape[0], data.shape[1], -1)
    with threadpool_limits(limits=1, user_api="blas"):
        out = np.einsum("ij,jkc,lk->ilc", rows, flat, cols, optimize=True)
    return out.reshape((height, width) + data.shape[2:]).astype(np.float32)
