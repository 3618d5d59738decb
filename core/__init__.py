"""Paint Relief's painter: photographs to paintings with relief, after Huang, Fu and Li (2011).

NumPy, SciPy and OpenImageIO only; never imports bpy. ``import core`` is
light: the array modules load on first use of ``analyze``.
"""

from .errors import Cancelled, InputError, OutputError, PaintReliefError, ParameterError
from .params import Params, SequenceSettings
from .version import __version__

__all__ = [
    "__version__", "Params", "SequenceSettings", "Analysis", "analyze", "Painting", "paint", "paint_file",
    "paint_sequence_files", "check_maps", "ensure_normal_map",
    "PaintReliefError", "InputError", "OutputError", "ParameterError", "Cancelled",
]


def __getattr__(name):
    if name in ("Analysis", "Painting"):
        from . import results
        return getattr(results, name)
    if name == "analyze":
        from .analysis.run import analyze
        return analyze
    if name == "paint":
        from .methods.registry import paint
        return paint
    if name == "check_maps":
        from .files.maps import check_maps
        return check_maps
    if name == "ensure_normal_map":
        from .files.export import ensure_normal_map
        return ensure_normal_map
    if name == "paint_file":
        from .api import paint_file
        return paint_file
    if name == "paint_sequence_files":
        from .api import paint_sequence_files
        return paint_sequence_files
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
