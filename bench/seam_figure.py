"""Figure of painting across UV seams: a crop across a seam at 3x, the source, the islands painted apart and
painted across the seam, side by side (ALGORITHM §10, strokes across seams).

The UV sphere of ``tests/seam_meshes.py`` (48 x 24, a colour smooth over the
surface baked into its UVs) at ``--size`` texels: its meridian seam lies at
u = 0.98 on one side and u = 0.02 on the other, so the crop puts the 30
texels before u = 0.98 beside the 30 texels after u = 0.02, as they meet on
the surface, 100 rows from a third of the way down. Written as PNG to
``-o`` (default docs/seams.png).

Usage: python bench/seam_figure.py [--size 512] [--seed 0] [-o docs/seams.png]
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from common import ROOT

sys.path.insert(0, str(ROOT / "tests"))

from seam_meshes import baked, uv_sphere  # noqa: E402

from core.files.writing import write_png  # noqa: E402
from core.params import Params  # noqa: E402
from core.surface.texture import paint_texture, surface_layout  # noqa: E402

SCALE = 3
"""Texels are drawn SCALE x SCALE pixels."""


def seam_crop(texture: np.ndarray, rows: slice, width: int = 30) -> np.ndarray:
    """(h, 2 width, 3): the sphere's ``width`` texels before its seam at u = 0.98 beside the ``width`` after its
    seam at u = 0.02, over ``rows``."""
    n = texture.shape[0]
    right, left = int(np.floor(0.98 * n - 0.5)), int(np.ceil(0.02 * n - 0.5))
    return np.concatenate([texture[rows, right - width + 1:right + 1], texture[rows, left:left + width]], axis=1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("-o", "--out", default=str(ROOT / "docs" / "seams.png"))
    args = parser.parse_args()
    mesh = uv_sphere(48, 24)
    source = baked(mesh, args.size)
    rows = slice(args.size // 3, args.size // 3 + 100)
    panels = [seam_crop(source, rows)]
    for across in (False, True):
        painted = paint_texture(source, surface_layout(mesh, args.size, across), Params(seed=args.seed))
        panels.append(seam_crop(painted.colour, rows))
    gap = np.ones((panels[0].shape[0], 4, 3), np.float32)
    figure = np.concatenate([part for panel in panels for part in (panel, gap)][:-1], axis=1)
    write_png(args.out, np.repeat(np.repeat(figure, SCALE, axis=0), SCALE, axis=1).astype(np.float32))
    print(f"wrote {args.out}: source | islands apart | across the seam (the seam in the middle of each)")


if __name__ == "__main__":
    main()
