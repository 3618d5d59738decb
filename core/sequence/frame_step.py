"""One frame of a sequence from the one before: carry, death, birth, fade and order (ALGORITHM §9).

Frame 0 is painted as a still. Each later frame carries the strokes of the
frame before by the motion (``carry``), lays the settled ones at full
contact on a judging canvas, and runs the still painter's layers and detail
pass against it where the carried painting leaves the canvas bare or wrong
(``birth_places``): there strokes are born, streams keyed by (seed, frame,
layer, visit), and the carried strokes anchored there start to fade out.
The frame shown is every stroke laid in order at its fade contact
(``shown_canvas``), a function of the frame's strokes alone, so it can be
laid anywhere once the strokes' life has reached the frame. It is made from
the judging canvas with the births laid (``PaintedFrame.laid_on``), laid
again only where a stroke fades, dies or is born (``strokes.relay``), which
gives the same bytes as laying every stroke anew.
"""

from __future__ import annotations

import dataclasses
import time
from typing import Dict, NamedTuple, Optional, Tuple

import numpy as np
from scipy import ndimage

from ..analysis.run import analyze
from ..methods.registry import paint_recorded, stroke_painter
from ..motion.warp import bilinear, pixel_positions
from ..params import Params, scaled_sizes
from ..progress import Stage
from ..strokes.brush import BrushTip, brush_tip, load_brush, tip_cache
from ..strokes.canvas import Canvas
from ..strokes.details import size_map
from ..strokes.path import nearest_pixels
from ..strokes.relay import relaid
from ..strokes.streams import frame_seed
from ..strokes.stroke import colour_sources, detail_sources
from ..strokes.stroke_list import (
    PAINTING_BRUSH,
    ROUND_BRUSH,
    StrokeRecorder,
    lay_strokes,
    reaching_rows,
    segment_boxes,
)
from .carry import carry, recoloured
from .living import LivingStrokes


class FrameMotion(NamedTuple):
    """The motion between frames t and t+1 (``core.motion``).

    ``visible`` is ALGORITHM §9's visibility, which the measures use. The strokes' life uses the round trip
    alone (``kept``, ``seen_before``): a flow's motion boundaries on texture (grass, foliage) are speckle over a
    tenth of the frame, not occlusions, and the tearing a true boundary means is the stretch and fold tests' work.
    """

    forward: np.ndarray         # float32 (H, W, 2) px, frame t's pixels to frame t+1
    backward: np.ndarray        # float32 (H, W, 2) px, frame t+1's pixels to frame t
    visible: np.ndarray         # bool (H, W), frame t's pixels visible in both frames (``visible_in_both``)
    kept: np.ndarray            # bool (H, W), frame t's pixels that land in frame t+1 and come back by w_b
    seen_before: np.ndarray     # bool (H, W), frame t+1's pixels that land in frame t and come back by w_f
    same_picture: bool = False  # frames t and t+1 are the same picture, pixel for pixel
    seconds: float = 0.0        # wall-clock seconds of finding it


class LaidCanvas(NamedTuple):
    """The canvas a frame's strokes were laid on while it was painted, which its frame shown is made from."""

    canvas: Canvas              # (H, W), colour not clipped
    changed: np.ndarray         # float64 (K, 4) px, the boxes (``segment_boxes``) of the strokes laid on it otherwise
                                #   than the frame shows them: at another contact, in another order, or not at all


class PaintedFrame(NamedTuple):
    """A painted frame and what the next frame needs of it."""

    living: LivingStrokes       # its strokes in laying order (``shown_canvas`` lays them)
    orientation: np.ndarray     # float32 (H, W) radians [0, pi), the frame's orientation field (Eq. 3)
    error: np.ndarray           # float32 (H, W) the settled canvas's distance from the reference
                                #   (``colour_distance``) when its strokes there were laid, carried with the motion
    fresh: np.ndarray           # bool (H, W) strokes may have been born here: its ``error`` is taken anew next frame
    opacity: np.ndarray         # float32 (H, W) [0, 1] the judging canvas's opacity, births laid
    next_ident: int             # the identity the next stroke born gets
    born: int                   # strokes born on this frame
    died: int                   # strokes gone since the frame before (occluded, or faded out)
    seconds: Dict[str, float]   # wall-clock seconds of each stage of painting it
    laid_on: Optional[LaidCanvas] = None  # the canvas laid while painting it; None: the frame shown is laid anew


