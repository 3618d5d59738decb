"""Evaluation: the studies that paint, light and measure, and write tables and figures.

``run_experiments``: the paper's method against Hertzmann 1998 and two
ablations (``experiments``). ``run_comparison``: Cycles renders of the
relief against the 2-D lighting (``comparison``). ``run_film``: a painted
shot relit by Cycles frame by frame and lit by the paper's model, both
films' warping errors against the footage's (``film``).
"""

from .comparison import run_comparison
from .experiments import run_experiments
from .film import run_film

__all__ = ["run_comparison", "run_experiments", "run_film"]
