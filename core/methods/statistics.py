"""The statistics every painter records (``Painting.statistics``, written to report.json)."""

from __future__ import annotations

from typing import Dict, List, Sequence

import numpy as np

from ..measures.metrics import psnr
from ..measures.stroke_metrics import stroke_shape
from ..params import Params, canonical_style
from ..version import __version__


def painting_statistics(image: np.ndarray, colour: np.ndarray, strokes: Sequence, per_layer: List[int], grids: int,
                        detail_strokes: int, seconds: Dict[str, float], params: Params, method: str, style: str,
                        layout: str, renderer: str) -> dict:
    """A painting's statistics: the first keys of its report.json, in their order.

    image: the (H, W, 3) sRGB [0, 1] photograph; colour: the painting's
    (H, W, 3) canvas colour (its PSNR against the photograph, in dB to 3
    decimals); strokes: the painting's ``Stroke`` records (their count and
    ``stroke_shape``); per_layer: strokes laid by each layer (the detail
    pass last, when there is one); grids: how many grids or cells the
    layout tiled the canvas into; detail_strokes: the detail pass's strokes
    (0 without one); seconds: {stage: seconds} (rounded to 0.1 ms); params:
    the painting's settings (height mode and seed); method, layout,
    renderer: as painted; style: a Hertzmann 1998 style name, recorded as
    ``canonical_style`` spells it.
    """
    return {
        "strokes": len(strokes),
        "strokes_per_layer": per_layer,
        "detail_strokes": detail_strokes,
        "stroke_shape": stroke_shape(strokes),
        "grids": int(grids),
        "psnr_db": round(psnr(colour, image), 3),
        "seconds": {k: round(v, 4) for k, v in seconds.items()},
        "width": int(image.shape[1]),
        "height": int(image.shape[0]),
        "height_mode": params.height_mode,
        "seed": params.seed,
        "version": __version__,
        "method": method,
        "style": canonical_style(style),
        "layout": layout,
        "renderer": renderer,
    }
