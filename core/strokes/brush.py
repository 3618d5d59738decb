"""Brush maps and brush tips: the bristles a stroke is painted with (ALGORITHM §5).

A brush map is a small grayscale float32 image (rows, cols) in [0, 1]; every
pixel with intensity > 0 is a bristle and its intensity is its contact with
the canvas (1 = full). Convention: the map's COLUMNS run ACROSS the stroke
(the brush's wide side) and its ROWS run ALONG it, so a flat brush map is
wide and short. Row 0 is the front (leading edge) of the brush and column 0
its right-hand side seen from above when the stroke goes up the image: a
stroke running up the image (direction (0, -1)) stamps the map exactly as
it looks in an image viewer, never mirrored.

A brush tip is the map resized to one stroke width, as a list of bristles
with offsets (pixels) from the brush centre in the stroke's own frame:
``along`` in the stroke direction d = (dx, dy) and ``across`` in the normal
n = (-dy, dx) (d turned by +90 degrees in image coordinates, x right, y
down). A bristle at (along a, across c) lies at ``centre + a * d + c * n``.
"""

from __future__ import annotations

import math
import os
import pathlib
from dataclasses import dataclass
from typing import Dict, Iterable, Union

import numpy as np
from scipy import ndimage

from ..errors import InputError, ParameterError

SHIPPED_BRUSHES = ("flat", "round", "filbert")

# Fixed seeds so every shipped brush is the same on every run and machine.
_SEEDS = {"flat": 20110101, "round": 20110202, "filbert": 20110303}

# Resized values at or below this are not bristles.
BRISTLE_THRESHOLD = 1e-3

PathLike = Union[str, os.PathLike]


# ---------------------------------------------------------------------------
# procedural brush maps


