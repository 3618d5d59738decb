"""Analysis: what the painter needs to know about a photograph (ALGORITHM §1, §2, §4).

``analyze(image, params) -> Analysis``: the bilateral reference and the
importance map (``importance``), the canvas partition into grids of one
stroke size each (``partition``) and the stroke orientation field
(``orientation``), run in order by ``run``.
"""

from .importance import importance_map, reference_image
from .orientation import orientation_field
from .partition import detail_threshold, nearest_size, partition
from .run import analyze, check_image

__all__ = ["analyze", "check_image", "detail_threshold", "importance_map", "nearest_size", "orientation_field",
           "partition", "reference_image"]
