"""The one place a painting method is chosen: method name -> painter of a still, and of its strokes alone.

Every painter has the signature ``painter(image, params, progress=None,
cancel=None, mask=None) -> Painting`` with ``image`` an (H, W, 3) sRGB
[0, 1] array and ``mask`` an optional (h, w) importance mask in [0, 1]. A
new method is a module in ``core/methods/`` with such a function, one entry
in ``PAINTERS`` and its name in ``core.params.METHODS``.

A method that can lay a still's strokes on a canvas painted already, only
where allowed, has a stroke painter in ``STROKE_PAINTERS`` too (its name in
``core.params.PLACED_METHODS``), and its painter takes ``record_strokes``:
a shot's frames and a texture's islands are painted with it
(``stroke_painter``, ``paint_recorded``), and refused in one sentence with
any other method (``Params.validate_placed``).
"""

from __future__ import annotations

from typing import Callable, Dict, Optional

import numpy as np

from ..errors import ParameterError
from ..params import METHODS, PLACED_METHODS, Params
from ..progress import CancelFn, ProgressFn
from ..results import Painting
from . import hertzmann98, huang11

Painter = Callable[..., Painting]

PAINTERS: Dict[str, Painter] = {
    "huang11": huang11.paint,          # the paper: importance partition, bristle brush, relief
    "hertzmann98": hertzmann98.paint,  # the baseline: layered grids, solid curved strokes
}
assert tuple(PAINTERS) == METHODS

StrokePainter = Callable[..., tuple]
"""``paint_strokes(canvas, image, analysis, params, stage, recorder=None, eligible=None, sources=None, tips=None)
-> (strokes, strokes per layer)``: a still's strokes laid on ``canvas``, anchored only where the (H, W) bool
``eligible`` is True (``huang11.paint_strokes`` says the rest)."""

STROKE_PAINTERS: Dict[str, StrokePainter] = {
    "huang11": huang11.paint_strokes,  # the paper's layers and detail pass, anchored where allowed
}
assert tuple(STROKE_PAINTERS) == PLACED_METHODS


def painter(method: str) -> Painter:
    """The painter of ``method`` (a name in ``core.params.METHODS``); ParameterError otherwise."""
    if method not in PAINTERS:
        raise ParameterError(f"Unknown method {method!r}; choose {' or '.join(PAINTERS)}.")
    return PAINTERS[method]


def paint(image: np.ndarray, params: Params, progress: ProgressFn = None, cancel: CancelFn = None,
          mask: Optional[np.ndarray] = None, record_strokes: bool = False, snapshots=None) -> Painting:
    """Paint an (H, W, 3) sRGB [0, 1] image with the method ``params.method``; returns its Painting.

    progress(fraction, message) is called now and then; cancel() is polled
    between strokes and raises Cancelled when it returns True. record_strokes: also keep the laid strokes
    (``Painting.stroke_list``) when the method can (``STROKE_PAINTERS``'s methods); other methods keep none.
    snapshots: an optional ``strokes.snapshots.Snapshots`` catching the canvas while the strokes are laid (every
    method takes one).
    """
    params.validate()
    extra = {} if snapshots is None else {"snapshots": snapshots}
    if record_strokes and params.method in STROKE_PAINTERS:
        return PAINTERS[params.method](image, params, progress=progress, cancel=cancel, mask=mask,
                                       record_strokes=True, **extra)
    return painter(params.method)(image, params, progress=progress, cancel=cancel, mask=mask, **extra)


def stroke_painter(params: Params, what: str) -> StrokePainter:
    """The stroke painter of ``params.method`` for ``what`` ("Shots", "Objects"): ParameterError in one sentence
    unless the method and layout can lay strokes only where allowed (``Params.validate_placed``)."""
    params.validate_placed(what)
    return STROKE_PAINTERS[params.method]


def paint_recorded(image: np.ndarray, params: Params, what: str, progress: ProgressFn = None,
                   cancel: CancelFn = None) -> Painting:
    """Paint an (H, W, 3) sRGB [0, 1] image as a still with ``params.method``, its strokes recorded
    (``Painting.stroke_list``), for ``what`` (a shot's first frame: "Shots"); ParameterError in one sentence as
    ``stroke_painter`` says."""
    params.validate_placed(what)
    return PAINTERS[params.method](image, params, progress=progress, cancel=cancel, record_strokes=True)
