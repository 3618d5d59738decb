"""Lighting a painting from its height field, in 2-D (ALGORITHM §7 and §8).

Three models, all arrays in, arrays out:

- ``paper``: the paper's Eq. 6-7. Brightness follows the height slope
  across each stroke (d = O - pi/2), so the "light" turns with the strokes.
- ``directional``: the same formula with one fixed light azimuth, so every
  slope facing the light brightens whatever the strokes do.
- ``bump``: Blinn-Phong shading of the height field seen as a bump map, with
  one directional light, in the manner of Hertzmann 2002 ("Fast paint
  texture"), computed in linear light.

Conventions (as everywhere in core/): colour is float32 (H, W, 3) sRGB in
[0, 1]; height is float32 (H, W) (or (H, W, 1)), dimensionless, 1 = one full
bristle's contact; x is the column, y the row (downwards); angles are
radians measured from +x towards +y, so on screen they turn clockwise.
A light azimuth phi is the direction from the canvas *towards* the light:
phi = 0 is a light on the right (+x), phi = -pi/2 a light at the top.
"""

from __future__ import annotations

import math
from typing import Optional

import numpy as np

from ..colour import linear_to_srgb, srgb_to_linear
from ..errors import ParameterError

MODELS = ("paper", "directional", "bump")

PAPER_STRENGTH = 1.0
"""Default a of Eq. 7. Chosen by eye on coffee.png (400 x 600, default
parameters): with a = 1 a mid-grey pixel moves by D intensity levels, i.e.
about 4 levels on the median bristle slope, 14 at the 90th and ~45 at the
99th percentile (stroke rims), which shows the bristle ridges clearly
without flattening colour; a = 0.5 was subtle, a = 2 made the ridges look
engraved and speckled the rims."""

DIRECTIONAL_STRENGTH = PAPER_STRENGTH
"""Default a of the directional variant: the same scale as the paper's."""

DEFAULT_AZIMUTH = math.radians(225.0)
"""Light from the upper left (the painters' and illustrators' convention):
(cos, sin) = (-0.71, -0.71), i.e. towards -x and up the image."""

DEFAULT_ELEVATION = math.radians(35.0)
"""A raking light, 35 degrees above the canvas: low enough that the relief
reads, high enough that few slopes fall fully into shadow."""

DEFAULT_RELIEF = 4.0
"""Pixel widths per height unit for normals and bump shading, chosen by eye
on coffee.png (400 x 600, default parameters): the surface tilts by a median
4 degrees, 12.5 at the 90th and 36 at the 99th percentile (bristle ridges and
stroke rims), a clearly visible bump. 3 is already visible; 6 looks carved;
12 looks like embossed metal."""

BUMP_AMBIENT = 0.35
BUMP_DIFFUSE = 0.65
"""ambient + diffuse = 1 and the diffuse term is divided by sin(elevation),
so a flat canvas is lit by exactly 1 x its colour."""
BUMP_SPECULAR = 0.03
BUMP_SHININESS = 60.0
"""A faint white Blinn highlight on the steepest rims (wet oil paint). Chosen
by eye on coffee.png: 0.08 with shininess 40 greyed the dark areas with
glints; 0.03 / 60 keeps them dark. A flat canvas gets
specular * cos^n((90 deg - elevation) / 2) on top of its colour:
0.03 * cos(27.5 deg)^60 = 2.3e-05 in linear light at the default elevation."""


# ---------------------------------------------------------------------------
# helpers


def _height2d(height: np.ndarray) -> np.ndarray:
    """(H, W) or (H, W, 1) -> float32 (H, W)."""
    h = np.asarray(height, dtype=np.float32)
    if h.ndim == 3 and h.shape[2] == 1:
        h = h[:, :, 0]
    if h.ndim != 2:
        raise ParameterError(f"The height map must be an (H, W) array, got shape {h.shape}.")
    return h


