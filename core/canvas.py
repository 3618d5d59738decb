"""The canvas being painted: colour, coverage, height and opacity (ALGORITHM §3, §5, §6)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .compositing import Footprint, band_opacity


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

    def apply(self, footprint: Footprint, band_width: float, height_mode: str, build: float) -> None:
        """Lay one stroke's footprint on the canvas.

        Colour by Eq. 4 (folded), coverage as the same stroke painted in white,
        stroke opacity o from an anti-aliased band ``band_width`` px wide, and
        height H = o h + (1 - o) H ('over') or H = H + o h build ('accumulate');
        opacity A = o + (1 - o) A.
        """
        p = footprint.pixels
        if p.size == 0:
            return
        colour = self.colour.reshape(-1, 3)
        keep = footprint.transmittance
        colour[p] = (colour[p] * keep[:, None] + footprint.paint).astype(np.float32)
        coverage = self.coverage.reshape(-1)
        coverage[p] = 1.0 - (1.0 - coverage[p]) * keep
        o = band_opacity(footprint.distance, band_width)
        height = self.height.reshape(-1)
        if height_mode == "accumulate":
            height[p] += o * footprint.height * build
        else:
            height[p] = o * footprint.height + (1.0 - o) * height[p]
        opacity = self.opacity.reshape(-1)
        opacity[p] = o + (1.0 - o) * opacity[p]
