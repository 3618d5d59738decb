"""Evaluation: the studies that paint, light and measure, and write tables and figures.

``run_experiments``: the paper's method against Hertzmann 1998 and two
ablations (``experiments``). ``run_comparison``: Cycles renders of the
relief against the 2-D lighting (``comparison``).
"""

from .comparison import run_comparison
from .experiments import run_experiments

__all__ = ["run_comparison", "run_experiments"]
