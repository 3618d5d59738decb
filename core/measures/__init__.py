"""Measures: numbers about an image or a painting's strokes.

Image measures (``metrics``: PSNR, SSIM, Pearson correlation, edge
fidelity) and stroke measures (``stroke_metrics``: stroke lengths and
shape). The painters record PSNR and stroke shape in their report; the
evaluation compares methods and lightings with the image measures.
"""

from .metrics import edge_fidelity, pearson, psnr, ssim
from .stroke_metrics import stroke_shape

__all__ = ["edge_fidelity", "pearson", "psnr", "ssim", "stroke_shape"]
