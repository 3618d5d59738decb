"""Methods: whole painters, one module each, chosen by name in ``registry``.

``huang11``: the paper's painter (Huang, Fu and Li 2011). ``hertzmann98``:
the Hertzmann 1998 baseline, with its ``styles``; both record the
``statistics``. ``paint(image, params)`` paints with ``params.method`` and
returns a ``core.results.Painting``.
"""

from .registry import PAINTERS, paint, painter
from .styles import STYLES, HertzmannStyle, get_style

__all__ = ["PAINTERS", "STYLES", "HertzmannStyle", "get_style", "paint", "painter"]
