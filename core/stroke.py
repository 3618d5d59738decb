"""One paint stroke: bristle colours (Eq. 5), its path, and laying it on the canvas (Eq. 4)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .brush import BrushTip
from .canvas import Canvas
from .compositing import stroke_footprint
from .params import Params
from .path import axial_difference, catmull_rom, clip_path, tangent_angles, trace_control_points


@dataclass
class Stroke:
    """A painted stroke as recorded in ``strokes.json``.

    layer: 0-based layer. anchor: (x, y) pixel. size: brush width (px).
    path: (K, 2) float32 (x, y) points of the kept path: its ends and the
    control points between them. colour: sRGB anchor colour (3,).
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


def nearest_pixels(shape: tuple, x: np.ndarray, y: np.ndarray) -> tuple:
    """(rows, columns) int arrays of the pixels nearest float positions x, y, clamped to an (H, W) canvas."""
    h, w = shape[:2]
    ix = np.minimum(np.maximum(np.floor(x + 0.5), 0), w - 1).astype(np.intp)
    iy = np.minimum(np.maximum(np.floor(y + 0.5), 0), h - 1).astype(np.intp)
    return iy, ix


def bristle_colours(reference: np.ndarray, anchor: tuple, angle: float, tip: BrushTip, alpha: float,
                    perturbation: np.ndarray) -> np.ndarray:
    """Eq. 5: (B, 3) sRGB colour of every bristle of ``tip``.

    The brush is centred on ``anchor`` (x, y) and turned to ``angle`` (its
    along axis); each bristle samples the reference under it:
    C = alpha C_bristle + (1 - alpha) C_anchor + perturbation, clipped to [0, 1].
    """
    c, s = np.cos(angle), np.sin(angle)
    x = anchor[0] + tip.along * c - tip.across * s
    y = anchor[1] + tip.along * s + tip.across * c
    under = reference[nearest_pixels(reference.shape, x, y)]
    at_anchor = reference[anchor[1], anchor[0]]
    mixed = alpha * under + ((1.0 - alpha) * at_anchor + perturbation)
    return np.minimum(np.maximum(mixed, 0.0), 1.0).astype(np.float32)


def keep_mask(samples: np.ndarray, reference: np.ndarray, canvas_colour: np.ndarray, orientation: np.ndarray,
              brush_colour: np.ndarray, anchor_angle: float, max_turn: float) -> np.ndarray:
    """(N,) bool: where a path may go on (ALGORITHM §5 stopping rules).

    A sample fails where (a) the canvas already matches the reference better
    than the brush colour would, |ref - canvas| < |ref - brush|, or (b) the
    orientation field turns more than ``max_turn`` from the anchor's angle.
    """
    at = nearest_pixels(reference.shape, samples[:, 0], samples[:, 1])
    ref = reference[at]
    can = canvas_colour[at]
    theta = orientation[at]
    closer = np.sum((ref - can) ** 2, axis=1) < np.sum((ref - brush_colour) ** 2, axis=1)
    turned = axial_difference(theta, anchor_angle) > max_turn
    return ~(closer | turned)


def paint_stroke(canvas: Canvas, reference: np.ndarray, orientation: np.ndarray, anchor: tuple, size: int,
                 layer: int, tip: BrushTip, rng: np.random.Generator, params: Params) -> Stroke:
    """Plan one stroke from ``anchor`` (x, y) with a brush ``size`` px wide, lay it on ``canvas``, return it."""
    angle = float(orientation[anchor[1], anchor[0]])
    perturbation = rng.uniform(-params.perturbation, params.perturbation, 3).astype(np.float32)
    colours = bristle_colours(reference, anchor, angle, tip, params.bristle_alpha, perturbation)
    brush_colour = (tip.intensity @ colours) / tip.intensity.sum()

    control, anchor_index = trace_control_points(anchor, orientation, max(1.0, 0.5 * size), params.max_length)
    samples, control_index = catmull_rom(control)
    keep = keep_mask(samples, reference, canvas.colour, orientation, brush_colour, angle,
                     params.orientation_threshold)
    start_index = control_index[anchor_index]
    kept, kept_anchor = clip_path(samples, start_index, keep)
    angles = tangent_angles(kept, angle)
    footprint = stroke_footprint(kept, angles, tip.along, tip.across, tip.intensity, colours, canvas.height.shape)
    canvas.apply(footprint, params.opacity_width * size, params.height_mode, params.height_build)

    first = start_index - kept_anchor
    inner = control_index[(control_index > first) & (control_index < first + len(kept) - 1)] - first
    path = kept[np.unique(np.concatenate(([0], inner, [len(kept) - 1])))].astype(np.float32)
    return Stroke(layer, (int(anchor[0]), int(anchor[1])), int(size), path, reference[anchor[1], anchor[0]].copy())
