"""The canvas being painted: colour, coverage, height and opacity (ALGORITHM §3, §5, §6)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .compositing import Footprint


@dataclass
class Canvas:
    """Painted state of an (H, W) canvas.

    colour:   float32 (H, W, 3) sRGB [0, 1]; starts as the canvas colour.
    coverage: float32 (H, W) [0, 1]; 1 - prod(1 - I) of every bristle that touched a pixel.
    height:   float32 (H, W) >= 0; paint height, 1 = one full bristle's contact.
    opacity:  float32 (H, W) [0, 1]; accumulated stroke opacity.
    """

    colour: np.ndarray
    coverage: np.ndarray
    height: np.ndarray
    opacity: np.ndarray

    @classmethod
    def blank(cls, shape: tuple, canvas_colour) -> "Canvas":
        """A bare canvas of (H, W) = ``shape`` in ``canvas_colour`` (sRGB triple)."""
        h, w = shape
        colour = np.empty((h, w, 3), dtype=np.float32)
        colour[...] = np.asarray(canvas_colour, dtype=np.float32)
        zeros = lambda: np.zeros((h, w), dtype=np.float32)  # noqa: E731
        return cls(colour, zeros(), zeros(), zeros())

    def apply(self, footprint: Footprint, height_mode: str, build: float) -> None:
        """Lay one stroke's footprint on the canvas (ALGORITHM §6).

        Colour by Eq. 4 (folded); coverage as the same stroke painted in white.
        The stroke's opacity o = a f, with a = 1 - transmittance its colour
        alpha and f = min(1, deposit / deposit_90) how fully its paint covers
        (deposit_90 the stroke's 90th-percentile deposit), so the opacity
        follows the bristles' real footprint and fades with them at the edges
        and ends. Height, with h the stroke's height:
        'over'        H <- H + o h - o f H          (= o h + (1 - o) H where f = 1),
        'accumulate'  H <- H + o h - o f (1 - b) H  (= o (h + b H) + (1 - o) H where f = 1),
        b = ``build`` in [0, 1). Where the stroke covers fully this is the
        paper's weighted sum (or bounded build-up: H tends to h / (1 - b)
        under repeated strokes); at its feathered edges and ends, where f < 1,
        the thin paint lies on the old instead of replacing it, so a stroke
        never digs a groove into the paint beneath. Opacity A = o + (1 - o) A.
        """
        keep = footprint.transmittance
        if keep.size == 0:
            return
        box = (slice(footprint.top, footprint.top + keep.shape[0]), slice(footprint.left, footprint.left + keep.shape[1]))
        colour = self.colour[box]
        colour *= keep[..., None]
        colour += footprint.paint
        alpha = 1.0 - keep
        coverage = self.coverage[box]
        coverage += alpha * (1.0 - coverage)
        deposit = footprint.deposit
        full = percentile_90(deposit[footprint.touched])
        fullness = np.minimum(deposit / full, np.float32(1.0)) if full > 0 else np.zeros_like(deposit)
        o = alpha * fullness
        loss = np.float32(1.0 if height_mode != "accumulate" else 1.0 - build)
        height = self.height[box]
        height += o * (footprint.height - fullness * loss * height)
        np.maximum(height, 0.0, out=height)
        opacity = self.opacity[box]
        opacity += o * (1.0 - opacity)


def percentile_90(values: np.ndarray) -> np.float32:
    """The 90th percentile of (N,) float32 ``values`` (linear between order statistics, as np.percentile), 0 if empty."""
    n = values.size
    if n == 0:
        return np.float32(0.0)
    position = 0.9 * (n - 1)
    below = int(position)
    above = min(below + 1, n - 1)
    ordered = np.partition(values, (below, above))
    return np.float32(ordered[below] + (ordered[above] - ordered[below]) * (position - below))
