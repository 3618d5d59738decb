"""Measures: numbers about an image or a painting's strokes.

Image measures (``metrics``: PSNR, SSIM, Pearson correlation, edge
fidelity) and stroke measures (``stroke_metrics``: lengths, elongated area,
cracks, height spread, kept highlights). The painters record some of them in
their report; the evaluation compares methods and lightings with them.
"""

from .metrics import edge_fidelity, pearson, psnr, ssim
from .stroke_metrics import stroke_shape

__all__ = ["edge_fidelity", "pearson", "psnr", "ssim", "stroke_shape"]
