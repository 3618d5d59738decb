"""Baseline: Hertzmann 1998, "Painterly rendering with curved brush strokes of multiple sizes" (ALGORITHM §8).

Coarse-to-fine layers, one per brush radius R (largest first):

1. reference = the input blurred by a Gaussian of sigma f_sigma R;
2. error = |reference - canvas| per pixel (Euclidean RGB on the 0-255 scale),
   +inf where the canvas is still bare (Hertzmann's "special colour"), so the
   first layer covers everything;
3. the canvas is tiled by cells of f_g R px; a cell whose mean error is above
   T gets a stroke anchored at its pixel of maximum error
   (``core.strokes.layout.hertzmann_anchors``);
4. every stroke of the layer is planned against the canvas as it was at the
   start of the layer (as painterJava does), then they are painted in a
   random (seeded) order.

A stroke (``trace_strokes``, all strokes of a layer at once): from the anchor,
step R px along the normal of the Sobel gradient of the layer reference's
luminance (0.30 R + 0.59 G + 0.11 B on 0-255, as painterJava), turned to agree
with the previous step and IIR-filtered by the curvature filter f_c; stop at
max_length control points, where R |gradient| < 1 (painterJava's vanishing
gradient test), where the next point leaves the canvas, or, once min_length
points are placed, at the first point where the canvas (at layer start) is
closer to the reference than the stroke colour is (that point is kept, as in
the paper's pseudocode). Its colour is the layer reference at the anchor,
then jittered as painterJava does: hue, saturation and value (HSV) each get
j (U - 1/2), RGB components j (U - 1/2), clipped (hue wraps).

A stroke is rendered as a solid anti-aliased round-capped line of radius R
along its control-point polyline with opacity alpha (``core.strokes.lines.solid_stroke``:
colour, coverage, height, opacity, orientation).

Radii are given at 512 x 512 px and scale with the image:
R = max(1, round(2 R_512 sqrt(H W / (512^2 m))) / 2), m = params.size_reference_megapixels
(default 1; half-pixel steps, so the
brush width 2R is a whole number of pixels); one layer per listed radius even
when two radii round to the same value. Grid spacing max(1, int(f_g R)).
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict
from typing import List, Optional, Tuple

import numpy as np
from scipy import ndimage

from ..analysis.run import analyze, check_image
from ..colour import hsv_to_rgb, rgb_to_hsv
from ..params import Params
from ..progress import CancelFn, ProgressFn, Stage
from ..results import Painting
from ..strokes.canvas import Canvas
from ..strokes.layout import canvas_error, hertzmann_anchors
from ..strokes.lines import solid_stroke
from ..strokes.stroke import Stroke
from .statistics import painting_statistics
from .styles import HertzmannStyle, get_style

REFERENCE_SIDE = 512
"""Radii of a style are for an image of REFERENCE_SIDE x REFERENCE_SIDE pixels."""

HERTZMANN_LUMA = np.array([0.30, 0.59, 0.11], dtype=np.float32)


def scaled_radii(radii, height: int, width: int, reference_megapixels: float = 1.0) -> Tuple[float, ...]:
    """Radii (px at 512 x 512) scaled to an image of height x width, in half pixels, at least 1.

    reference_megapixels is params.size_reference_megapixels: the radii are
    taken at (512 x 512) * reference_megapixels pixels (1.0: Hertzmann's 512 px;
    the paper's stroke sizes, given at 1 MP * the same factor, scale alike).
    """
    scale = math.sqrt(height * width / reference_megapixels) / REFERENCE_SIDE
    return tuple(max(1.0, round(2.0 * r * scale) / 2.0) for r in radii)


def layer_reference(image: np.ndarray, sigma: float) -> np.ndarray:
    """The image blurred by a Gaussian of ``sigma`` px in each channel (float32)."""
    if sigma <= 0:
        return image.copy()
    return ndimage.gaussian_filter(image, sigma=(sigma, sigma, 0), mode="nearest").astype(np.float32)


def sobel_gradient(reference: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Sobel derivatives (gx, gy), float32, of the reference's 0-255 luminance (kernel weights 1, 2, 1)."""
    lum = (reference @ HERTZMANN_LUMA) * np.float32(255.0)
    return ndimage.sobel(lum, axis=1, mode="nearest"), ndimage.sobel(lum, axis=0, mode="nearest")


def trace_strokes(anchors: np.ndarray, gx: np.ndarray, gy: np.ndarray, error: np.ndarray, reference: np.ndarray,
                  colours: np.ndarray, radius: float, style: HertzmannStyle) -> Tuple[np.ndarray, np.ndarray]:
    """Control points of every stroke of a layer, traced together (see the module text).

    anchors (N, 2) int (x, y); gx, gy (H, W) Sobel derivatives; error (H, W)
    |reference - canvas| on 0-255 at the start of the layer (+inf where bare);
    reference (H, W, 3) [0, 1]; colours (N, 3) un-jittered stroke colours.
    Returns (points (N, max_length + 1, 2) float64, counts (N,) int): stroke i
    is points[i, :counts[i]].
    """
    n = len(anchors)
    h, w = error.shape
    points = np.zeros((n, style.max_length + 1, 2), np.float64)
    points[:, 0] = anchors
    counts = np.ones(n, np.int64)
    x = anchors[:, 0].astype(np.float64)
    y = anchors[:, 1].astype(np.float64)
    last = np.zeros((n, 2), np.float64)
    active = np.arange(n)
    fc = style.curvature
    for k in range(1, style.max_length + 1):
        if active.size == 0:
            break
        ix = x[active].astype(np.int64)
        iy = y[active].astype(np.int64)
        gxv = gx[iy, ix].astype(np.float64)
        gyv = gy[iy, ix].astype(np.float64)
        mag = np.hypot(gxv, gyv)
        ok = radius * mag >= 1.0
        safe = np.where(ok, mag, 1.0)
        dx, dy = -gyv / safe, gxv / safe                       # normal of the gradient
        lx, ly = last[active, 0], last[active, 1]
        if k > 1:
            flip = lx * dx + ly * dy < 0
            dx, dy = np.where(flip, -dx, dx), np.where(flip, -dy, dy)
        dx, dy = fc * dx + (1.0 - fc) * lx, fc * dy + (1.0 - fc) * ly
        norm = np.hypot(dx, dy)
        ok &= norm > 1e-12
        norm = np.where(ok, norm, 1.0)
        dx, dy = dx / norm, dy / norm
        nx = x[active] + radius * dx
        ny = y[active] + radius * dy
        ok &= (nx >= 0) & (ny >= 0) & (nx < w) & (ny < h)
        go = active[ok]
        nx, ny, dx, dy = nx[ok], ny[ok], dx[ok], dy[ok]
        x[go], y[go] = nx, ny
        last[go, 0], last[go, 1] = dx, dy
        points[go, k, 0], points[go, k, 1] = nx, ny
        counts[go] = k + 1
        if k >= style.min_length and go.size:
            px, py = nx.astype(np.int64), ny.astype(np.int64)
            ref = reference[py, px].astype(np.float64) * 255.0
            stroke_error = np.sqrt(np.sum((ref - colours[go] * 255.0) ** 2, axis=1))
            done = error[py, px] < stroke_error
            go = go[~done]
        active = go
    return points, counts


def jitter_colours(colours: np.ndarray, style: HertzmannStyle, rng: np.random.Generator) -> np.ndarray:
    """(N, 3) colours with the style's HSV and RGB jitter (painterJava's j (U - 1/2)), clipped to [0, 1]."""
    out = np.asarray(colours, np.float64).copy()
    n = len(out)
    if n and (style.jitter_hue or style.jitter_saturation or style.jitter_value):
        hsv = rgb_to_hsv(out)
        hsv[:, 0] = np.mod(hsv[:, 0] + style.jitter_hue * (rng.random(n) - 0.5), 1.0)
        hsv[:, 1] = np.clip(hsv[:, 1] + style.jitter_saturation * (rng.random(n) - 0.5), 0.0, 1.0)
        hsv[:, 2] = np.clip(hsv[:, 2] + style.jitter_value * (rng.random(n) - 0.5), 0.0, 1.0)
        out = hsv_to_rgb(hsv)
    if n and style.jitter_rgb:
        out = np.clip(out + style.jitter_rgb * (rng.random((n, 3)) - 0.5), 0.0, 1.0)
    return out.astype(np.float32)


def paint_hertzmann(image: np.ndarray, params: Params, style: str = "impressionist", progress: ProgressFn = None,
                    cancel: CancelFn = None, mask: Optional[np.ndarray] = None, snapshots=None):
    """Paint an (H, W, 3) sRGB [0, 1] image by Hertzmann 1998 in the named style; returns a core.results.Painting.

    The Painting's analysis is core.analysis.analyze's (importance, partition,
    orientation of the paper's method, for the record); its orientation map is
    the direction of the topmost stroke at each pixel (where a stroke laid at
    least half its opacity), the analysis orientation elsewhere. Statistics
    carry core.paint's keys plus method, style, layout, renderer and radii_px. snapshots: an optional
    ``strokes.snapshots.Snapshots`` of the image's (H, W) that catches the canvas while the strokes are laid (a
    time-lapse); the painting is the same with or without.
    """
    params.validate()
    chosen = get_style(style)
    image = check_image(image)
    stage = Stage(progress, cancel)
    analysis = analyze(image, params, mask=mask, progress=stage.sub(0.0, 0.1).report if progress else None,
                       cancel=cancel)
    t0 = time.perf_counter()
    h, w = image.shape[:2]
    radii = scaled_radii(chosen.radii, h, w, params.size_reference_megapixels)
    canvas = Canvas.blank((h, w), params.canvas_colour)
    canvas.snapshots = snapshots
    orientation = analysis.orientation.astype(np.float32, copy=True)
    rng = np.random.default_rng(params.seed)
    strokes: List[Stroke] = []
    per_layer: List[int] = []
    cells = 0
    paint_stage = stage.sub(0.1, 1.0)
    last_report = time.monotonic()
    for layer, radius in enumerate(radii):
        layer_stage = paint_stage.sub(layer / len(radii), (layer + 1) / len(radii))
        layer_stage.report(0.0, f"Layer {layer + 1}/{len(radii)} (radius {radius:g} px)")
        reference = layer_reference(image, chosen.blur * radius)
        gx, gy = sobel_gradient(reference)
        error = canvas_error(canvas, reference)
        spacing = max(1, int(chosen.grid * radius))
        cells += (-(-h // spacing)) * (-(-w // spacing))
        anchors = hertzmann_anchors(error, spacing, chosen.threshold)
        base = reference[anchors[:, 1], anchors[:, 0]].astype(np.float64)
        points, counts = trace_strokes(anchors, gx, gy, error, reference, base, radius, chosen)
        colours = jitter_colours(base, chosen, rng)
        order = rng.permutation(len(anchors))
        size = int(round(2 * radius))
        for done, i in enumerate(order.tolist()):
            path = points[i, :counts[i]]
            solid_stroke(canvas, path, radius, colours[i], chosen.alpha, params.height_mode, params.height_build,
                         orientation)
            strokes.append(Stroke(layer, (int(anchors[i, 0]), int(anchors[i, 1])), size, path.astype(np.float32),
                                  colours[i].copy()))
            if done % 64 == 0:
                layer_stage.check()
                if progress is not None and time.monotonic() - last_report > 0.1:
                    last_report = time.monotonic()
                    layer_stage.report(done / max(1, len(order)),
                                       f"Layer {layer + 1}/{len(radii)}: {len(strokes)} strokes")
        per_layer.append(len(order))
    np.clip(canvas.colour, 0.0, 1.0, out=canvas.colour)   # solid strokes keep [0, 1] up to float32 rounding
    seconds = {**analysis.seconds, "strokes": time.perf_counter() - t0}
    statistics = painting_statistics(image, canvas.colour, strokes, per_layer, cells, 0, seconds, params,
                                     "hertzmann98", style, "hertzmann98", "lines")
    statistics["radii_px"] = list(radii)
    statistics["hertzmann_style"] = {k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(chosen).items()}
    stage.report(1.0, f"Painted {len(strokes)} strokes")
    return Painting(canvas.colour, canvas.height, canvas.opacity, canvas.coverage, orientation, strokes, analysis,
                    params, statistics)


def paint(image: np.ndarray, params: Params, progress: ProgressFn = None, cancel: CancelFn = None,
          mask: Optional[np.ndarray] = None, snapshots=None) -> Painting:
    """The registry's painter: ``paint_hertzmann`` in the style ``params.style`` (``snapshots`` as there)."""
    return paint_hertzmann(image, params, params.style, progress=progress, cancel=cancel, mask=mask,
                           snapshots=snapshots)
