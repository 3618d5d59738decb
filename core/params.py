"""Every parameter of the painter, with its default and meaning, in one place.

Images are float32 (H, W, 3) sRGB in [0, 1]; lengths are pixels unless a
name says otherwise; angles are radians. Thresholds the paper gives on the
0-255 scale are divided by 255 here.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Tuple

from .errors import ParameterError

CANVAS_COLOUR = (0.93, 0.90, 0.84)

METHODS = ("huang11", "hertzmann98")
METHOD_TITLES = {"huang11": "Huang 2011", "hertzmann98": "Hertzmann 1998"}
"""Each method's name as the Blender panel shows it."""
PLACED_METHODS = ("huang11",)
"""The methods whose strokes can be laid only where allowed, on a canvas painted already: a shot's frames (its
births) and a texture's islands are painted with these (``methods.registry.STROKE_PAINTERS``), the first of them
the paper's; the others paint still images only."""
STYLE_NAMES = ("impressionist", "expressionist", "colorist_wash", "pointillist")
LAYOUTS = ("paper", "hertzmann98")
RENDERERS = ("bristles", "lines")
PATH_RULES = ("natural", "literal")
MAX_STROKE_SIZE = 1024
"""Largest standard stroke size (px at 1 megapixel, a brush as wide as such an image)."""
SEED_LIMIT = 2**63
"""Seeds are whole numbers 0 <= seed < SEED_LIMIT."""
TEXTURE_SIZE_RANGE = (64, 16384)
"""The smallest and largest texture (texels a side) ``api.paint_object`` paints."""


def canonical_style(name) -> str:
    """A style name spelt as in STYLE_NAMES when it names one: spaces around it dropped, lower case,
    '-' as '_' ('Colorist-Wash' -> 'colorist_wash'); any other name comes back changed alike."""
    return str(name).strip().lower().replace("-", "_")