def smoothstep(x: np.ndarray) -> np.ndarray:
    """0 for x <= 0, 1 for x >= 1, the cubic 3x^2 - 2x^3 between (any shape; float x keeps its dtype)."""
    t = np.clip(x, 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def _brush_from_profile(rows: int, cols: int, half_length: np.ndarray, density: np.ndarray,
                        rng: np.random.Generator, ragged: float = 3.0, soft: float = 1.5,
                        side_soft: float = 0.0) -> np.ndarray:
    """Bristle map (rows, cols) float32 in [0, 1] with max exactly 1 from a footprint profile.

    half_length: (cols,) half of each column's along extent, in rows.
    density: (rows, cols) smooth contact multiplier in (0, 1] (1 = flat).
    ragged: each column's front and back end move inward by U(0, ragged) rows.
    soft: rows over which a column end fades in (smoothstep).
    side_soft: columns over which the left and right sides fade in (0 = none).
    Columns get their own contact level U(0.7, 1) (streaks) and every pixel
    fine multiplicative noise; values below 0.01 become exactly 0.
    """
    v = (np.arange(rows) + 0.5 - rows / 2.0)[:, None]          # along, rows from the centre
    x = (np.arange(cols) + 0.5 - cols / 2.0)[None, :]          # across, columns from the centre
    front = -half_length[None, :] + rng.uniform(0.0, ragged, cols)[None, :]
    back = half_length[None, :] - rng.uniform(0.0, ragged, cols)[None, :]
    footprint = smoothstep((v - front) / soft) * smoothstep((back - v) / soft)
    if side_soft > 0:
        footprint = footprint * smoothstep((cols / 2.0 - np.abs(x)) / side_soft)
    level = rng.uniform(0.7, 1.0, cols)[None, :]
    noise = np.clip(1.0 + 0.06 * rng.standard_normal((rows, cols)), 0.8, 1.2)
    values = footprint * density * level * noise
    values[values < 0.01 * values.max()] = 0.0
    values = values / values.max()
    return np.clip(values, 0.0, 1.0).astype(np.float32)


def _flat(rng: np.random.Generator) -> np.ndarray:
    """Flat brush, 24 x 96: a rectangle with ragged ends and softly fading sides."""
    rows, cols = 24, 96
    half = np.full(cols, rows / 2.0)
    return _brush_from_profile(rows, cols, half, np.ones((rows, cols)), rng, side_soft=2.0)


def _round(rng: np.random.Generator) -> np.ndarray:
    """Round brush, 40 x 64: an elliptical footprint, denser in the centre."""
    rows, cols = 40, 64
    x = (np.arange(cols) + 0.5 - cols / 2.0) / (cols / 2.0)
    half = rows / 2.0 * np.sqrt(np.clip(1.0 - x * x, 0.0, None))
    v = (np.arange(rows) + 0.5 - rows / 2.0) / (rows / 2.0)
    r2 = np.clip(x[None, :] ** 2 + v[:, None] ** 2, 0.0, 1.0)
    return _brush_from_profile(rows, cols, half, 0.6 + 0.4 * (1.0 - r2), rng, ragged=2.5)


def _filbert(rng: np.random.Generator) -> np.ndarray:
    """Filbert brush, 32 x 80: flat in the middle, its along extent rounding off toward both sides."""
    rows, cols = 32, 80
    x = np.abs(np.arange(cols) + 0.5 - cols / 2.0) / (cols / 2.0)
    flat_part = 0.4
    t = np.clip((x - flat_part) / (1.0 - flat_part), 0.0, 1.0)
    half = rows / 2.0 * np.sqrt(1.0 - t * t)
    density = np.broadcast_to(0.85 + 0.15 * (1.0 - x * x), (rows, cols))
    return _brush_from_profile(rows, cols, half, density, rng, ragged=2.5)


_BUILDERS = {"flat": _flat, "round": _round, "filbert": _filbert}


def procedural_brush(name: str) -> np.ndarray:
    """A shipped brush map: float32 (rows, cols) in [0, 1], max exactly 1, zero outside its footprint.

    name: one of SHIPPED_BRUSHES. flat 24 x 96, round 40 x 64 (ellipse,
    denser centre), filbert 32 x 80 (flat with rounded ends). All are wider
    across (columns) than along (rows), with per-column contact levels
    (streaks), fine noise, ragged ends and soft edges. Deterministic: a fixed
    seed per name. Raises ParameterError for an unknown name.
    """
    key = str(name).strip().lower()
    if key not in _BUILDERS:
        raise ParameterError(f"Unknown shipped brush {name!r}; choose one of {', '.join(SHIPPED_BRUSHES)}.")
    return _BUILDERS[key](np.random.default_rng(_SEEDS[key]))


# ---------------------------------------------------------------------------
# loading


def crop_to_bristles(brush_map: np.ndarray) -> np.ndarray:
    """The (rows, cols) map cut to the bounding box of its pixels > 0 (a copy, float32).

    The map must have at least one pixel > 0.
    """
    values = np.asarray(brush_map, dtype=np.float32)
    rows = np.flatnonzero((values > 0).any(axis=1))
    cols = np.flatnonzero((values > 0).any(axis=0))
    return np.ascontiguousarray(values[rows[0]:rows[-1] + 1, cols[0]:cols[-1] + 1])


def load_brush(spec: PathLike, max_megapixels: float = 1.0) -> np.ndarray:
    """Brush map float32 (rows, cols) in [0, 1], cropped to its bristles.

    spec: a shipped brush name (flat, round, filbert; any letter case) or a
    path to an image OpenImageIO reads (colour becomes luminance, alpha
    multiplies it; see ``reading.read_gray``). A user map is used as it is (not
    normalised), its columns across and its rows along the stroke.
    Raises ParameterError when spec is neither a shipped name nor an existing
    file, InputError when the file cannot be read (or is above
    ``max_megapixels``) or has no pixel > 0.
    """
    text = os.fspath(spec) if isinstance(spec, (str, os.PathLike)) else str(spec)
    if text.strip().lower() in _BUILDERS:
        return crop_to_bristles(procedural_brush(text))
    path = pathlib.Path(text).expanduser()
    if not text.strip() or not path.exists():
        raise ParameterError(
            f"Brush {text!r} is neither a shipped brush ({', '.join(SHIPPED_BRUSHES)}) nor an existing image file.")
    from ..files.reading import read_gray  # OpenImageIO loads only when a brush file is used
    values = read_gray(path, max_megapixels=max_megapixels)
    if not np.any(values > 0):
        raise InputError(f"Brush image {path} has no bristles: every pixel is black.")
    return crop_to_bristles(values)


# ---------------------------------------------------------------------------
# brush tips


@dataclass(frozen=True, eq=False)
class BrushTip:
    """The bristles of a brush map resized to one stroke width.

    along, across: float32 (N,) offsets in pixels of each bristle's centre
    from the brush centre (along: + in the stroke direction; across: + along
    the stroke direction turned by +90 degrees in image coordinates).
    intensity: float32 (N,) contact in (0, 1], already times the
    transparency. width: across extent of the resized map (px); length: its
    along extent (px). N >= 1; bristles in row-major order of the resized
    map (front row first). Arrays are read-only.
    """

    along: np.ndarray
    across: np.ndarray
    intensity: np.ndarray
    width: float
    length: float

    def __len__(self) -> int:
        """Number of bristles N."""
        return int(self.intensity.shape[0])

    def mean_intensity(self) -> float:
        """Mean bristle intensity in (0, 1]."""
        return float(np.mean(self.intensity, dtype=np.float64))

    @property
    def radius(self) -> float:
        """Half the across extent (px)."""
        return self.width / 2.0


def _frozen(values: np.ndarray) -> np.ndarray:
    """Contiguous read-only float32 copy of a (N,) array."""
    out = np.array(values, dtype=np.float32)
    out.setflags(write=False)
    return out


def tip_length(brush_map_shape, width: int) -> int:
    """Along extent (px) of a tip ``width`` px wide: max(1, round(width * rows / cols)), halves rounded up."""
    rows, cols = brush_map_shape
    return max(1, int(math.floor(width * rows / cols + 0.5)))


def resize_map(brush_map: np.ndarray, rows: int, cols: int) -> np.ndarray:
    """Bicubic resize of a (r, c) map to (rows, cols), float32 clipped to [0, 1].

    Pixel centres are aligned (output pixel i samples input position
    (i + 0.5) * r / rows - 0.5); edges extend the border pixels, so a
    constant map stays constant. When an axis shrinks by a factor f > 1 the
    map is first blurred along it by a Gaussian of sigma (f - 1) / 2 input
    pixels (anti-aliasing; edges reflected), so small tips keep the map's average contact
    instead of point samples of its noise. The cubic spline interpolation is
    ``scipy.ndimage.map_coordinates(order=3)`` with its prefilter.
    """
    src = np.asarray(brush_map, dtype=np.float64)
    r, c = src.shape
    factors = (r / rows, c / cols)
    sigma = [max(0.0, (f - 1.0) / 2.0) for f in factors]
    if any(s > 0 for s in sigma):
        src = ndimage.gaussian_filter(src, sigma=sigma, mode="reflect")
    ys = (np.arange(rows) + 0.5) * factors[0] - 0.5
    xs = (np.arange(cols) + 0.5) * factors[1] - 0.5
    grid = np.meshgrid(ys, xs, indexing="ij")
    out = ndimage.map_coordinates(src, grid, order=3, mode="nearest", prefilter=True)
    return np.clip(out, 0.0, 1.0).astype(np.float32)


def keep_contact(resized: np.ndarray, brush_map: np.ndarray) -> np.ndarray:
    """``resized`` scaled so its 90th-percentile bristle contact is the map's, clipped to [0, 1].

    Shrinking a map averages each column's ragged, fading ends into its few
    remaining rows, so a one-row tip would press less than the brush it
    comes from; this restores the contact level and keeps the columns'
    differences (streaks).
    """
    source = brush_map[brush_map > 0]
    target = resized[resized > BRISTLE_THRESHOLD]
    if source.size == 0 or target.size == 0:
        return resized
    scale = float(np.percentile(source, 90)) / max(float(np.percentile(target, 90)), 1e-6)
    return np.clip(resized * np.float32(max(scale, 1.0)), 0.0, 1.0).astype(np.float32)


def _check_tip_args(brush_map: np.ndarray, width, transparency: float) -> int:
    """Validate brush_tip's arguments; return the width as a whole number of pixels >= 1."""
    if brush_map.ndim != 2 or brush_map.size == 0 or not np.all(np.isfinite(brush_map)):
        raise ValueError(f"A brush map must be a finite 2-D array, got shape {brush_map.shape}.")
    if not np.any(brush_map > 0):
        raise ValueError("A brush map needs at least one pixel > 0.")
    if not (isinstance(width, (int, float, np.integer, np.floating)) and math.isfinite(width) and width >= 0.5):
        raise ParameterError(f"The brush width must be at least 1 pixel, got {width}.")
    if not 0.0 < transparency <= 1.0:
        raise ParameterError(f"The transparency factor must be in (0, 1], got {transparency}.")
    return max(1, int(math.floor(float(width) + 0.5)))


def brush_tip(brush_map: np.ndarray, width: int, transparency: float) -> BrushTip:
    """Bristles of ``brush_map`` resized to ``width`` pixels across.

    brush_map: float32 (rows, cols) in [0, 1] with a pixel > 0.
    width: stroke width in pixels (rounded to a whole number >= 1); the
    resized map is width px across and ``tip_length`` = max(1,
    round(width * rows / cols)) px along (aspect kept). transparency in
    (0, 1] multiplies every intensity. A tip much shorter than the map keeps
    the map's contact (``keep_contact``). Resized pixels > 1e-3 are the
    bristles, offset from the centre of the resized map by their pixel
    centres: across = (j + 0.5) - width / 2, along = length / 2 - (i + 0.5)
    (row 0 is the front). A 1-pixel tip, or one where no pixel survives, is
    a single bristle at offset (0, 0) with the map's mean non-zero intensity
    times transparency. Raises ParameterError for a width below 1 or a
    transparency outside (0, 1].
    """
    values = np.asarray(brush_map, dtype=np.float32)
    w = _check_tip_args(values, width, transparency)
    length = tip_length(values.shape, w)
    resized = keep_contact(resize_map(values, length, w), values) * np.float32(transparency) if w > 1 else None
    if resized is None or not np.any(resized > BRISTLE_THRESHOLD):
        contact = float(values[values > 0].mean(dtype=np.float64)) * transparency
        zero = np.zeros(1, np.float32)
        return BrushTip(_frozen(zero), _frozen(zero), _frozen([contact]), float(w), float(length))
    i, j = np.nonzero(resized > BRISTLE_THRESHOLD)            # row-major order
    along = length / 2.0 - (i + 0.5)
    across = (j + 0.5) - w / 2.0
    return BrushTip(_frozen(along), _frozen(across), _frozen(resized[i, j]), float(w), float(length))


def tip_cache(brush_map: np.ndarray, widths: Iterable[int], transparency: float) -> Dict[int, BrushTip]:
    """{width: brush_tip(brush_map, width, transparency)} for each standard stroke width (px)."""
    return {int(w): brush_tip(brush_map, int(w), transparency) for w in widths}
