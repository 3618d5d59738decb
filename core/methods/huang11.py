"""The paper's painter, Huang, Fu and Li 2011: ``paint(image, params) -> Painting``, and its strokes laid on any
canvas only where allowed, ``paint_strokes`` (ALGORITHM §3, §5, §6)."""

from __future__ import annotations

import dataclasses
import time
from typing import Dict, List, Optional, Tuple

import numpy as np

from ..analysis.run import analyze, check_image
from ..errors import ParameterError
from ..params import Params
from ..progress import CancelFn, ProgressFn, Stage
from ..results import Analysis, Painting
from ..strokes.brush import BrushTip, brush_tip, load_brush, tip_cache
from ..strokes.canvas import Canvas
from ..strokes.details import detail_anchors, size_map
from ..strokes.layout import (
    canvas_error,
    choose_anchors,
    grids_holding,
    hertzmann_anchors,
    painting_order,
    size_runs,
)
from ..strokes.rounds import paint_round
from ..strokes.streams import visit_uniforms
from ..strokes.stroke import ColourSources, Stroke, colour_sources, detail_sources
from ..strokes.stroke_list import PAINTING_BRUSH, ROUND_BRUSH, StrokeRecorder, recording
from .statistics import painting_statistics
from .styles import get_style


def paint(image: np.ndarray, params: Params, progress: ProgressFn = None, cancel: CancelFn = None,
          mask: Optional[np.ndarray] = None, record_strokes: bool = False, snapshots=None) -> Painting:
    """Paint an (H, W, 3) sRGB [0, 1] image stroke by stroke: a still's recipe, declared here once.

    The analysis (``analyze``, with the optional (h, w) [0, 1] importance
    ``mask``), a blank canvas, the strokes laid everywhere on it
    (``paint_strokes``: the layers, then the detail pass) and the
    statistics. progress(fraction, message) is called now and then; cancel()
    is polled between rounds and raises Cancelled when it returns True.
    record_strokes: also hand back the laid strokes as a ``StrokeList``
    (``Painting.stroke_list``), which ``lay_strokes`` lays again to the same
    bytes. snapshots: an optional ``strokes.snapshots.Snapshots`` of the image's (H, W) that catches the canvas
    while the strokes are laid (a time-lapse); the painting is the same with or without.
    """
    params.validate()
    image = check_image(image)
    stage = Stage(progress, cancel)
    brush = load_brush(params.brush)                      # a brush that cannot be read is refused before the analysis
    analysis = analyze(image, params, mask=mask, progress=stage.sub(0.0, 0.15).report if progress else None,
                       cancel=cancel)
    t0 = time.perf_counter()
    canvas = Canvas.blank(image.shape[:2], params.canvas_colour)
    canvas.snapshots = snapshots
    recorder = StrokeRecorder() if record_strokes else None
    strokes, per_layer = paint_strokes(canvas, image, analysis, params, stage.sub(0.15, 1.0), recorder,
                                       tips=tip_cache(brush, analysis.sizes, params.transparency))
    seconds = {**analysis.seconds, "strokes": time.perf_counter() - t0}
    statistics = painting_statistics(image, canvas.colour, strokes, per_layer, len(analysis.grids),
                                     per_layer[-1] if params.detail_pass else 0, seconds, params, params.method,
                                     params.style, params.layout, params.renderer)
    stage.report(1.0, f"Painted {len(strokes)} strokes")
    np.clip(canvas.colour, 0.0, 1.0, out=canvas.colour)   # Eq. 4 keeps [0, 1] up to float32 rounding
    return Painting(canvas.colour, canvas.height, canvas.opacity, canvas.coverage, analysis.orientation,
                    strokes, analysis, params, statistics,
                    None if recorder is None else recorder.stroke_list())


LAYERS_SHARE = 0.9
"""The share of ``paint_strokes``'s progress its layers take when a detail pass follows them."""