@dataclass(frozen=True)
class Params:
    """Parameters of analysis and painting. ``validate()`` checks every range."""

    # --- reference image (bilateral filter, ALGORITHM §1.1) ---
    bilateral_sigma_spatial: float = 0.005
    """Spatial sigma as a fraction of the image diagonal (0.005 = 0.5 %)."""
    bilateral_sigma_range: float = 0.1
    """Range sigma in sRGB intensity units [0, 1]."""

    # --- importance (ALGORITHM §1.2-1.4) ---
    energy_percentile: float = 99.0
    """Energy is divided by this percentile of itself, then clipped to [0, 1]."""
    mask_strength: float = 1.0
    """k in E' = E (1 + k mask) for a user importance mask."""

    # --- partition (ALGORITHM §2, Eq. 2) ---
    stroke_sizes: Tuple[int, ...] = (64, 32, 16, 8, 4)
    """Standard brush widths in pixels for an image of ``size_reference_megapixels``."""
    size_reference_megapixels: float = 1.0
    """Stroke sizes scale with sqrt(pixels / this)."""
    detail: float = 0.9
    """0..1: how finely detailed areas are split (ALGORITHM §2). T_e = q * e_detail * s2^2 with
    q = 16^(1 - detail), s2 the second-smallest stroke size and e_detail the 95th percentile of the mean
    energy over s2 x s2 windows, so the photo's most detailed areas reach the small sizes and smooth
    areas keep the large ones, whatever the photo holds and at any size. 0.9 (q = 1.32) gives a detailed
    photo's engine, badge and fork the two smallest sizes and its floor and wall the large ones, without a
    rain of detail dabs; 0.75 (q = 2) left a motorcycle's engine to strokes too wide for it."""
    partition_delta: float = 0.01 / 255.0
    """delta of Eq. 2 on the [0, 1] energy scale (the paper's 0.01 on 0-255)."""
    partition_gamma: float = 1.0
    """gamma of Eq. 2: how strongly uneven area splits are penalised."""

    # --- orientation (ALGORITHM §4, Eq. 3) ---
    orientation_smoothing: float = 1.5
    """Gaussian sigma (px, at 1 MP) of the structure tensor behind O_GN."""
    key_cells: int = 40
    """Key points: the strongest pixel of each cell of a key_cells x key_cells grid."""
    key_threshold: float = 0.1
    """Key points need normalised energy at least this."""
    max_key_points: int = 2000
    """At most this many key points feed the RBF fit."""
    rbf_neighbors: int = 32
    """Key points used for each RBF evaluation (local fit)."""
    rbf_grid_step: int = 8
    """The RBF is evaluated every this many pixels, then bilinearly upsampled."""

    # --- strokes (ALGORITHM §3, §5, §6) ---
    layers: int = 4
    coverage_threshold: float = 0.5
    """T_c: a grid whose least-covered pixel is below this gets a stroke there."""
    difference_threshold: float = 0.1
    """T_d: Euclidean RGB distance above which a grid gets a stroke at p_max."""
    mend_ratio: float = 2.0
    """A stroke placed at p_max (rule 2 of ALGORITHM §3) is laid only when the squared colour error it mends
    (summed over the pixels where it brings the canvas closer to the reference) is more than this many times
    the squared error it spoils (where it takes the canvas further away), judged alone on the canvas as its
    round found it. A brush wider than a feature it runs beside otherwise mends a pixel of its own side and
    spoils the feature as much, and the next layer undoes it: a two-pixel line drawn on one layer and covered
    by its neighbours' strokes on the next. A stroke placed at p_min (rule 1) on a layer after the first is
    laid unless it spoils more than this many times what it mends: a wide brush covering a last bare spot of
    its grid must not sweep over small features painted since; the spot is left to the layer's next smaller
    brush, judged again. 0 lays every stroke (the paper)."""
    orientation_threshold: float = math.pi / 6
    """T_o: a path stops where the orientation turns more than this from the anchor's."""
    path_rule: str = "natural"
    """How paths stop (ALGORITHM §5). 'natural' (the default, the settled reading): the edge test on the
    brush-scale reference from the first step, the colour and orientation tests only at control points
    and only once the stroke has ``min_length`` control points. 'literal' (the paper read literally, for
    ablation): the colour and orientation tests at every curve sample from the anchor, no minimum, no edge test."""
    min_length: int = 5
    """Control points (anchor included) a 'natural' stroke has before the colour and orientation tests
    may end it; only an edge or the canvas border ends it sooner."""
    max_length: int = 16
    """Control points of a curved stroke at most, anchor included (one brush radius apart: 16 = 7.5 widths)."""
    edge_threshold: float = 0.11
    """T_e of the edge test: Euclidean RGB distance, on the brush-scale reference, from the anchor colour."""
    edge_smoothing: float = 0.25
    """Sigma, as a fraction of the brush width, of the reference the edge and colour tests read."""
    anchor_smoothing: float = 0.1
    """Sigma, as a fraction of the brush width, of the reference the anchor colour of Eq. 5 is read from."""
    bristle_smoothing: float = 0.1
    """Sigma, as a fraction of the brush width, of the reference the bristles sample."""
    bristle_deviation: float = 0.15
    """Largest Euclidean RGB distance alpha |C_bristle - C_anchor| a bristle's own colour may add (Eq. 5)."""
    brush: str = "flat"
    """A shipped brush name (flat, round, filbert) or a path to a grayscale PNG."""
    transparency: float = 0.9
    """Bristle intensities are multiplied by this."""
    bristle_alpha: float = 0.7
    """alpha of Eq. 5: weight of each bristle's own sampled colour."""
    perturbation: float = 0.03
    """Amplitude of the per-stroke random lightness change of Eq. 5: an offset of 100 U(-a, a) in CIELAB L*
    (hue and chroma kept; 0.03 is +-3 L*, about +-0.03 in sRGB at mid-gray)."""
    hue_perturbation: float = 0.0
    """Amplitude of an extra per-channel random offset (hue jitter); at most a quarter of ``perturbation``."""
    taper: float = 0.5
    """Length, in brush widths, over which the contact falls off at each end of a stroke (the brush lifting)."""
    ridge_height: float = 0.25
    """Extra height at the sides of a stroke's height profile, as a fraction of its centre (paint pushed aside)."""
    lift_buildup: float = 0.15
    """Extra height gathered just before a stroke's lift-off end, as a fraction of its body."""
    detail_pass: bool = True
    """After the layers, dot isolated point highlights the layers missed (lights, stars, glints) with the
    smallest brush, one dab each (ALGORITHM §5, detail pass)."""
    height_mode: str = "over"
    """'over' (the paper's weighted sum) or 'accumulate' (new paint on part of the old, bounded)."""
    height_build: float = 0.5
    """beta of 'accumulate': H <- o (h + beta H) + (1 - o) H, so H stays below h / (1 - beta); in [0, 1)."""
    canvas_colour: Tuple[float, float, float] = CANVAS_COLOUR
    """sRGB colour of the bare canvas."""

    # --- method, baselines and ablations (ALGORITHM §8) ---
    method: str = "huang11"
    """'huang11' (the paper's painter) or 'hertzmann98' (the baseline in core/methods/hertzmann98.py)."""
    style: str = "impressionist"
    """Hertzmann 1998 style (impressionist, expressionist, colorist_wash, pointillist): the whole
    baseline when method is 'hertzmann98'; its threshold T and grid factor f_g when layout is 'hertzmann98'."""
    layout: str = "paper"
    """'paper' (importance partition, §2-3) or 'hertzmann98' (the Fig. 8b ablation: one layer per
    standard size, cells of f_g * size / 2 px, a stroke at the max-error pixel of each cell whose mean
    error exceeds the style's T, random order); only for method 'huang11'."""
    renderer: str = "bristles"
    """'bristles' (the paper's brush, §5) or 'lines' (the Fig. 8c ablation: one solid anti-aliased
    line of the anchor colour, brush width wide); only for method 'huang11'."""

    # --- limits and randomness ---
    max_megapixels: float = 50.0
    """Inputs above this many megapixels are refused."""
    seed: int = 0

    def replace(self, **changes) -> "Params":
        """A copy with some fields changed."""
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict:
        """JSON-ready dictionary of every field."""
        return {k: (list(v) if isinstance(v, tuple) else v) for k, v in dataclasses.asdict(self).items()}

    def validate(self) -> "Params":
        """Raise ParameterError (one sentence) for the first value out of range; return self."""
        def need(ok: bool, text: str) -> None:
            if not ok:
                raise ParameterError(text)

        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            for v in (value if isinstance(value, tuple) else (value,)):
                need(not isinstance(v, float) or math.isfinite(v),
                     f"The parameter {f.name} must be a finite number, got {v}.")
        need(len(self.stroke_sizes) > 0, "Stroke sizes must list at least one size.")
        need(all(isinstance(s, (int, float)) and not isinstance(s, bool) and s > 0 for s in self.stroke_sizes),
             f"Stroke sizes must all be positive, got {list(self.stroke_sizes)}.")
        need(all(s <= MAX_STROKE_SIZE for s in self.stroke_sizes),
             f"Stroke sizes must be at most {MAX_STROKE_SIZE} px (a brush as wide as a 1-megapixel image), "
             f"got {max(self.stroke_sizes)}.")
        need(self.bilateral_sigma_spatial >= 0, "The bilateral spatial sigma must not be negative.")
        need(self.bilateral_sigma_range > 0, "The bilateral range sigma must be positive.")
        need(0 < self.energy_percentile <= 100, "The energy percentile must be in (0, 100].")
        need(self.mask_strength >= -1, "The mask strength must be at least -1.")
        need(0.0 <= self.detail <= 1.0, f"Detail must be between 0 and 1, got {self.detail}.")
        need(self.partition_delta > 0, "The partition delta must be positive.")
        need(self.partition_gamma >= 0, "The partition gamma must not be negative.")
        need(self.size_reference_megapixels > 0, "The size reference megapixels must be positive.")
        need(self.key_cells >= 1 and self.max_key_points >= 1 and self.rbf_neighbors >= 1 and self.rbf_grid_step >= 1,
             "Orientation key-point settings must be at least 1.")
        need(isinstance(self.layers, int) and 1 <= self.layers <= 16, f"Layers must be a whole number from 1 to 16, got {self.layers}.")
        need(0.0 <= self.coverage_threshold <= 1.0, "The coverage threshold must be between 0 and 1.")
        need(self.difference_threshold >= 0, "The difference threshold must not be negative.")
        need(self.mend_ratio >= 0, f"The mend ratio must not be negative, got {self.mend_ratio}.")
        need(0 < self.orientation_threshold <= math.pi, "The orientation threshold must be in (0, pi].")
        need(self.path_rule in PATH_RULES, f"Unknown path rule {self.path_rule!r}; choose natural or literal.")
        need(isinstance(self.max_length, int) and self.max_length >= 0, "The maximum stroke length must be a whole number >= 0.")
        need(isinstance(self.min_length, int) and 0 <= self.min_length,
             "The minimum stroke length must be a whole number >= 0.")
        need(self.edge_threshold > 0, "The edge threshold must be positive.")
        need(self.edge_smoothing >= 0 and self.anchor_smoothing >= 0 and self.bristle_smoothing >= 0, "Colour smoothing must not be negative.")
        need(self.bristle_deviation >= 0, "The bristle deviation limit must not be negative.")
        need(0 <= self.hue_perturbation <= self.perturbation / 4 + 1e-12,
             "The hue perturbation must be between 0 and a quarter of the lightness perturbation.")
        need(self.taper >= 0, "The taper length must not be negative.")
        need(self.ridge_height >= 0 and self.lift_buildup >= 0, "Ridge and build-up heights must not be negative.")
        need(0.0 < self.transparency <= 1.0, f"The transparency factor must be in (0, 1], got {self.transparency}.")
        need(0.0 <= self.bristle_alpha <= 1.0, f"Alpha must be between 0 and 1, got {self.bristle_alpha}.")
        need(self.perturbation >= 0, "The colour perturbation must not be negative.")
        need(self.height_mode in ("over", "accumulate"), f"Height mode must be 'over' or 'accumulate', got {self.height_mode!r}.")
        need(0 <= self.height_build < 1, f"The height build factor must be in [0, 1), got {self.height_build}.")
        need(len(self.canvas_colour) == 3 and all(0 <= c <= 1 for c in self.canvas_colour),
             "The canvas colour must be three values between 0 and 1.")
        need(self.method in METHODS, f"Unknown method {self.method!r}; choose huang11 or hertzmann98.")
        need(isinstance(self.style, str) and canonical_style(self.style) in STYLE_NAMES,
             f"Unknown style {self.style!r}; choose impressionist, expressionist, colorist_wash or pointillist.")
        need(self.layout in LAYOUTS, f"Unknown layout {self.layout!r}; choose paper or hertzmann98.")
        need(self.renderer in RENDERERS, f"Unknown renderer {self.renderer!r}; choose bristles or lines.")
        need(0 < self.max_megapixels <= 2000, "The pixel limit must be positive and at most 2000 megapixels.")
        need(isinstance(self.seed, int) and not isinstance(self.seed, bool) and 0 <= self.seed < SEED_LIMIT,
             f"The seed must be a whole number from 0 to 2^63 - 1, got {_short(self.seed)}.")
        return self

    def validate_placed(self, what: str) -> "Params":
        """``validate()``, and ParameterError (one sentence) unless these parameters can paint ``what`` (a plural,
        capitalised as the sentence begins: "Shots", "Objects"), whose strokes are laid only where allowed: a method
        of ``PLACED_METHODS`` and the paper's layout; return self."""
        self.validate()
        if self.method not in PLACED_METHODS:
            method = PLACED_METHODS[0]
            raise ParameterError(f"{what} are painted with the paper's method ({METHOD_TITLES[method]}, {method}); "
                                 f"{METHOD_TITLES[self.method]} ({self.method}) paints still images only.")
        if self.layout != "paper":
            raise ParameterError(f"{what} are painted with the paper's layout; the layout {self.layout} paints "
                                 f"still images only.")
        return self

    def validate_shot(self) -> "Params":
        """``validate_placed("Shots")``: a shot's births are laid only where its carried strokes leave the canvas
        bare or wrong; return self."""
        return self.validate_placed("Shots")

    def validate_object(self) -> "Params":
        """``validate_placed("Objects")``: a texture's strokes are laid only on each island's texels; return
        self."""
        return self.validate_placed("Objects")


