"""Labelled contact sheets: several pictures side by side in one image."""

from __future__ import annotations

import math
from typing import Sequence, Tuple

import numpy as np
from scipy import ndimage

from .text import draw_text

BACKGROUND = (0.12, 0.12, 0.12)
LABEL_COLOUR = (0.95, 0.95, 0.95)


def fit_height(image: np.ndarray, height: int) -> np.ndarray:
    """Resample an (h, w[, 3]) [0, 1] image (bilinear) to ``height`` rows, keeping its aspect; returns (H, W, 3)."""
    a = np.asarray(image, dtype=np.float32)
    if a.ndim == 2:
        a = np.repeat(a[..., None], 3, axis=2)
    scale = height / a.shape[0]
    width = max(1, int(round(a.shape[1] * scale)))
    if a.shape[:2] == (height, width):
        return a
    zoomed = ndimage.zoom(a, (height / a.shape[0], width / a.shape[1], 1), order=1, mode="nearest", grid_mode=True)
    return np.clip(zoomed, 0.0, 1.0).astype(np.float32)


def label_strip(text: str, width: int, height: int) -> np.ndarray:
    """float32 (height, width, 3) strip with ``text`` written in it (the painter's bitmap font, core/figures/text.py)."""
    strip = np.empty((height, width, 3), np.float32)
    strip[...] = BACKGROUND
    size = max(8, int(height * 0.62))
    return draw_text(strip, 6, int(height * 0.75), text, size, LABEL_COLOUR)


def contact_sheet(panels: Sequence[Tuple[str, np.ndarray]], panel_height: int = 256, columns: int = 4,
                  gap: int = 6, label_height: int = 24) -> np.ndarray:
    """Pictures in a grid, each under its label, on a dark background.

    panels: (label, image) pairs; images (h, w) or (h, w, 3) in [0, 1], any
    size (scaled to ``panel_height`` rows). Returns (H, W, 3) float32 sRGB.
    """
    tiles = [(label, fit_height(image, panel_height)) for label, image in panels]
    columns = max(1, min(columns, len(tiles)))
    rows = math.ceil(len(tiles) / columns)
    cell_w = max(tile.shape[1] for _, tile in tiles)
    cell_h = label_height + panel_height
    sheet = np.empty((rows * cell_h + (rows + 1) * gap, columns * cell_w + (columns + 1) * gap, 3), np.float32)
    sheet[...] = BACKGROUND
    for i, (label, tile) in enumerate(tiles):
        r, c = divmod(i, columns)
        y = gap + r * (cell_h + gap)
        x = gap + c * (cell_w + gap)
        sheet[y:y + label_height, x:x + cell_w] = label_strip(label, cell_w, label_height)
        sheet[y + label_height:y + cell_h, x:x + tile.shape[1]] = tile
    return sheet
