"""Strokes: one stroke from anchor to canvas (ALGORITHM §3, §5, §6).

Brushes and their tips (``brush``), where anchors go (``layout``, and
``details`` for the detail pass), a stroke's path (``path``, ``planning``,
``smoothing``), its bristle colours and relief (``stroke``), and laying it
on the ``canvas`` (``compositing``). ``paint_stroke`` hands the methods a
``Stroke`` record and a changed ``Canvas``.
"""

from .brush import BrushTip, brush_tip, load_brush, tip_cache
from .canvas import Canvas
from .layout import choose_anchor, grid_order, hertzmann_anchors
from .stroke import ColourSources, Stroke, colour_sources, detail_sources, paint_stroke, solid_stroke

__all__ = ["BrushTip", "Canvas", "ColourSources", "Stroke", "brush_tip", "choose_anchor", "colour_sources",
           "detail_sources", "grid_order", "hertzmann_anchors", "load_brush", "paint_stroke", "solid_stroke",
           "tip_cache"]
