"""The one place a painting method is chosen: method name -> painter.

Every painter has the signature ``painter(image, params, progress=None,
cancel=None, mask=None) -> Painting`` with ``image`` an (H, W, 3) sRGB
[0, 1] array and ``mask`` an optional (h, w) importance mask in [0, 1]. A
new method is a module in ``core/methods/`` with such a function, one entry
in ``PAINTERS`` and its name in ``core.params.METHODS``.
"""

from __future__ import annotations

from typing import Callable, Dict, Optional

import numpy as np

from ..errors import ParameterError
from ..params import METHODS, Params
from ..progress import CancelFn, ProgressFn
from ..results import Painting
from . import hertzmann98, huang11

Painter = Callable[..., Painting]

PAINTERS: Dict[str, Painter] = {
    "huang11": huang11.paint,          # the paper: importance partition, bristle brush, relief
    "hertzmann98": hertzmann98.paint,  # the baseline: layered grids, solid curved strokes
}
assert tuple(PAINTERS) == METHODS


def painter(method: str) -> Painter:
    """The painter of ``method`` (a name in ``core.params.METHODS``); ParameterError otherwise."""
    if method not in PAINTERS:
        raise ParameterError(f"Unknown method {method!r}; choose {' or '.join(PAINTERS)}.")
    return PAINTERS[method]


def paint(image: np.ndarray, params: Params, progress: ProgressFn = None, cancel: CancelFn = None,
          mask: Optional[np.ndarray] = None) -> Painting:
    """Paint an (H, W, 3) sRGB [0, 1] image with the method ``params.method``; returns its Painting.

    progress(fraction, message) is called now and then; cancel() is polled
    between strokes and raises Cancelled when it returns True.
    """
    params.validate()
    return painter(params.method)(image, params, progress=progress, cancel=cancel, mask=mask)
