"""sRGB transfer functions, luminance, CIELAB and HSV.

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


D65_WHITE = np.array([0.95047, 1.0, 1.08883])
SRGB_TO_XYZ = np.array([[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]])
XYZ_TO_SRGB = np.linalg.inv(SRGB_TO_XYZ)


def _transform(values: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """(..., 3) ``values`` times the 3 x 3 ``matrix`` (each row of values as a column vector), float64.

    An einsum rather than ``@``: painting calls this once per stroke, and a
    BLAS call there would wake BLAS threads for a 3 x 3 product.
    """
    return np.einsum("...j,ij->...i", values, matrix)


def srgb_to_lab(srgb: np.ndarray) -> np.ndarray:
    """(..., 3) sRGB [0, 1] -> float64 CIELAB (L* in [0, 100], a*, b*), D65 white."""
    c = np.clip(np.asarray(srgb, np.float64), 0.0, 1.0)
    linear = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    xyz = _transform(linear, SRGB_TO_XYZ) / D65_WHITE
    f = np.where(xyz > 216 / 24389, np.cbrt(xyz), (24389 / 27 * xyz + 16) / 116)
    return np.stack([116 * f[..., 1] - 16, 500 * (f[..., 0] - f[..., 1]), 200 * (f[..., 1] - f[..., 2])], -1)


def lab_to_srgb(lab: np.ndarray) -> np.ndarray:
    """(..., 3) CIELAB (D65 white) -> float64 sRGB, clipped to [0, 1]; the inverse of ``srgb_to_lab``."""
    lab = np.asarray(lab, np.float64)
    fy = (lab[..., 0] + 16) / 116
    f = np.stack([fy + lab[..., 1] / 500, fy, fy - lab[..., 2] / 200], axis=-1)
    xyz = np.where(f > 6 / 29, f ** 3, (116 * f - 16) * 27 / 24389) * D65_WHITE
    linear = np.clip(_transform(xyz, XYZ_TO_SRGB), 0.0, 1.0)
    return np.clip(np.where(linear <= 0.0031308, linear * 12.92, 1.055 * linear ** (1 / 2.4) - 0.055), 0.0, 1.0)


def rgb_to_hsv(rgb: np.ndarray) -> np.ndarray:
    """(N, 3) RGB [0, 1] -> (N, 3) HSV, each in [0, 1]: hue a fraction of a turn from red (0 for a grey),
    saturation, value (the largest channel); float64 for float64 RGB. As ``colorsys.rgb_to_hsv``."""
    r, g, b = rgb[:, 0], rgb[:, 1], rgb[:, 2]
    v = rgb.max(axis=1)
    c = v - rgb.min(axis=1)
    s = np.where(v > 0, c / np.where(v > 0, v, 1.0), 0.0)
    cc = np.where(c > 0, c, 1.0)
    hue = np.where(v == r, (g - b) / cc, np.where(v == g, 2.0 + (b - r) / cc, 4.0 + (r - g) / cc))
    hue = np.where(c > 0, np.mod(hue / 6.0, 1.0), 0.0)
    return np.stack([hue, s, v], axis=1)


def hsv_to_rgb(hsv: np.ndarray) -> np.ndarray:
    """(N, 3) HSV in [0, 1] (hue a fraction of a turn) -> (N, 3) RGB [0, 1]; the inverse of ``rgb_to_hsv``.
    As ``colorsys.hsv_to_rgb``."""
    h, s, v = hsv[:, 0], hsv[:, 1], hsv[:, 2]
    k = np.mod(np.array([5.0, 3.0, 1.0])[None, :] + h[:, None] * 6.0, 6.0)
    return v[:, None] - v[:, None] * s[:, None] * np.clip(np.minimum(k, 4.0 - k), 0.0, 1.0)
