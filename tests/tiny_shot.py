# SPDX-License-Identifier: GPL-3.0-or-later
"""A tiny shot for the animation tests: a checkered ball crossing a striped background, PNG frames."""

import numpy as np

from core.files import writing

WIDTH, HEIGHT, FRAMES, FIRST = 96, 64, 4, 11


def shot(folder, frames=FRAMES, width=WIDTH, height=HEIGHT, first=FIRST):
    """``frames`` PNG frames numbered from ``first`` of a checkered ball moving 10 px a frame to the right over
    stripes."""
    folder.mkdir(parents=True, exist_ok=True)
    y, x = np.mgrid[0:height, 0:width].astype(np.float32)
    background = np.stack([0.3 + 0.3 * x / width, 0.4 + 0.2 * np.sin(y / 4.0), 0.6 - 0.3 * y / height], axis=-1)
    for number in range(first, first + frames):
        cx, cy = width / 4 + 10 * (number - first), height / 2
        disc = ((x - cx) ** 2 + (y - cy) ** 2 < (height / 4.5) ** 2)[..., None]
        ball = np.stack([0.9 + 0 * x, 0.8 * (((x - cx) // 5 + (y - cy) // 5) % 2), 0.1 + 0 * x], axis=-1)
        writing.write_png(folder / "frame_{:04d}.png".format(number), np.where(disc, ball, background))
    return folder