class FrameAnalysis(NamedTuple):
    """What a frame's strokes are painted from, which needs nothing of the frames before it."""

    analysis: object            # ``core.analysis.run.Analysis`` of the frame
    sources: dict               # {width px: ColourSources} of the frame's reference (``colour_sources``)
    seconds: float = 0.0        # wall-clock seconds of making them


def analyse_frame(image: np.ndarray, params: Params, cancel=None) -> FrameAnalysis:
    """The analysis of (H, W, 3) sRGB [0, 1] ``image`` and its colour sources at every stroke width."""
    clock = time.perf_counter()
    analysis = analyze(image, params, cancel=cancel)
    sources = colour_sources(analysis.reference, analysis.sizes, params)
    return FrameAnalysis(analysis, sources, time.perf_counter() - clock)


def first_frame(image: np.ndarray, params: Params, fade_frames: int, stage: Stage) -> PaintedFrame:
    """Frame 0: the still painting of (H, W, 3) sRGB [0, 1] ``image``, its strokes at full contact."""
    clock = time.perf_counter()
    painting = paint_recorded(image, params, "Shots", stage.progress, stage.cancel)
    strokes = painting.statistics["seconds"]["strokes"]
    living = LivingStrokes.born(painting.stroke_list, 0, 0, fade_frames, fade_frames)
    canvas = Canvas(painting.colour, painting.coverage, painting.height, painting.opacity)
    return PaintedFrame(living, painting.orientation, colour_distance(painting.colour, painting.analysis.reference),
                        np.zeros(image.shape[:2], bool), painting.opacity, len(living), len(living), 0,
                        {"analysis": time.perf_counter() - clock - strokes, "strokes": strokes},
                        LaidCanvas(canvas, np.zeros((0, 4))))


class CarriedFrame(NamedTuple):
    """The frame before's strokes carried to this frame, before births: what the judging canvas is laid from."""

    living: LivingStrokes       # carried and recoloured, in laying order (dying ones start fading out later)
    gone: int                   # strokes that died at once (hidden, torn) or finished fading out
    sizes: tuple                # the frame's standard stroke widths (px), whose tips lay the strokes
    seconds: float              # wall-clock seconds of carrying them


def next_frame(previous: PaintedFrame, index: int, image: np.ndarray, motion: FrameMotion, params: Params,
               stage: Stage, analysed: Optional[FrameAnalysis] = None) -> PaintedFrame:
    """Frame ``index`` (>= 1) of (H, W, 3) sRGB [0, 1] ``image`` from the ``previous`` frame and the ``motion``
    between them; ``analysed``: the frame's ``analyse_frame`` when it was made elsewhere (made here when None).
    The three steps, each a piece of its own in ``pieces`` (CARRY, JUDGE, BIRTH): ``carried_frame``, the judging
    canvas laid (``settled_rows``, of every row here; bands of rows side by side on a cluster) and
    ``born_frame``."""
    seconds = {}
    if analysed is None:
        analysed = analyse_frame(image, params, stage.cancel)
        seconds["analysis"] = analysed.seconds
    carried = carried_frame(previous, image, motion, params, analysed)
    stage.check()
    judging = settled_rows(carried, params, image.shape[:2], (0, image.shape[0]))
    painted = born_frame(previous, index, image, motion, params, stage, analysed, carried, [judging])
    return painted._replace(seconds={**seconds, **painted.seconds})


def carried_frame(previous: PaintedFrame, image: np.ndarray, motion: FrameMotion, params: Params,
                  analysed: FrameAnalysis) -> CarriedFrame:
    """The ``previous`` frame's strokes carried by the ``motion`` onto (H, W, 3) ``image`` (``carry``), dead ones
    gone, anchor colours taken again from the frame (``recoloured``)."""
    clock = time.perf_counter()
    analysis, sources = analysed.analysis, analysed.sources
    carried = carry(previous.living, motion.forward, motion.kept,
                    size_map(analysis.grids, analysis.grid_sizes, image.shape[:2]), analysis.sizes,
                    params.orientation_threshold)
    living = recoloured(carried.living, {s: sources[s].anchor for s in analysis.sizes}, detail_sources(image).anchor)
    return CarriedFrame(living, carried.occluded + carried.faded, tuple(analysis.sizes), time.perf_counter() - clock)


class CanvasRows(NamedTuple):
    """Rows first .. first + H - 1 of a canvas, and the seconds laying them took."""

    first: int
    canvas: Canvas              # (H, W) rows of the canvas
    seconds: float


