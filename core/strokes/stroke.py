"""Paint strokes: their record, bristle colours (Eq. 5), end and ridge profiles (ALGORITHM §5)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, Iterable, NamedTuple

import numpy as np

from ..colour import lab_to_srgb, srgb_to_lab
from ..params import Params
from ..workers import run_all
from .brush import BrushTip, smoothstep
from .smoothing import SmoothedImage, smooth, smoothing_cost

# A stroke covers as a brush at least this many rows long would: a short tip (small brushes have one or
# two rows) is counted as passing that many times, so small strokes are as opaque as large ones.
MIN_ROWS = 4.0

# Contact left at the very tip of a stroke's ends (the brush lifting off), as a fraction of full contact.
LIFT_FLOOR = 0.3


@dataclass
class Stroke:
    """A painted stroke as recorded in ``strokes.json``.

    layer: 0-based layer (the detail pass is the layer after the last).
    anchor: (x, y) pixel. size: brush width (px). path: (K, 2) float32 (x, y)
    points of the kept path: its ends and the control points between them.
    colour: sRGB anchor colour (3,).
    """

    layer: int
    anchor: tuple
    size: int
    path: np.ndarray
    colour: np.ndarray

    def to_dict(self) -> dict:
        """JSON-ready form."""
        return {"layer": self.layer, "anchor": [int(self.anchor[0]), int(self.anchor[1])], "size": int(self.size),
                "path": np.round(self.path, 2).tolist(), "colour": np.round(self.colour, 4).tolist()}


@dataclass(frozen=True)
class ColourSources:
    """Where the strokes of one brush width take their colours (ALGORITHM §5).

    reference: float32 (H, W, 3) sRGB [0, 1], the bilateral reference.
    edges: the reference smoothed at the brush's scale (the path's edge and colour tests).
    anchor: the reference smoothed for the anchor colour of Eq. 5.
    bristles: the reference lightly smoothed (each bristle's own colour).
    deviation: how far a bristle's own colour may stray from the anchor colour
    (Euclidean RGB), or None for ``Params.bristle_deviation``.
    """

    reference: np.ndarray
    edges: SmoothedImage
    anchor: SmoothedImage
    bristles: SmoothedImage
    deviation: float = None


def colour_sources(reference: np.ndarray, sizes: Iterable[int], params: Params) -> Dict[int, ColourSources]:
    """{width: ColourSources} for each brush width (px): sigmas edge_smoothing, anchor_smoothing and
    bristle_smoothing x width (equal sigmas share one smoothed image), the costliest first on the worker threads."""
    sigmas = {int(s): (params.edge_smoothing * s, params.anchor_smoothing * s, params.bristle_smoothing * s)
              for s in sizes}
    distinct = sorted({sigma for three in sigmas.values() for sigma in three}, key=smoothing_cost, reverse=True)
    levels = dict(zip(distinct, run_all(lambda sigma: smooth(reference, sigma), distinct), strict=True))
    return {s: ColourSources(reference, *(levels[sigma] for sigma in three)) for s, three in sigmas.items()}


def detail_sources(reference: np.ndarray) -> ColourSources:
    """ColourSources of the detail pass: the reference itself, one colour per stroke, so a dotted
    highlight keeps its full colour."""
    exact = smooth(reference, 0.0)
    return ColourSources(reference, exact, exact, exact, deviation=0.0)


class ColourJitter(NamedTuple):
    """N strokes' random colour changes (Eq. 5)."""

    shift: np.ndarray           # float64 (N,) CIELAB L* offsets
    offset: np.ndarray          # float32 (N, 3) RGB offsets


def colour_jitter(draws: np.ndarray, lightness: float, hue: float) -> ColourJitter:
    """N strokes' random colour changes of Eq. 5 from their (N, 4) uniform ``draws`` in [0, 1).

    The lightness offset ``shift`` is 100 U(-lightness, lightness) CIELAB L*
    units (a* and b* are kept, so hue and chroma stay); when ``hue`` > 0 the
    RGB ``offset`` adds U(-hue, hue) to each channel (hue jitter), else it is 0.
    """
    draws = np.asarray(draws, np.float64).reshape(-1, 4)
    shift = 100.0 * lightness * (2.0 * draws[:, 0] - 1.0)
    offset = (hue * (2.0 * draws[:, 1:4] - 1.0)).astype(np.float32)
    return ColourJitter(shift, offset)


class BristleColours(NamedTuple):
    """The colours N strokes of a brush of B bristles paint with (Eq. 5)."""

    bristles: np.ndarray        # float32 (N, B, 3) sRGB [0, 1], every bristle's colour
    anchor: np.ndarray          # float32 (N, 3) sRGB, C_anchor: ``sources.anchor`` at each anchor


def bristle_colours(sources: ColourSources, anchors: np.ndarray, angles: np.ndarray, tip: BrushTip, alpha: float,
                    deviation: float, shift: np.ndarray, offset: np.ndarray,
                    lightness: bool = True) -> BristleColours:
    """Eq. 5 for N strokes: the colour of every bristle of ``tip`` and the anchor colours.

    Each brush is centred on its anchor (``anchors`` (N, 2) (x, y)) and
    turned to its angle (``angles`` (N,), its along axis). C_anchor is
    ``sources.anchor`` at the anchor; each bristle samples
    ``sources.bristles`` under it (bilinear) and C = C_anchor + d, with
    d = alpha (C_bristle - C_anchor) shortened to at most ``deviation``
    (Euclidean RGB), then moved by the stroke's L* offset ``shift`` (N,)
    (through CIELAB, when ``lightness``) and RGB ``offset`` (N, 3), clipped to
    [0, 1]. So an anchor on a star or a glint neither tints the stroke nor
    drags it along as a scratch.
    """
    anchors = np.asarray(anchors, np.float64).reshape(-1, 2)
    c, s = np.cos(angles)[:, None], np.sin(angles)[:, None]
    x = anchors[:, 0:1] + tip.along * c - tip.across * s
    y = anchors[:, 1:2] + tip.along * s + tip.across * c
    at_anchor = sources.anchor.sample(anchors[:, 0], anchors[:, 1])
    d = np.float32(alpha) * (sources.bristles.sample(x, y) - at_anchor[:, None, :])
    norm = np.sqrt(np.sum(d * d, axis=2, keepdims=True))
    d *= np.minimum(np.float32(1.0), np.float32(deviation) / np.maximum(norm, np.float32(1e-12)))
    mixed = at_anchor[:, None, :] + d
    if lightness:
        lab = srgb_to_lab(mixed.reshape(-1, 3))
        lab[:, 0] += np.repeat(shift, d.shape[1])
        mixed = lab_to_srgb(lab).reshape(d.shape)
    mixed = mixed + offset[:, None, :]
    return BristleColours(np.clip(mixed, 0.0, 1.0).astype(np.float32), at_anchor)


class EndProfile(NamedTuple):
    """What S stamps of strokes press and build where the brush touches down and lifts off."""

    contact: np.ndarray         # float32 (S,) in (0, 1], the brush's pressure
    relief: np.ndarray          # float32 (S,) >= 1, the factor on the height the stamp builds


def end_profile(arc: np.ndarray, total: np.ndarray, width: float, taper: float, buildup: float) -> EndProfile:
    """The contact and relief of stamps at arc lengths ``arc`` (S,) px along strokes ``total`` (S,) px long
    (each stamp's own stroke's length).

    The brush lifts off over the last taper x width px (at most half the
    stroke) and touches down over the first half of that (at most a quarter
    of the stroke): the contact falls from 1 to LIFT_FLOOR at the very ends.
    Paint gathers where the brush starts to lift: relief 1 + buildup at one
    taper length before the end, fading to 1 within half a taper length.
    """
    arc = np.asarray(arc, np.float64)
    total = np.asarray(total, np.float64)
    lift = np.minimum(taper * width, 0.5 * total)
    touch = np.minimum(0.5 * taper * width, 0.25 * total)
    to_end = total - arc
    lifting = lift > 0
    ratio = np.divide(to_end, lift, out=np.ones_like(arc), where=lifting)
    contact = np.where(lifting, LIFT_FLOOR + (1.0 - LIFT_FLOOR) * smoothstep(ratio), 1.0)
    relief = np.where(lifting, 1.0 + buildup * np.exp(-((ratio - 1.0) / 0.5) ** 2), 1.0)
    touching = touch > 0
    start = np.divide(arc, touch, out=np.ones_like(arc), where=touching)
    contact = contact * np.where(touching, LIFT_FLOOR + (1.0 - LIFT_FLOOR) * smoothstep(start), 1.0)
    return EndProfile(contact.astype(np.float32), relief.astype(np.float32))


def ridge_profile(across: np.ndarray, radius: float, ridge: float) -> np.ndarray:
    """(B,) float32 height factor of bristles at ``across`` px from the centre line of a brush ``radius`` px:
    1 in the middle, rising to 1 + ridge at the sides (paint pushed aside by the brush)."""
    t = np.abs(np.asarray(across, np.float64)) / max(radius, 1e-6)
    return (1.0 + ridge * smoothstep((t - 0.45) / 0.4)).astype(np.float32)