def _short(value) -> str:
    """``value`` as text, long ones cut to their first and last digits."""
    text = str(value)
    return text if len(text) <= 24 else f"{text[:10]}...{text[-6:]} ({len(text)} characters)"


def scaled_sizes(params: Params, height: int, width: int) -> Tuple[int, ...]:
    """Standard stroke sizes (px, descending, distinct, >= 2) scaled to an image of height x width."""
    scale = math.sqrt(height * width / (params.size_reference_megapixels * 1e6))
    sizes = sorted({max(2, int(round(s * scale))) for s in params.stroke_sizes}, reverse=True)
    return tuple(sizes)


def screen_stroke_mm(params: Params, width: int, height: int, pixel_mm: float) -> Tuple[float, ...]:
    """The stroke widths (mm, descending) on surfaces where a pixel of a width x height render spans ``pixel_mm``
    millimetres: the widths a still of that render is painted with (``scaled_sizes``), so that strokes laid there
    show on screen as wide as the still's."""
    if not pixel_mm > 0 or pixel_mm == float("inf"):
        raise ParameterError(f"A pixel must span a positive number of millimetres, got {pixel_mm}.")
    return tuple(float(size * pixel_mm) for size in scaled_sizes(params, height, width))


@dataclass(frozen=True)
class SequenceSettings:
    """What painting a sequence adds to ``Params`` (ALGORITHM §9).

    fade_frames: K, 1 to 100, the frames a stroke takes to fade in when born and out when it dies.
    normal_map: also write each frame's normal map.
    measures: also measure each pair of frames' steadiness into report.json (ALGORITHM §9, "Measures"); it
    changes no painted byte.
    """

    fade_frames: int = 3
    normal_map: bool = False
    measures: bool = False

    def validate(self) -> "SequenceSettings":
        """Return self; ParameterError (one sentence) for a setting out of range."""
        fade = self.fade_frames
        if not (isinstance(fade, int) and not isinstance(fade, bool) and 1 <= fade <= 100):
            raise ParameterError(f"The fade must be a whole number of frames from 1 to 100, got {_short(fade)}.")
        return self