def paint_strokes(canvas: Canvas, image: np.ndarray, analysis: Analysis, params: Params, stage: Stage,
                  recorder: Optional[StrokeRecorder] = None, eligible: Optional[np.ndarray] = None,
                  sources: Optional[Dict[int, ColourSources]] = None,
                  tips: Optional[Dict[int, BrushTip]] = None) -> Tuple[List[Stroke], List[int]]:
    """A still's strokes laid on ``canvas`` (H, W): every layer in ``params.layout``, then the detail pass (with
    ``params.detail_pass``); returns (strokes in laying order, strokes per layer, the detail pass's last).

    The registry's stroke painter (``registry.STROKE_PAINTERS``): a still
    lays them on a blank canvas, a shot's frame where its carried strokes
    leave the canvas bare or wrong, a texture's island on the island's
    texels. ``image`` (H, W, 3) sRGB [0, 1] is the picture and ``analysis``
    its analysis; ``eligible`` (optional (H, W) bool): strokes are anchored
    only where it is True (the paper's layout only). ``sources`` ({width px:
    ColourSources} of the analysis's reference) and ``tips`` ({width px:
    BrushTip} of ``params.brush``) are made here when None. ``recorder``
    (optional) keeps the strokes laid. ``stage`` hears the progress and is
    polled for cancel between rounds.
    """
    if eligible is not None and params.layout != "paper":
        raise ParameterError(f"The layout {params.layout} lays strokes over the whole canvas; only the paper's "
                             f"layout lays them where allowed.")
    if sources is None:
        sources = colour_sources(analysis.reference, analysis.sizes, params)
    if tips is None:
        tips = tip_cache(load_brush(params.brush), analysis.sizes, params.transparency)
    layers_stage = stage.sub(0.0, LAYERS_SHARE if params.detail_pass else 1.0)
    if params.layout == "hertzmann98":
        strokes, per_layer = paint_layers_hertzmann98(canvas, analysis, tips, sources, params, layers_stage,
                                                      recorder)
    else:
        strokes, per_layer = paint_layers(canvas, analysis, tips, sources, params, layers_stage, recorder, eligible)
    if params.detail_pass:
        details = paint_details(canvas, image, analysis, sources, params, len(per_layer),
                                stage.sub(LAYERS_SHARE, 1.0), recorder, eligible)
        strokes += details
        per_layer.append(len(details))
    return strokes, per_layer


def paint_details(canvas: Canvas, image: np.ndarray, analysis: Analysis,
                  sources: Dict[int, ColourSources], params: Params, layer: int, stage: Stage,
                  recorder: Optional[StrokeRecorder] = None, eligible: Optional[np.ndarray] = None) -> List[Stroke]:
    """The detail pass: one dab of the smallest brush on each point highlight the layers missed (``core.strokes.details``).

    It reads the photograph ``image`` (H, W, 3) itself, not the bilateral
    reference: an edge-preserving denoise halves the contrast of features a
    pixel or two wide, which are exactly the lights and glints this pass is
    for. The dabs are one more round, planned from the canvas after the
    layers (anchors at least 2 smallest + 1 px apart, so no dab paints
    another's anchor). Dabs are laid with the round brush, whatever the
    layers' brush: a flat brush's dab is a dash, and a star is a dot.
    ``recorder`` (optional) keeps the dabs laid; ``eligible`` (optional (H, W) bool) keeps only the dabs
    anchored where it is True (a sequence's births).
    """
    smallest = min(analysis.sizes)
    anchors = detail_anchors(image, canvas.colour,
                             size_map(analysis.grids, analysis.grid_sizes, canvas.height.shape),
                             {s: sources[s].edges for s in analysis.sizes}, smallest, params.difference_threshold)
    if eligible is not None:
        anchors = anchors[eligible[anchors[:, 1], anchors[:, 0]]]
    stage.report(0.0, f"Details: {len(anchors)} strokes")
    dab = dataclasses.replace(params, min_length=0, max_length=0)   # the anchor alone: a dab, no path
    tip = brush_tip(load_brush("round"), smallest, params.transparency)
    draws = visit_uniforms(params.seed, layer, np.arange(len(anchors)), 5)[:, 1:]
    strokes = paint_round(canvas, detail_sources(image), analysis.orientation, anchors, smallest, layer, tip, draws,
                          dab, record=recording(recorder, smallest, layer, ROUND_BRUSH))
    stage.check()
    return strokes


