"""sRGB transfer functions and luminance.

Arrays are float32, any shape; values in [0, 1] for display-referred data,
unbounded (>= 0) for scene-linear data.
"""

from __future__ import annotations

import numpy as np

REC709_LUMA = np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)


def srgb_to_linear(srgb: np.ndarray) -> np.ndarray:
    """sRGB-encoded values -> scene-linear Rec.709 (IEC 61966-2-1 curve)."""
    c = np.asarray(srgb, dtype=np.float32)
    return np.where(c <= 0.04045, c / 12.92, ((np.maximum(c, 0.04045) + 0.055) / 1.055) ** 2.4).astype(np.float32)


def linear_to_srgb(linear: np.ndarray) -> np.ndarray:
    """Scene-linear Rec.709 -> sRGB-encoded values, clipped to [0, 1]."""
    c = np.clip(np.asarray(linear, dtype=np.float32), 0.0, 1.0)
    return np.where(c <= 0.0031308, c * 12.92, 1.055 * np.power(np.maximum(c, 0.0031308), 1.0 / 2.4) - 0.055).astype(np.float32)


def luminance(rgb: np.ndarray) -> np.ndarray:
    """(..., 3) -> (...): Rec.709 weighted sum of the channels (in whatever encoding they are)."""
    return np.asarray(rgb, dtype=np.float32) @ REC709_LUMA
