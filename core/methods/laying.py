"""A painting made from a stroke list alone: its strokes laid again on a blank canvas (``core lay``).

Laying a painting's own, unedited list against the photograph it was painted
from gives the painting's maps to the bit (``lay_strokes`` lays as the painter
did); an edited list (strokes deleted, moved, recoloured) gives the painting
those strokes make.
"""

from __future__ import annotations

import time
from typing import List

import numpy as np

from ..analysis.run import analyze, check_image
from ..params import Params
from ..progress import CancelFn, ProgressFn, Stage
from ..results import Painting
from ..strokes.canvas import Canvas
from ..strokes.stroke import Stroke
from ..strokes.stroke_list import ROUND_BRUSH, StrokeList, lay_strokes, stroke_tips
from .statistics import painting_statistics


def strokes_per_layer(strokes: StrokeList, params: Params) -> List[int]:
    """How many of ``strokes`` each layer holds: ``params.layers`` layers (the layout's count, or the largest
    layer in the list plus one when that is more), then the detail pass's with ``params.detail_pass``."""
    laid = (strokes.brush != ROUND_BRUSH) if params.detail_pass else np.ones(len(strokes), bool)
    layers = max(params.layers, int(strokes.layer[laid].max()) + 1 if laid.any() else 0)
    per_layer = np.bincount(strokes.layer[laid], minlength=layers)[:layers].tolist() if laid.any() else [0] * layers
    if params.detail_pass:
        per_layer.append(int(np.count_nonzero(~laid)))
    return [int(count) for count in per_layer]


ANALYSIS_SHARE = 0.3
"""The share of ``lay_painting``'s progress the analysis takes."""


def lay_painting(image: np.ndarray, strokes: StrokeList, records: List[Stroke], params: Params,
                 progress: ProgressFn = None, cancel: CancelFn = None) -> Painting:
    """The Painting of ``strokes`` (and their ``records``, in the same order) laid on a blank canvas of the size
    of ``image`` (H, W, 3) sRGB [0, 1], the photograph they were painted from, with ``params`` as painted.

    The image's analysis gives the orientation field (orientation.exr and
    the paper's lighting) and the grid count; the statistics are those
    ``huang11.paint`` reports (PSNR against ``image``). A stroke whose data
    does not fit its brush raises ValueError. progress(fraction, message) hears the analysis and the strokes
    laid after each run of them; cancel() is polled as often and raises Cancelled when it returns True.
    """
    image = check_image(image)
    stage = Stage(progress, cancel)
    analysis = analyze(image, params, progress=stage.sub(0.0, ANALYSIS_SHARE).report if progress else None,
                       cancel=cancel)
    laying = stage.sub(ANALYSIS_SHARE, 1.0)
    laying.report(0.0, f"Laying {len(strokes)} strokes")
    t0 = time.perf_counter()
    canvas = Canvas.blank(image.shape[:2], params.canvas_colour)
    lay_strokes(canvas, strokes, stroke_tips(strokes, params), params,
                lambda laid: laying.report(laid / max(1, len(strokes)), f"Laid {laid} of {len(strokes)} strokes"))
    seconds = {**analysis.seconds, "strokes": time.perf_counter() - t0}
    per_layer = strokes_per_layer(strokes, params)
    statistics = painting_statistics(image, canvas.colour, records, per_layer, len(analysis.grids),
                                     per_layer[-1] if params.detail_pass else 0, seconds, params, params.method,
                                     params.style, params.layout, params.renderer)
    np.clip(canvas.colour, 0.0, 1.0, out=canvas.colour)
    return Painting(canvas.colour, canvas.height, canvas.opacity, canvas.coverage, analysis.orientation,
                    records, analysis, params, statistics, strokes)
