"""Lighting: a painting's colour and height maps lit in 2-D.

The paper's Eq. 6-7 with the light turning with the strokes (``paper``) or
one fixed light (``directional``), Blinn-Phong bump shading (``bump``), the
normal map of a height field, and ``light(model, ...)`` choosing by name.
"""

from .models import (
    DEFAULT_AZIMUTH,
    DEFAULT_ELEVATION,
    DEFAULT_RELIEF,
    MODELS,
    PAPER_STRENGTH,
    bump_lighting,
    check_model,
    default_strength,
    directional_lighting,
    encode_normals,
    height_difference,
    light,
    normal_map,
    paper_lighting,
)

__all__ = ["DEFAULT_AZIMUTH", "DEFAULT_ELEVATION", "DEFAULT_RELIEF", "MODELS", "PAPER_STRENGTH", "bump_lighting",
           "check_model", "default_strength", "directional_lighting", "encode_normals", "height_difference",
           "light", "normal_map", "paper_lighting"]