def settled_rows(carried: CarriedFrame, params: Params, shape: tuple, rows: Tuple[int, int]) -> CanvasRows:
    """Rows ``rows`` = (first, stop) of the judging canvas of the (H, W) ``shape`` frame: the carried strokes that
    are not dying laid at full contact on a blank canvas (only those that reach the rows: ``reaching_rows``)."""
    clock = time.perf_counter()
    strokes = carried.living.settled().strokes
    first, stop = rows
    whole = (first, stop) == (0, shape[0])
    lines = params.renderer == "lines"                  # solid lines are drawn on a whole frame
    canvas = Canvas.blank(shape, params.canvas_colour, None if whole or lines else rows)
    lay_strokes(canvas, strokes.subset(reaching_rows(strokes, *rows)), frame_tips(params, carried.sizes), params)
    if lines and not whole:
        canvas = Canvas(*(np.ascontiguousarray(values[first:stop]) for values in
                          (canvas.colour, canvas.coverage, canvas.height, canvas.opacity)))
    return CanvasRows(first, canvas, time.perf_counter() - clock)


def joined_rows(parts) -> Canvas:
    """One canvas of consecutive ``CanvasRows`` covering every row, in order of their first row."""
    parts = sorted(parts, key=lambda part: part.first)
    if len(parts) == 1:
        return parts[0].canvas
    return Canvas(*(np.concatenate([getattr(part.canvas, name) for part in parts])
                    for name in ("colour", "coverage", "height", "opacity")))


def born_frame(previous: PaintedFrame, index: int, image: np.ndarray, motion: FrameMotion, params: Params,
               stage: Stage, analysed: FrameAnalysis, carried: CarriedFrame, judging_rows) -> PaintedFrame:
    """Frame ``index`` from its ``carried`` strokes and the judging canvas they lay (``judging_rows``: its
    ``CanvasRows``): where the carried painting leaves the frame bare or wrong (``birth_places``) the still's
    strokes are born (the method's stroke painter, ``methods.registry.stroke_painter``: its layers and detail pass),
    and the carried strokes anchored there start to fade out."""
    clock = time.perf_counter()
    analysis, sources = analysed.analysis, analysed.sources
    shape = image.shape[:2]
    tips = frame_tips(params, analysis.sizes)
    judging = joined_rows(judging_rows)
    came_from = pixel_positions(*shape) + motion.backward
    error = colour_distance(judging.colour, analysis.reference)
    laid_error = np.where(nearest(previous.fresh, came_from), error, bilinear(previous.error, came_from))
    eligible = birth_places(judging, error, laid_error, bilinear(previous.opacity, came_from), motion.seen_before,
                            params)
    stale = anchored_in(carried.living.strokes.anchor, eligible)
    living, gone = carried.living.fading_out(stale)
    recorder = StrokeRecorder()
    births = dataclasses.replace(params, seed=frame_seed(params.seed, index))
    stroke_painter(births, "Shots")(judging, image, analysis, births, stage, recorder, eligible, sources,
                                    {s: tips[PAINTING_BRUSH, s] for s in analysis.sizes})
    born = LivingStrokes.born(recorder.stroke_list(), previous.next_ident, index, 1, living.fade_frames)
    frame = LivingStrokes.joined([living, born])
    unsettled = carried.living.dying | (carried.living.strokes.contact != 1)
    changed = np.concatenate([segment_boxes(carried.living.strokes.subset(stale | unsettled))[0],
                              segment_boxes(born.strokes)[0]])
    seconds = {"carry": carried.seconds, "settling": sum(part.seconds for part in judging_rows),
               "birth": time.perf_counter() - clock}
    return PaintedFrame(frame, analysis.orientation, laid_error, eligible, judging.opacity,
                        previous.next_ident + len(born), len(born), carried.gone + gone, seconds,
                        LaidCanvas(judging, changed))


def unchanged(previous: PaintedFrame, motion: FrameMotion) -> bool:
    """Whether ``next_frame`` would give ``previous`` again: the frames are the same picture and nothing moves, no
    stroke of ``previous`` is fading, and no place of it was open to births (so its judging canvas was its strokes
    laid in order). Then every stroke stays where and as it is, none dies and none is born, so a still stretch of a
    shot is painted once."""
    return (motion.same_picture and not motion.forward.any() and not motion.backward.any()
            and previous.living.at_full_contact() and not previous.fresh.any())