def paint_layers(canvas: Canvas, analysis: Analysis, tips: dict, sources: Dict[int, ColourSources],
                 params: Params, stage: Stage, recorder: Optional[StrokeRecorder] = None,
                 eligible: Optional[np.ndarray] = None) -> tuple:
    """Run every layer over every grid, largest first, one round per stroke size (ALGORITHM §5, "Speed").

    Returns (strokes, strokes per layer); see ``paint_layer``. eligible: optional (H, W) bool, anchors are
    chosen only where it is True (``choose_anchors``; a sequence's births, ALGORITHM §9).
    """
    order = painting_order(analysis.grids, analysis.grid_sizes)
    grids = analysis.grids[order]
    runs = size_runs(analysis.grid_sizes[order])
    holding = None if eligible is None else grids_holding(grids, eligible)
    strokes: List[Stroke] = []
    per_layer: List[int] = []
    for layer in range(params.layers):
        laid = paint_layer(canvas, layer, grids, runs, analysis.orientation, tips, sources, params,
                           layer_progress(stage, layer, params.layers, len(runs), len(strokes)), recorder,
                           eligible, holding)
        strokes += laid
        per_layer.append(len(laid))
    return strokes, per_layer


def layer_progress(stage: Stage, layer: int, layers: int, runs: int, before: int):
    """report(runs done, strokes laid) for ``paint_layer``: polls cancel and shows the layer and the stroke count
    (``before`` laid by earlier layers)."""
    def report(done: int, count: int) -> None:
        stage.check()
        stage.report((layer + done / runs) / layers, f"Layer {layer + 1}/{layers}: {before + count} strokes")
    return report


def paint_layer(canvas: Canvas, layer: int, grids: np.ndarray, runs: list, orientation: np.ndarray, tips: dict,
                sources: Dict[int, ColourSources], params: Params, report,
                recorder: Optional[StrokeRecorder] = None, eligible: Optional[np.ndarray] = None,
                holding: Optional[np.ndarray] = None) -> List[Stroke]:
    """One layer over (N, 4) ``grids`` in painting order, one round per run (size, first, stop) of ``runs``.

    The grids of one size are a run (``painting_order``): their anchors are
    chosen and their strokes planned from the canvas as it stood when the run
    began, then laid in order. Grid i draws its random numbers from stream
    (seed, layer, i). A bare spot whose stroke was refused (``mend_ratios``)
    is left to the next smaller brush: its anchor, with its stream, opens
    that size's run if it is still bare when the run begins (``still_bare``),
    and is judged again there. report(runs done, strokes laid) is called after
    each run; ``recorder`` (optional) keeps the strokes laid; ``eligible`` (optional) as for ``choose_anchors``,
    with ``holding`` (N,) bool, which grids hold an eligible pixel (``grids_holding``, which every layer shares).
    Returns the layer's strokes.
    """
    draws = visit_uniforms(params.seed, layer, np.arange(len(grids)), 5)
    strokes: List[Stroke] = []
    waiting = np.zeros((0, 2), np.int64), np.zeros((0, 4))          # refused bare spots' anchors and draws
    for done, (size, first, stop) in enumerate(runs):
        anchors, chosen, by_difference = choose_anchors(
            grids[first:stop], canvas.opacity, canvas.colour, sources[size].edges, params.coverage_threshold,
            params.difference_threshold, draws[first:stop, 0], eligible,
            None if holding is None else holding[first:stop])
        bare = still_bare(waiting[0], canvas.opacity, params.coverage_threshold)
        anchors = np.concatenate([waiting[0][bare], anchors[chosen]])
        run_draws = np.concatenate([waiting[1][bare], draws[first:stop][chosen, 1:]])
        spots = np.concatenate([np.ones(int(bare.sum()), bool), ~by_difference[chosen]])
        ratios = mend_ratios(~spots, layer, params.mend_ratio)
        laid = paint_round(canvas, sources[size], orientation, anchors, size, layer, tips[size], run_draws, params,
                           ratios, record=recording(recorder, size, layer, PAINTING_BRUSH))
        left = spots & refused(anchors, laid) if ratios is not None else np.zeros(len(anchors), bool)
        waiting = anchors[left], run_draws[left]
        strokes += laid
        report(done + 1, len(strokes))
    return strokes


