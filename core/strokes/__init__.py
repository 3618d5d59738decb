"""Strokes: from anchors to canvas, a round at a time (ALGORITHM §3, §5, §6).

Brushes and their tips (``brush``), where anchors go (``layout``, and
``details`` for the detail pass), strokes' paths (``path``, ``planning``,
``smoothing``), their bristle colours and relief (``stroke``), what they lay
(``folding``, ``compositing``) and laying it on the ``canvas``, each
stroke's random numbers (``streams``), solid strokes (``lines``: Hertzmann
1998's and the "lines" renderer's). ``paint_round`` plans and lays a round
of strokes and hands the methods their ``Stroke`` records; ``stroke_list``
keeps what laying the strokes again needs, and ``lay_strokes`` lays them;
``stroke_file_list`` reads that list back from a strokes.json.
"""

from .brush import BrushTip, brush_tip, load_brush, tip_cache
from .canvas import Canvas
from .layout import choose_anchors, hertzmann_anchors, painting_order
from .lines import solid_stroke
from .rounds import paint_round
from .stroke import ColourSources, Stroke, colour_sources, detail_sources

__all__ = ["BrushTip", "Canvas", "ColourSources", "Stroke", "brush_tip", "choose_anchors", "colour_sources",
           "detail_sources", "hertzmann_anchors", "load_brush", "paint_round", "painting_order", "solid_stroke",
           "tip_cache"]