def _check_colour(colour: np.ndarray, shape: tuple) -> np.ndarray:
    """float32 (H, W, 3) colour matching ``shape`` = (H, W); ParameterError otherwise."""
    c = np.asarray(colour, dtype=np.float32)
    if c.ndim != 3 or c.shape[2] != 3:
        raise ParameterError(f"The colour must be an (H, W, 3) array, got shape {c.shape}.")
    if c.shape[:2] != shape:
        raise ParameterError(f"The colour is {c.shape[1]} x {c.shape[0]} pixels but the height map is "
                             f"{shape[1]} x {shape[0]}.")
    return c


def sample_bilinear(field: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Bilinear samples of (H, W) ``field`` at float positions ``x`` (column), ``y`` (row).

    Positions are clamped to the image ([0, W-1], [0, H-1]), which is the
    same as extending the border pixels outwards. Returns float32 of x's shape.
    """
    h, w = field.shape
    x = np.clip(x, 0.0, w - 1).astype(np.float32, copy=False)
    y = np.clip(y, 0.0, h - 1).astype(np.float32, copy=False)
    x0 = np.floor(x)
    y0 = np.floor(y)
    fx = x - x0
    fy = y - y0
    x0 = x0.astype(np.intp)
    y0 = y0.astype(np.intp)
    x1 = np.minimum(x0 + 1, w - 1)
    y1 = np.minimum(y0 + 1, h - 1)
    flat = field.ravel()
    r0 = y0 * w
    r1 = y1 * w
    top = flat[r0 + x0] * (1 - fx) + flat[r0 + x1] * fx
    bottom = flat[r1 + x0] * (1 - fx) + flat[r1 + x1] * fx
    return (top * (1 - fy) + bottom * fy).astype(np.float32, copy=False)


def height_difference(height: np.ndarray, direction) -> np.ndarray:
    """Eq. 6: D(x, y) = h(x + cos d, y + sin d) - h(x, y) on the 0-255 scale.

    height (H, W) in height units (multiplied by 255 here); direction d is a
    scalar or an (H, W) array of radians. Bilinear sampling, clamped at the
    borders. Returns float32 (H, W).
    """
    h = _height2d(height) * np.float32(255.0)
    rows, cols = h.shape
    d = np.asarray(direction, dtype=np.float32)
    dx = np.cos(d)
    dy = np.sin(d)
    x = np.arange(cols, dtype=np.float32)[None, :] + dx
    y = np.arange(rows, dtype=np.float32)[:, None] + dy
    x, y = np.broadcast_arrays(x, y)
    return sample_bilinear(h, x, y) - h


def adjust_intensity(colour: np.ndarray, difference: np.ndarray, strength: float) -> np.ndarray:
    """Eq. 7: I' = I + a D min(I, 255 - I) / 127.5 per channel, clipped, on the 0-255 scale.

    colour (H, W, 3) sRGB [0, 1]; difference (H, W) D on the 0-255 scale.
    Returns float32 (H, W, 3) sRGB [0, 1]. The change is largest at I = 127.5
    and vanishes at I = 0 and I = 255.
    """
    i = np.asarray(colour, dtype=np.float32) * np.float32(255.0)
    gain = np.float32(strength / 127.5) * np.asarray(difference, dtype=np.float32)[:, :, None]
    out = i + gain * np.minimum(i, np.float32(255.0) - i)
    return (np.clip(out, 0.0, 255.0) / np.float32(255.0)).astype(np.float32)


def _check_strength(strength: float) -> float:
    """A finite, non-negative strength; ParameterError otherwise."""
    if not (math.isfinite(strength) and strength >= 0):
        raise ParameterError(f"The lighting strength must be a number >= 0, got {strength}.")
    return float(strength)


# ---------------------------------------------------------------------------
# the models


def paper_lighting(colour: np.ndarray, height: np.ndarray, orientation: np.ndarray,
                   strength: float = PAPER_STRENGTH) -> np.ndarray:
    """The paper's lighting (Eq. 6-7, ALGORITHM §7).

    colour (H, W, 3) sRGB [0, 1]; height (H, W) height units (1 = full
    bristle contact, scaled by 255 internally); orientation (H, W) stroke
    direction O in radians; strength a (default ``PAPER_STRENGTH``).
    With d = O - pi/2, D = h(x + cos d, y + sin d) - h(x, y) (bilinear) and
    I' = I + a D min(I, 255 - I) / 127.5 per channel, clipped to [0, 255].
    Returns float32 (H, W, 3) sRGB [0, 1].
    """
    h = _height2d(height)
    c = _check_colour(colour, h.shape)
    o = np.asarray(orientation, dtype=np.float32)
    if o.ndim == 3 and o.shape[2] == 1:
        o = o[:, :, 0]
    if o.shape != h.shape:
        raise ParameterError(f"The orientation field has shape {o.shape} but the height map {h.shape}.")
    d = o - np.float32(math.pi / 2)
    return adjust_intensity(c, height_difference(h, d), _check_strength(strength))


def directional_lighting(colour: np.ndarray, height: np.ndarray, azimuth: float = DEFAULT_AZIMUTH,
                         strength: float = DIRECTIONAL_STRENGTH) -> np.ndarray:
    """Eq. 6-7 with one fixed light instead of the stroke-following direction.

    colour (H, W, 3) sRGB [0, 1]; height (H, W) height units; azimuth phi in
    radians, the direction from the canvas towards the light (0 = light on
    the right, +x; angles from +x towards +y, y down); strength a.
    Sign: D is sampled *away* from the light, d = phi + pi, so
    D = h(p - l) - h(p) with l = (cos phi, sin phi). A slope facing the
    light (height falling towards the light, rising away from it) has D > 0
    and brightens; a slope facing away darkens. Returns float32 (H, W, 3).
    """
    h = _height2d(height)
    c = _check_colour(colour, h.shape)
    if not math.isfinite(azimuth):
        raise ParameterError(f"The light azimuth must be a finite number, got {azimuth}.")
    return adjust_intensity(c, height_difference(h, azimuth + math.pi), _check_strength(strength))


def normal_map(height: np.ndarray, relief: float = DEFAULT_RELIEF) -> np.ndarray:
    """Unit surface normals of the height field, tangent space as Blender's Normal Map node reads it.

    height (H, W) height units; relief = pixel widths per height unit, so
    the surface is z = relief * h in pixel units and its slopes are
    relief * dh/dx per pixel (central differences, one-sided at the borders).
    Returns float32 (H, W, 3) unit vectors in the OpenGL convention:
    X = image right (+column), Y = image UP (-row), Z = out of the canvas:
    N = normalize(-relief dh/dcol, +relief dh/drow, 1).
    """
    if not (math.isfinite(relief) and relief >= 0):
        raise ParameterError(f"The relief must be a number >= 0, got {relief}.")
    h = _height2d(height)
    rows, cols = h.shape
    s = np.float32(relief)
    d_row = np.gradient(h, axis=0) if rows > 1 else np.zeros_like(h)
    d_col = np.gradient(h, axis=1) if cols > 1 else np.zeros_like(h)
    n = np.empty((rows, cols, 3), dtype=np.float32)
    n[:, :, 0] = -s * d_col
    n[:, :, 1] = s * d_row
    n[:, :, 2] = 1.0
    n /= np.sqrt(np.einsum("ijk,ijk->ij", n, n))[:, :, None]
    return n


def encode_normals(normals: np.ndarray) -> np.ndarray:
    """Unit normals in [-1, 1] -> colour data in [0, 1] as n * 0.5 + 0.5 (float32, same shape)."""
    return (np.asarray(normals, dtype=np.float32) * np.float32(0.5) + np.float32(0.5)).astype(np.float32)


def light_vector(azimuth: float, elevation: float) -> np.ndarray:
    """Unit vector towards the light in the normal map's frame (X right, Y up, Z out).

    azimuth in image coordinates (radians from +x towards +y, y down),
    elevation in radians above the canvas: (cos e cos phi, -cos e sin phi, sin e).
    """
    ce = math.cos(elevation)
    return np.array([ce * math.cos(azimuth), -ce * math.sin(azimuth), math.sin(elevation)], dtype=np.float32)


def bump_lighting(colour: np.ndarray, height: np.ndarray, azimuth: float = DEFAULT_AZIMUTH,
                  elevation: float = DEFAULT_ELEVATION, relief: float = DEFAULT_RELIEF,
                  ambient: float = BUMP_AMBIENT, diffuse: float = BUMP_DIFFUSE,
                  specular: float = BUMP_SPECULAR, shininess: float = BUMP_SHININESS) -> np.ndarray:
    """Blinn-Phong bump shading with one directional light (Hertzmann 2002, ALGORITHM §8).

    colour (H, W, 3) sRGB [0, 1]; height (H, W) height units; azimuth
    (radians, image coordinates, towards the light) and elevation (radians
    above the canvas, in (0, pi/2]); relief as in ``normal_map``.
    In linear light c = srgb_to_linear(colour), with N from ``normal_map``,
    L from ``light_vector``, V = (0, 0, 1), H = normalize(L + V):

        out = c (ambient + diffuse max(N.L, 0) / sin(elevation)) + specular max(N.H, 0)^shininess

    The division by sin(elevation) normalises a flat canvas (N.L = sin e) to
    (ambient + diffuse) x its colour, i.e. exactly its colour with the
    defaults (ambient + diffuse = 1), plus the flat highlight
    specular cos^shininess((pi/2 - e) / 2) (see BUMP_SHININESS). The result
    goes back through the sRGB curve (clipped to [0, 1]): float32 (H, W, 3).
    """
    h = _height2d(height)
    c = _check_colour(colour, h.shape)
    if not (math.isfinite(azimuth) and math.isfinite(elevation)):
        raise ParameterError("The light azimuth and elevation must be finite numbers.")
    if not (0.0 < elevation <= math.pi / 2 + 1e-9):
        raise ParameterError(f"The light elevation must be above 0 and at most 90 degrees, "
                             f"got {math.degrees(elevation):g}.")
    n = normal_map(h, relief)
    lv = light_vector(azimuth, elevation)
    half = lv + np.array([0.0, 0.0, 1.0], dtype=np.float32)
    half /= np.linalg.norm(half)
    n_dot_l = np.maximum(n @ lv, 0.0)
    shade = np.float32(ambient) + np.float32(diffuse / math.sin(elevation)) * n_dot_l
    out = srgb_to_linear(c) * shade[:, :, None]
    if specular:
        out += (np.float32(specular) * np.maximum(n @ half, 0.0) ** np.float32(shininess))[:, :, None]
    return linear_to_srgb(out)


def default_strength(model: str) -> float:
    """The default ``strength`` of ``light`` for a model: a of Eq. 7, or the relief for 'bump'."""
    return {"paper": PAPER_STRENGTH, "directional": DIRECTIONAL_STRENGTH, "bump": DEFAULT_RELIEF}[check_model(model)]


def check_model(model: str) -> str:
    """``model`` if it is one of MODELS; ParameterError (one sentence) otherwise."""
    if model not in MODELS:
        raise ParameterError(f"Unknown lighting model '{model}'; choose paper, directional or bump.")
    return model


def light(model: str, colour: np.ndarray, height: np.ndarray, orientation: Optional[np.ndarray] = None,
          azimuth: float = DEFAULT_AZIMUTH, elevation: float = DEFAULT_ELEVATION,
          strength: Optional[float] = None) -> np.ndarray:
    """Light a painting with one of MODELS; returns float32 (H, W, 3) sRGB [0, 1].

    colour (H, W, 3) sRGB [0, 1]; height (H, W); orientation (H, W) radians
    (needed by 'paper' only); azimuth, elevation in radians (azimuth: all but
    'paper'; elevation: 'bump' only). ``strength`` (None = the model's
    default): a of Eq. 7 for 'paper' and 'directional', the relief (pixel
    widths per height unit) for 'bump'. Unknown models raise ParameterError.
    """
    check_model(model)
    if strength is None:
        strength = default_strength(model)
    if model == "paper":
        if orientation is None:
            raise ParameterError("The paper's lighting needs the orientation field.")
        return paper_lighting(colour, height, orientation, strength)
    if model == "directional":
        return directional_lighting(colour, height, azimuth, strength)
    return bump_lighting(colour, height, azimuth, elevation, relief=_check_strength(strength))