def mend_ratios(by_difference: np.ndarray, layer: int, ratio: float) -> Optional[np.ndarray]:
    """(N,) how many times the error it spoils each of N strokes of a layer must mend to be laid (0: laid
    unjudged), or None with ``ratio`` 0 (the paper: every stroke is laid).

    A stroke placed where the canvas differs from the reference (``by_difference``) must mend ``ratio``
    times what it spoils. One placed to cover a bare spot is laid on the first layer, which lays the
    ground, and on later layers unless it spoils more than ``ratio`` times what it mends: a wide brush
    covering a last bare spot of its grid must not sweep the dark of a sky over a galaxy painted since
    (the spot is then left to a smaller brush, ``paint_layer``).
    """
    if ratio <= 0:
        return None
    return np.where(by_difference, ratio, 1.0 / ratio if layer > 0 else 0.0)


def still_bare(anchors: np.ndarray, opacity: np.ndarray, coverage_threshold: float) -> np.ndarray:
    """(K,) bool: whether the canvas ``opacity`` (H, W) at each of K (x, y) ``anchors`` is still below T_c."""
    return opacity[anchors[:, 1], anchors[:, 0]] < coverage_threshold


def refused(anchors: np.ndarray, laid: List[Stroke]) -> np.ndarray:
    """(N,) bool: which of a round's N (x, y) ``anchors`` have no stroke among ``laid`` (a round's anchors
    are distinct pixels: each lies in its own grid)."""
    kept = {stroke.anchor for stroke in laid}
    return np.array([anchor not in kept for anchor in map(tuple, anchors.tolist())], bool)


def paint_layers_hertzmann98(canvas: Canvas, analysis: Analysis, tips: dict, sources: Dict[int, ColourSources],
                             params: Params, stage: Stage, recorder: Optional[StrokeRecorder] = None) -> tuple:
    """The Fig. 8b ablation: the paper's strokes on Hertzmann 1998's layered layout.

    One layer per standard stroke size (largest first; params.layers is not
    used), and so one round per layer, planned from the canvas at the
    layer's start as Hertzmann 1998 does. A layer tiles the canvas with
    cells of max(1, int(f_g * size / 2)) px, finds the cells whose mean
    error |reference - canvas| (Euclidean RGB on 0-255, +inf where the
    coverage is 0) exceeds the style's T, anchors a stroke at each such
    cell's max-error pixel, and lays those strokes in a random (seeded)
    order with the paper's brush, colours and relief against the paper's
    bilateral reference and orientation field. ``recorder`` (optional) keeps the strokes laid. Returns
    (strokes, strokes per layer).
    """
    style = get_style(params.style)
    reference = analysis.reference
    strokes: List[Stroke] = []
    per_layer: List[int] = []
    sizes = list(analysis.sizes)
    for layer, size in enumerate(sizes):
        error = canvas_error(canvas, reference)
        anchors = hertzmann_anchors(error, max(1, int(style.grid * size / 2.0)), style.threshold)
        order = np.random.default_rng([params.seed, layer]).permutation(len(anchors))
        draws = visit_uniforms(params.seed, layer, order, 5)[:, 1:]
        strokes += paint_round(canvas, sources[size], analysis.orientation, anchors[order], size, layer, tips[size],
                               draws, params, record=recording(recorder, size, layer, PAINTING_BRUSH))
        stage.check()
        stage.report((layer + 1) / len(sizes), f"Layer {layer + 1}/{len(sizes)}: {len(strokes)} strokes")
        per_layer.append(len(order))
    return strokes, per_layer
