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
        top, left = footprint.top, footprint.left
        box = (slice(top, top + keep.shape[0]), slice(left, left + keep.shape[1]))
        colour = self.colour[box]
        for ch in range(3):                      # a plane at a time: a broadcast over 3 channels is slow
            colour[..., ch] *= keep
        colour += footprint.paint
        alpha = 1.0 - keep
        scratch = np.subtract(1.0, self.coverage[box])
        scratch *= alpha
        self.coverage[box] += scratch
        deposit = footprint.deposit
        full = percentile_90(deposit)
        if full <= 0:
            return
        fullness = np.multiply(deposit, np.float32(1.0 / full))
        np.minimum(fullness, np.float32(1.0), out=fullness)
        o = np.multiply(alpha, fullness, out=alpha)                  # the stroke's opacity (alpha is done)
        loss = np.float32(1.0 if height_mode != "accumulate" else 1.0 - build)
        height = self.height[box]
        fullness *= loss
        fullness *= height
        np.subtract(footprint.height, fullness, out=fullness)
        fullness *= o
        height += fullness
        np.maximum(height, 0.0, out=height)
        opacity = self.opacity[box]
        np.subtract(1.0, opacity, out=scratch)
        scratch *= o
        opacity += scratch


def percentile_90(values: np.ndarray) -> np.float32:
    """The 90th percentile of the positive entries of ``values`` (any shape, >= 0), linear between order
    statistics as np.percentile; 0 when none is positive.

    The zeros are the smallest entries, so the percentile is an order
    statistic of the whole array: no copy of the positive entries is needed.
    """
    n = int(np.count_nonzero(values))
    if n == 0:
        return np.float32(0.0)
    position = 0.9 * (n - 1)
    below = int(position)
    at = values.size - n + below
    ordered = np.partition(values.ravel(), at)
    low = ordered[at]
    high = ordered[at + 1:].min() if below + 1 < n else low    # the next order statistic
    return np.float32(low + (high - low) * (position - below))
