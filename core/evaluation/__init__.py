"""Evaluation: the studies that paint, light and measure, and write tables and figures.

``run_experiments``: the paper's method against Hertzmann 1998 and two
ablations (``experiments``). ``run_comparison``: Cycles renders of the
relief against the 2-D lighting (``comparison``). ``run_film``: a painted
shot relit by Cycles frame by frame and lit by the paper's model, both
films' warping errors against the footage's (``film``; its file names in
``film_files``).

``import core.evaluation`` is light: the public functions below load their
module (and NumPy, OpenImageIO) on first use, so ``core.evaluation.film_files``
serves the extension before the painter's libraries are loaded.
"""

from ..lazy import lazy_names

# {public name: the module of this package that defines it}
_HOMES = {"run_comparison": "comparison", "run_experiments": "experiments", "run_film": "film"}

__all__ = list(_HOMES)

__getattr__, __dir__ = lazy_names(__name__, _HOMES)
