"""Paint Relief's painter: photographs to paintings with relief, after Huang, Fu and Li (2011).

NumPy, SciPy and OpenImageIO only; never imports bpy. ``import core`` is
light: the array modules load on first use of ``analyze``.
"""

from .errors import Cancelled, InputError, OutputError, PaintReliefError, ParameterError
from .lazy import lazy_names
from .params import Params, SequenceSettings
from .version import __version__

__all__ = [
    "__version__", "Params", "SequenceSettings", "Analysis", "analyze", "Painting", "paint", "paint_file",
    "paint_sequence_files", "paint_object", "paint_objects", "ObjectOutcome", "screen_stroke_mm", "SurfaceMesh", "check_maps",
    "ensure_normal_map", "drawn_strokes", "lay_drawn", "DrawnStrokes", "PaintReliefError", "InputError", "OutputError",
    "ParameterError", "Cancelled",
]


# {public name: the module of this package that defines it}
_HOMES = {"Analysis": "results", "Painting": "results", "analyze": "analysis.run", "paint": "methods.registry",
          "check_maps": "files.maps", "ensure_normal_map": "files.export", "paint_file": "api",
          "paint_sequence_files": "api", "paint_object": "api", "paint_objects": "objects.side_by_side",
          "ObjectOutcome": "objects.side_by_side", "screen_stroke_mm": "params",
          "SurfaceMesh": "surface.mesh",
          "drawn_strokes": "api", "lay_drawn": "api", "DrawnStrokes": "strokes.drawn"}

__getattr__, __dir__ = lazy_names(__name__, _HOMES)

