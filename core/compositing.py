"""Whole-stroke compositing of stamped bristles (ALGORITHM §5, Eq. 4, and §6).

A stroke is the brush stamped at every sample of its path, turned along the
path. Every (stamp, bristle) pair that lands on a pixel is a contribution.
Folding Eq. 4, C <- I C_b + (1 - I) C, over a pixel's contributions in stamp
order gives

    C = sum_s I_s C_s prod_{t>s} (1 - I_t) + C_0 prod_t (1 - I_t),

which is computed for all pixels at once: contributions are sorted by pixel
(stably, so stamp order is kept inside a pixel) and the suffix products come
from a cumulative sum of log(1 - I).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

MAX_INTENSITY = 1.0 - 1e-6  # keeps log(1 - I) finite for full-contact bristles
MAX_ROWS_PER_PIXEL = 16  # contributions a pixel gets from one stroke before stamps are spaced out


@dataclass
class Footprint:
    """What one stroke does to the pixels it touches.

    pixels:        int32 (U,) flat indices (row * W + column), ascending, unique.
    transmittance: float64 (U,) prod (1 - I) over all contributions: the share of
                   the old canvas colour that shows through.
    paint:         float32 (U, 3) sum_s I_s C_s prod_{t>s} (1 - I_t): the paint laid on top.
    height:        float32 (U,) mean bristle intensity of the stamps that covered the pixel.
    distance:      float32 (U,) distance (px) from the pixel centre to the nearest path sample.
    """

    pixels: np.ndarray
    transmittance: np.ndarray
    paint: np.ndarray
    height: np.ndarray
    distance: np.ndarray


def stamp_positions(samples: np.ndarray, angles: np.ndarray, along: np.ndarray, across: np.ndarray) -> tuple:
    """Pixel positions (x, y), each (S, B) float, of B bristles stamped at S path samples.

    samples (S, 2) (x, y); angles (S,) direction of travel; along/across (B,)
    bristle offsets along the path and towards its left-hand normal
    (direction turned by +90 degrees, in image axes). Successive stamps are
    shifted across the path by -1/4 and +1/4 px in turn: stamps one pixel
    apart then land on a lattice twice as dense across the stroke, which
    leaves about eight times fewer unpainted pixels inside a turned stroke
    than stamping on the bare path.
    """
    shift = np.where(np.arange(len(samples)) % 2 == 0, -0.25, 0.25)[:, None]
    c = np.cos(angles)[:, None]
    s = np.sin(angles)[:, None]
    across_shifted = across[None, :] + shift
    x = samples[:, 0:1] + along[None, :] * c - across_shifted * s
    y = samples[:, 1:2] + along[None, :] * s + across_shifted * c
    return x, y


def stamp_stride(brush_length: int, max_rows: int = MAX_ROWS_PER_PIXEL) -> int:
    """Path samples per stamp for a brush ``brush_length`` px along: 1 up to ``max_rows``, then more.

    A brush L rows long stamped every pixel lays L contributions on each pixel
    it crosses, so the cost of a stroke grows with its width times its area.
    Stamping every k = round(L / max_rows) samples, each stamp counted k times
    (see stroke_footprint's ``repeat``), keeps about ``max_rows`` contributions
    per pixel and the painter's cost linear in pixels. Brushes up to
    ``max_rows`` rows (all standard sizes of a 1-megapixel image with the
    shipped brushes) are stamped at every sample.
    """
    return max(1, int(round(brush_length / max_rows)))


def stroke_footprint(samples: np.ndarray, angles: np.ndarray, along: np.ndarray, across: np.ndarray,
                     intensity: np.ndarray, colours: np.ndarray, shape: tuple, repeat: int = 1) -> Footprint:
    """Composite a whole stroke: the Footprint of B bristles stamped at S samples on an (H, W) canvas.

    intensity (B,) in (0, 1]; colours (B, 3) sRGB, one per bristle, kept along the whole path.
    repeat: each stamp stands for this many identical stamps, so a bristle of
    intensity I lets (1 - I)^repeat of the colour below show through; the
    height still averages the bristles' own intensities.
    Contributions go to the nearest pixel (halves round up, so the half-integer
    offsets of an even-width brush land on distinct pixels); those off the canvas are dropped.
    """
    h, w = shape
    x, y = stamp_positions(samples.astype(np.float32), angles.astype(np.float32), along, across)
    ix = np.floor(x + 0.5).astype(np.int32).ravel()
    iy = np.floor(y + 0.5).astype(np.int32).ravel()
    n_bristles = len(intensity)
    inside = (ix >= 0) & (ix < w) & (iy >= 0) & (iy < h)
    contribution = np.flatnonzero(inside).astype(np.int32)
    if contribution.size == 0:
        empty = np.zeros(0)
        return Footprint(np.zeros(0, np.int32), empty, np.zeros((0, 3)), empty.astype(np.float32),
                         empty.astype(np.float32))
    pixel = iy[contribution] * np.int32(w) + ix[contribution]  # int32: the stable sort is much faster than on int64
    order = np.argsort(pixel, kind="stable")
    contribution = contribution[order]
    pixel = pixel[order]
    stamp = contribution // n_bristles
    bristle = contribution - stamp * n_bristles

    new_pixel = np.empty(len(pixel), dtype=bool)
    new_pixel[0] = True
    np.not_equal(pixel[1:], pixel[:-1], out=new_pixel[1:])
    starts = np.flatnonzero(new_pixel)
    ends = np.append(starts[1:], len(pixel))
    counts = ends - starts

    bristle_strength = np.minimum(np.asarray(intensity, dtype=np.float64), MAX_INTENSITY)
    bristle_log_keep = repeat * np.log1p(-bristle_strength)
    strength = bristle_strength[bristle]
    log_keep = bristle_log_keep[bristle]
    opacity = -np.expm1(bristle_log_keep)[bristle] if repeat > 1 else strength  # 1 - (1 - I)^repeat
    cumulative = np.cumsum(log_keep)
    segment_total_cum = np.repeat(cumulative[ends - 1], counts)
    after = np.exp(segment_total_cum - cumulative)          # prod over later contributions of (1 - I)
    weight = (opacity * after).astype(np.float32)
    paint = np.add.reduceat(weight[:, None] * np.asarray(colours, dtype=np.float32)[bristle], starts, axis=0)
    before_start = cumulative[starts] - log_keep[starts]
    transmittance = np.exp(cumulative[ends - 1] - before_start)
    height = (np.add.reduceat(strength, starts) / counts).astype(np.float32)

    samples32 = samples.astype(np.float32)
    dx = (pixel % np.int32(w)).astype(np.float32) - samples32[stamp, 0]
    dy = (pixel // np.int32(w)).astype(np.float32) - samples32[stamp, 1]
    distance = np.minimum.reduceat(np.hypot(dx, dy), starts)
    return Footprint(pixel[starts], transmittance, paint, height, distance)


def band_opacity(distance: np.ndarray, width: float) -> np.ndarray:
    """Anti-aliased line opacity in [0, 1]: 1 within width/2 of the path, a 1 px ramp outside."""
    return np.clip(0.5 * width - distance + 0.5, 0.0, 1.0).astype(np.float32)
