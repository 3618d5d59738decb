"""Hertzmann 1998's styles: the baseline's parameters, shared by the baseline and the paper's layout ablation.

``methods.hertzmann98`` paints with a whole style; ``methods.huang11`` with
``--layout hertzmann98`` takes a style's threshold T and grid f_g for its
layered layout (Fig. 8b).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, Tuple

from ..errors import ParameterError
from ..params import STYLE_NAMES, canonical_style


@dataclass(frozen=True)
class HertzmannStyle:
    """The parameters of a Hertzmann 1998 style (the paper's Section 4 names).

    threshold: T, mean cell error (Euclidean RGB, 0-255) above which a cell gets a stroke.
    radii: brush radii R_i (px at 512 x 512), largest first.
    curvature: f_c, IIR filter of the stroke direction (1 = no filter).
    blur: f_sigma, reference blur sigma = f_sigma R.
    alpha: stroke opacity a in (0, 1].
    grid: f_g, grid spacing = f_g R.
    min_length, max_length: control points after the anchor (0, 0 = dabs).
    jitter_hue, jitter_saturation, jitter_value: HSV jitter amplitudes j (a
    component moves by j (U - 1/2)); jitter_rgb: the same for R, G and B.
    """

    threshold: float = 100.0
    radii: Tuple[float, ...] = (8.0, 4.0, 2.0)
    curvature: float = 1.0
    blur: float = 0.5
    alpha: float = 1.0
    grid: float = 1.0
    min_length: int = 4
    max_length: int = 16
    jitter_hue: float = 0.0
    jitter_saturation: float = 0.0
    jitter_value: float = 0.0
    jitter_rgb: float = 0.0


STYLES: Dict[str, HertzmannStyle] = {
    # T=100 R=8,4,2 f_c=1 f_sigma=.5 a=1 f_g=1 len 4-16
    "impressionist": HertzmannStyle(),
    # T=50 R=8,4,2 f_c=.25 f_sigma=.5 a=.7 f_g=1 len 10-16 j_v=.5
    "expressionist": HertzmannStyle(threshold=50.0, curvature=0.25, alpha=0.7, min_length=10, jitter_value=0.5),
    # T=200 R=8,4,2 f_c=1 f_sigma=.5 a=.5 f_g=1 len 4-16 j_r=j_g=j_b=.3
    "colorist_wash": HertzmannStyle(threshold=200.0, alpha=0.5, jitter_rgb=0.3),
    # T=100 R=4,2 f_c=1 f_sigma=.5 a=1 f_g=.5 len 0-0 j_v=1 j_h=.3 (the paper's Pointillist entry)
    "pointillist": HertzmannStyle(radii=(4.0, 2.0), grid=0.5, min_length=0, max_length=0,
                                  jitter_value=1.0, jitter_hue=0.3),
}
assert tuple(STYLES) == STYLE_NAMES


def get_style(name: str) -> HertzmannStyle:
    """The named style ('colorist-wash' is accepted for 'colorist_wash'); ParameterError otherwise."""
    key = canonical_style(name)
    if key not in STYLES:
        raise ParameterError(f"Unknown style {name!r}; choose impressionist, expressionist, colorist_wash or pointillist.")
    return STYLES[key]