def anchored_in(anchors: np.ndarray, places: np.ndarray) -> np.ndarray:
    """(N,) bool: which of N ``anchors`` (N, 2) px lie on a pixel where the (H, W) bool ``places`` holds."""
    rows, cols = nearest_pixels(places.shape, anchors[:, 0], anchors[:, 1])
    return places[rows, cols]


def nearest(mask: np.ndarray, positions: np.ndarray) -> np.ndarray:
    """(H, W) bool: (H, W) ``mask`` at the pixels nearest (H, W, 2) (x, y) ``positions`` (clamped to the frame)."""
    rows, cols = nearest_pixels(mask.shape, positions[..., 0], positions[..., 1])
    return mask[rows, cols]


def birth_places(judging: Canvas, error: np.ndarray, laid_error: np.ndarray, opacity_before: np.ndarray,
                 seen_before: np.ndarray, params: Params) -> np.ndarray:
    """(H, W) bool: where frame t+1's grids may get new strokes, the carried strokes laid on ``judging``.

    Pixels not ``seen_before`` (disoccluded); bare (opacity below T_c) where frame t's ``opacity_before`` was not and
    was more than BARED higher; or whose ``error`` (``colour_distance`` of the canvas from the reference) is more than
    T_d above what it was when its strokes were laid (``laid_error``, carried with the motion, so a slow drift is
    caught as surely as a jump). Frame t's maps are taken where each pixel came from. Where the carried painting is
    as bare or as wrong as when it was laid, the still painter left it so: nothing is born. A pixel where strokes
    may have been born takes the error of the next frame's carried canvas as its own (``PaintedFrame.fresh``), so
    a flaw the births did not mend is not painted over again and again.
    """
    bared = ((judging.opacity < params.coverage_threshold) & (opacity_before >= params.coverage_threshold)
             & (opacity_before - judging.opacity > BARED))
    return ~seen_before | bared | (error > laid_error + np.float32(params.difference_threshold))


BARED = 0.25
"""A pixel is newly bare when its opacity fell below T_c by more than this since the frame before: an opacity near
T_c re-sampled a fraction of a pixel away is not a gap."""


ERROR_SMOOTHING = 1.0
"""px: the Gaussian sigma over which a canvas's error is averaged before frames are compared, so that a pixel's
aliasing (an edge re-sampled a fraction of a pixel away) is not taken for a wrong canvas."""


def colour_distance(colour: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """(H, W) float32: the Euclidean RGB distance between (H, W, 3) ``colour`` and ``reference``, sRGB [0, 1],
    averaged by a Gaussian of ERROR_SMOOTHING px."""
    diff = colour - reference
    return ndimage.gaussian_filter(np.sqrt(np.einsum("ijk,ijk->ij", diff, diff)), ERROR_SMOOTHING, mode="nearest")


def frame_tips(params: Params, sizes) -> Dict[Tuple[int, int], BrushTip]:
    """{(brush, size): BrushTip} of a sequence's strokes: the painting's brush at every standard size (px) and
    the round brush at the smallest (the detail pass's dabs)."""
    tips = {(PAINTING_BRUSH, size): tip for size, tip in tip_cache(load_brush(params.brush), sizes,
                                                                    params.transparency).items()}
    tips[ROUND_BRUSH, min(sizes)] = brush_tip(load_brush("round"), min(sizes), params.transparency)
    return tips


def shown_canvas(frame: PaintedFrame, params: Params, shape: tuple) -> Canvas:
    """The (H, W) ``shape`` frame as shown: its strokes laid in order at their contact, colour clipped to [0, 1];
    made from the canvas laid while painting it (``relay.relaid``) when the frame keeps one."""
    tips = frame_tips(params, scaled_sizes(params, *shape))
    if frame.laid_on is None:
        return laid(frame.living, tips, params, shape)
    canvas = relaid(frame.laid_on.canvas, frame.laid_on.changed, frame.living.strokes, tips, params)
    np.clip(canvas.colour, 0.0, 1.0, out=canvas.colour)
    return canvas


def laid(frame: LivingStrokes, tips: Dict[Tuple[int, int], BrushTip], params: Params, shape: tuple) -> Canvas:
    """A blank (H, W) canvas with the frame's strokes laid in order at their contact, colour clipped to [0, 1]."""
    canvas = Canvas.blank(shape, params.canvas_colour)
    lay_strokes(canvas, frame.strokes, tips, params)
    np.clip(canvas.colour, 0.0, 1.0, out=canvas.colour)
    return canvas
