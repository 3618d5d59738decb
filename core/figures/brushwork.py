"""The brushwork figure: crops of paintings at 1:1 and 3x, with their relief under a raking light."""

from __future__ import annotations

import math
from typing import Sequence, Tuple

import numpy as np

from ..lighting import bump_lighting
from .sheet import contact_sheet

RAKING_ELEVATION = math.radians(20.0)
RAKING_AZIMUTH = math.radians(225.0)
RELIEF_GRAY = (0.7, 0.7, 0.7)


def raking_light(height: np.ndarray, relief: float = 4.0) -> np.ndarray:
    """(H, W, 3) float32 sRGB: a gray canvas with relief ``height`` (H, W) lit from the upper left at 20 degrees."""
    gray = np.empty(height.shape + (3,), np.float32)
    gray[...] = RELIEF_GRAY
    return bump_lighting(gray, height, RAKING_AZIMUTH, RAKING_ELEVATION, relief, specular=0.0)


def crop(image: np.ndarray, box: Tuple[int, int, int, int]) -> np.ndarray:
    """image[y0:y1, x0:x1] for box (x0, y0, x1, y1), clamped to the image."""
    x0, y0, x1, y1 = box
    h, w = image.shape[:2]
    return image[max(0, y0):min(h, y1), max(0, x0):min(w, x1)]


def enlarge(image: np.ndarray, factor: int) -> np.ndarray:
    """Each pixel of an (h, w[, c]) image repeated ``factor`` x ``factor`` times (nearest neighbour)."""
    return np.repeat(np.repeat(image, factor, axis=0), factor, axis=1)


def brushwork_sheet(paintings: Sequence[Tuple[str, np.ndarray, np.ndarray]], box: Tuple[int, int, int, int],
                    zoom: int = 3, panel_height: int = 240) -> np.ndarray:
    """(H, W, 3) float32 sRGB sheet: for each (name, colour (H, W, 3) sRGB, height (H, W)) a row of
    four panels: the crop ``box`` (x0, y0, x1, y1) at 1:1 and its centre at ``zoom``x, of the painting
    and of its height map under a raking light. Crops are shown pixel for pixel (the 1:1 box should be
    ``panel_height`` px tall)."""
    x0, y0, x1, y1 = box
    cw, ch = (x1 - x0) // zoom, (y1 - y0) // zoom
    cx, cy = x0 + (x1 - x0 - cw) // 2, y0 + (y1 - y0 - ch) // 2
    centre = (cx, cy, cx + cw, cy + ch)
    panels = []
    for name, colour, height in paintings:
        lit = raking_light(height)
        panels += [(f"{name}: painting 1:1", crop(colour, box)),
                   (f"{name}: painting {zoom}x", enlarge(crop(colour, centre), zoom)),
                   (f"{name}: relief 1:1", crop(lit, box)),
                   (f"{name}: relief {zoom}x", enlarge(crop(lit, centre), zoom))]
    return contact_sheet(panels, panel_height=panel_height, columns=4)
