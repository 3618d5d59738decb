"""Painting in rounds: every stroke of one size in a layer planned at once, then laid in order (ALGORITHM §5, "Speed").

A round's strokes are planned (bristle colours, path, stopping tests)
against the canvas as it stood when the round began, all together as
arrays; they are then laid in the round's order, each stroke's Eq. 4
contributions after the previous one's, so overlaps composite exactly as
laying them one by one would.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, List, NamedTuple, Optional

import numpy as np

from .. import tuning
from ..params import Params
from ..workers import balanced_runs, bounded_runs, run_all, worker_count
from .brush import BrushTip
from .canvas import Canvas
from .compositing import Footprints, track_footprints
from .lines import solid_stroke
from .path import resample_by_length, tangent_angles
from .planning import PlannedPaths, plan_paths, sample_spacing, samples_per_segment
from .stroke import (
    MIN_ROWS,
    ColourSources,
    Stroke,
    bristle_colours,
    colour_jitter,
    end_profile,
    ridge_profile,
)


@dataclass
class RoundPlan:
    """Everything N strokes of a round need to be laid, in the round's order.

    anchors: int64 (N, 2) (x, y) px.
    colours: float32 (N, B, 3) sRGB [0, 1], the colour of every bristle of the brush (Eq. 5).
    anchor_colours: float32 (N, 3) sRGB [0, 1], each stroke's colour at its anchor (what it records).
    paths: the strokes' kept curves.
    angles: float64 (N,) radians, the orientation field at each anchor.
    ratios: float64 (N,) >= 0 or None: stroke i is laid only if it mends more than ratios[i] times the error
            it spoils (``improves``), 0 lays it unjudged; None when the round lays every stroke.
    contact: float32 (N,) in [0, 1] or None: the factor on each stroke's contact (a fading stroke's, ALGORITHM
             §9); None lays every stroke at full contact.
    """

    anchors: np.ndarray
    colours: np.ndarray
    anchor_colours: np.ndarray
    paths: PlannedPaths
    angles: np.ndarray
    ratios: np.ndarray = None
    contact: np.ndarray = None

    def subset(self, index) -> "RoundPlan":
        """The plan of some of the strokes, in order: ``index`` a slice or an ascending (K,) int array."""
        paths = self.paths
        return RoundPlan(self.anchors[index], self.colours[index], self.anchor_colours[index],
                         PlannedPaths(paths.samples[index], paths.first[index], paths.last[index], paths.per_segment),
                         self.angles[index], None if self.ratios is None else self.ratios[index],
                         None if self.contact is None else self.contact[index])

    @staticmethod
    def joined(parts: list) -> "RoundPlan":
        """The plan of several runs of strokes (unjudged, at full contact), one run after another."""
        join = lambda arrays: np.concatenate(list(arrays))  # noqa: E731
        return RoundPlan(join(p.anchors for p in parts), join(p.colours for p in parts),
                         join(p.anchor_colours for p in parts),
                         PlannedPaths(join(p.paths.samples for p in parts), join(p.paths.first for p in parts),
                                      join(p.paths.last for p in parts), parts[0].paths.per_segment),
                         join(p.angles for p in parts))


class Stamps(NamedTuple):
    """M stamps one px apart along N strokes' paths; stroke i's stamps are [starts[i], starts[i + 1])."""

    points: np.ndarray          # float64 (M, 2) (x, y) px
    directions: np.ndarray      # float64 (M,) radians, the direction of travel
    contact: np.ndarray         # float32 (M,) in (0, 1], the brush's pressure (``end_profile``)
    relief: np.ndarray          # float32 (M,) >= 1, paint gathering where the brush lifts
    starts: np.ndarray          # int64 (N + 1,)


class JudgedFootprints(NamedTuple):
    """What N strokes lay and whether each is laid."""

    runs: List[Footprints]      # the Footprints of consecutive runs of the strokes
    mends: np.ndarray           # (N,) bool: the stroke ``improves`` the canvas by its ratio


def stamp_paths(paths: PlannedPaths, angles: np.ndarray, size: int, params: Params) -> Stamps:
    """Stamps one px apart along N planned paths; ``angles`` (N,) the direction a stroke of one stamp takes."""
    resampled = resample_by_length(paths.samples, paths.first, paths.last)
    starts = resampled.starts
    total = np.repeat(resampled.arc[starts[1:] - 1], np.diff(starts))
    profile = end_profile(resampled.arc, total, size, params.taper, params.lift_buildup)
    return Stamps(resampled.stamps, tangent_angles(resampled.stamps, starts, angles), profile.contact,
                  profile.relief, starts)


def paint_round(canvas: Canvas, sources: ColourSources, orientation: np.ndarray, anchors: np.ndarray, size: int,
                layer: int, tip: BrushTip, draws: np.ndarray, params: Params, ratios: np.ndarray = None,
                record: Optional[Callable[[RoundPlan], None]] = None) -> List[Stroke]:
    """Plan and lay N strokes ``size`` px wide from (N, 2) int ``anchors`` (x, y); returns their records.

    draws: (N, 4) uniform numbers of each stroke's own stream (its colour
    perturbation, ``colour_jitter``). ratios: optional (N,) float >= 0,
    stroke i is laid only if it mends more than ratios[i] times the error
    it spoils (``improves``), judged alone on the canvas as the round found
    it; 0 lays it unjudged (all are, by the 'lines' renderer). record:
    optional, called with the plan of the strokes laid, in order, once they
    are laid (what ``core.strokes.stroke_list`` keeps of them).
    """
    anchors = np.asarray(anchors, np.int64).reshape(-1, 2)
    if len(anchors) == 0:
        return []
    plan = plan_round(canvas, sources, orientation, anchors, size, tip, draws, params)
    chunks = lay_chunks(plan.paths, tip, size)
    if ratios is not None and params.renderer != "lines" and np.any(ratios):
        plan.ratios = np.asarray(ratios, np.float64)
        plan = plan.subset(judge_and_lay(canvas, plan, chunks, size, tip, params, sources.reference))
    else:
        for first, stop in chunks:
            lay_round(canvas, plan.subset(slice(first, stop)), size, tip, params)
    if record is not None:
        record(plan)
    return records(plan, size, layer)


def judge_and_lay(canvas: Canvas, plan: RoundPlan, chunks: list, size: int, tip: BrushTip, params: Params,
                  reference: np.ndarray) -> np.ndarray:
    """Judge a plan's strokes by their ``plan.ratios`` (``improves``; 0 lays a stroke unjudged) on the canvas
    as the round found it, and lay the kept ones in order, one of ``lay_chunks``' (first, stop) ``chunks`` after
    another; returns the kept strokes' indices, ascending.

    Each chunk's footprints are made once, judged, and its kept strokes' footprints laid before the next chunk
    is made, so a round holds one chunk's footprints at a time. A round of several chunks judges against a
    copy of the canvas colour taken before its first chunk is laid (the judge reads nothing else).
    """
    found = canvas.colour.copy() if len(chunks) > 1 else canvas.colour
    indices = []
    for first, stop in chunks:
        part = plan.subset(slice(first, stop))
        judged = judged_footprints(part, size, tip, params, found, reference)
        kept = judged.mends | (part.ratios == 0)
        canvas.lay(judged.runs, params.height_mode, params.height_build, kept)
        indices.append(first + np.flatnonzero(kept))
    return np.concatenate(indices)


def improves(colour: np.ndarray, footprints: Footprints, reference: np.ndarray, ratio,
             strokes: np.ndarray = None) -> np.ndarray:
    """(N,) bool: whether each of N strokes' ``footprints``, laid alone on a canvas of ``colour`` (H, W, 3)
    float32, mends more than ``ratio`` (a number, or (N,) one per stroke) times the error it spoils. With e and
    e' a pixel's squared Euclidean RGB distance from ``reference`` (H, W, 3) float32 before and after the
    stroke (Eq. 4), the stroke mends sum max(0, e - e') and spoils sum max(0, e' - e) over its pixels.
    strokes: optional (M,) bool over the footprints' M strokes, judge only those (N of them, in order)."""
    pixel, starts = footprints.pixel, footprints.starts
    transmittance, paint = footprints.transmittance, footprints.paint
    if strokes is not None:
        counts = np.diff(starts)
        entries = np.repeat(strokes, counts)
        pixel, transmittance, paint = pixel[entries], transmittance[entries], paint[entries]
        starts = np.zeros(int(np.count_nonzero(strokes)) + 1, np.int64)
        np.cumsum(counts[strokes], out=starts[1:])
    before = np.take(colour.reshape(-1, 3), pixel, axis=0)
    target = np.take(reference.reshape(-1, 3), pixel, axis=0)
    after = before * transmittance[:, None]
    after += paint
    after -= target
    before -= target
    change = (np.einsum("ij,ij->i", after, after, dtype=np.float64)
              - np.einsum("ij,ij->i", before, before, dtype=np.float64))
    mended, spoiled = np.zeros(len(starts) - 1), np.zeros(len(starts) - 1)
    touched = np.diff(starts) > 0
    mended[touched] = np.add.reduceat(np.maximum(-change, 0.0), starts[:-1][touched])
    spoiled[touched] = np.add.reduceat(np.maximum(change, 0.0), starts[:-1][touched])
    return mended > ratio * spoiled


def lay_chunks(paths: PlannedPaths, tip: BrushTip, size: int) -> list:
    """[(first, stop), ...]: runs of consecutive strokes whose track samples times brush columns stay within
    tuning.LAY_CHUNK_SAMPLES (a stroke of more is a run of its own). A stroke's track is at most its kept curve's
    length in px (curve samples ``sample_spacing`` apart) plus the brush's length."""
    return bounded_runs(track_costs(paths, tip, size), tuning.LAY_CHUNK_SAMPLES)


def track_costs(paths: PlannedPaths, tip: BrushTip, size: int) -> np.ndarray:
    """(N,) int64: an upper bound on each stroke's track samples times brush columns: its kept curve's length
    in px (curve samples ``sample_spacing`` apart) plus the brush's length, times the brush's columns."""
    length = np.ceil((paths.last - paths.first) * sample_spacing(size)).astype(np.int64)
    return (length + int(tip.length) + 3) * (int(np.ptp(tip.across)) + 1)


def plan_round(canvas: Canvas, sources: ColourSources, orientation: np.ndarray, anchors: np.ndarray, size: int,
               tip: BrushTip, draws: np.ndarray, params: Params) -> RoundPlan:
    """The (unjudged) plan of N strokes, planned against ``canvas`` as it is now.

    The strokes are planned in runs of equal length on the worker threads
    (the canvas does not change in between): at least as many runs as keep
    each within tuning.PLAN_CHUNK_SAMPLES / workers curve samples (so the workers
    hold at most tuning.PLAN_CHUNK_SAMPLES at a time, which bounds the memory of
    the tests), one per worker when every run has tuning.WORKER_LEAST_STROKES, and
    a multiple of the workers, so every worker is busy to the last run.
    """
    workers, n = worker_count(), len(anchors)
    samples = (2 * max(0, params.max_length - 1) * samples_per_segment(size) + 1) * (len(tip) + 8)
    cost = np.full(n, samples, np.int64)
    count = max(len(bounded_runs(cost, tuning.PLAN_CHUNK_SAMPLES // workers)), min(workers, n // tuning.WORKER_LEAST_STROKES))
    if count > 1:
        count = min(n, -(-count // workers) * workers)
    runs = balanced_runs(cost, count, 0)
    parts = run_all(lambda run: plan_strokes(canvas, sources, orientation, anchors[slice(*run)], size, tip,
                                             draws[slice(*run)], params), runs)
    return parts[0] if len(parts) == 1 else RoundPlan.joined(parts)


def plan_strokes(canvas: Canvas, sources: ColourSources, orientation: np.ndarray, anchors: np.ndarray, size: int,
                 tip: BrushTip, draws: np.ndarray, params: Params) -> RoundPlan:
    """``plan_round`` of one chunk of strokes."""
    angles = orientation[anchors[:, 1], anchors[:, 0]].astype(np.float64)
    jitter = colour_jitter(draws, params.perturbation, params.hue_perturbation)
    deviation = params.bristle_deviation if sources.deviation is None else sources.deviation
    colours = bristle_colours(sources, anchors, angles, tip, params.bristle_alpha, deviation, jitter.shift,
                              jitter.offset, lightness=params.perturbation > 0)
    if params.renderer == "lines":
        brush = colours.anchor
    else:
        brush = np.einsum("b,nbc->nc", tip.intensity, colours.bristles) / tip.intensity.sum()
    paths = plan_paths(anchors, size, orientation, canvas.colour, brush, sources.reference, sources.edges, params)
    return RoundPlan(anchors, colours.bristles, colours.anchor, paths, angles)


def lay_round(canvas: Canvas, plan: RoundPlan, size: int, tip: BrushTip, params: Params) -> None:
    """Lay a plan's strokes on ``canvas`` in order (a solid line's opacity is its ``plan.contact``)."""
    paths = plan.paths
    if params.renderer == "lines":
        if canvas.frame_height is not None or canvas.only is not None:
            raise ValueError("solid lines are drawn on every pixel of a whole frame")
        every = max(1, int(size) // 4)
        alphas = np.ones(len(paths.first)) if plan.contact is None else plan.contact.astype(np.float64)
        for i in range(len(paths.first)):
            curve = paths.samples[i, paths.first[i]:paths.last[i] + 1]
            line = curve[np.unique(np.append(np.arange(0, len(curve), every), len(curve) - 1))]
            solid_stroke(canvas, line, 0.5 * size, plan.anchor_colours[i], float(alphas[i]), params.height_mode,
                         params.height_build)
        return
    canvas.lay(footprint_runs(plan, size, tip, params, canvas.frame_shape), params.height_mode,
               params.height_build)


def footprint_runs(plan: RoundPlan, size: int, tip: BrushTip, params: Params, shape: tuple) -> List[Footprints]:
    """The ``Footprints`` of consecutive runs of a plan's strokes on a canvas of ``shape`` (H, W), made on the
    worker threads."""
    return in_runs(plan, size, tip, lambda part: strokes_footprints(part, size, tip, params, shape))


def judged_footprints(plan: RoundPlan, size: int, tip: BrushTip, params: Params, colour: np.ndarray,
                      reference: np.ndarray) -> JudgedFootprints:
    """``footprint_runs`` of a plan's N strokes and whether each ``improves`` the canvas ``colour`` (H, W, 3) by
    its ``plan.ratios``, runs of strokes made and judged on the worker threads."""
    def made_and_judged(part: RoundPlan) -> JudgedFootprints:
        footprints = strokes_footprints(part, size, tip, params, colour.shape[:2])
        judged = part.ratios > 0                                         # 0: laid unjudged
        mends = np.zeros(len(judged), bool)
        if judged.any():
            mends[judged] = improves(colour, footprints, reference, part.ratios[judged],
                                     None if judged.all() else judged)
        return JudgedFootprints([footprints], mends)

    parts = in_runs(plan, size, tip, made_and_judged)
    return JudgedFootprints([part.runs[0] for part in parts], np.concatenate([part.mends for part in parts]))


def in_runs(plan: RoundPlan, size: int, tip: BrushTip, work) -> list:
    """[work(plan of a run of strokes), ...] over runs of a plan's strokes of about equal track samples, in order,
    on the worker threads."""
    runs = balanced_runs(track_costs(plan.paths, tip, size), worker_count(), tuning.WORKER_LEAST_SAMPLES)
    return run_all(lambda run: work(plan.subset(slice(*run))), runs)


def strokes_footprints(plan: RoundPlan, size: int, tip: BrushTip, params: Params, shape: tuple) -> Footprints:
    """The ``Footprints`` of a plan's strokes on a canvas of ``shape`` (H, W), made together. A stroke's
    ``plan.contact`` c below 1 (a fading stroke) presses the brush c as hard (each stamp's contact times c) and
    counts its full deposit as the stroke's at full contact (``Footprints.full`` / c): it lays a thinner coat that
    covers c as fully, so it moves the relief c of the way to its own height rather than replacing the paint
    beneath with a thin one (``canvas.composite``)."""
    stamps = stamp_paths(plan.paths, plan.angles, size, params)
    contact = stamps.contact
    if plan.contact is not None:
        contact = contact * np.repeat(np.asarray(plan.contact, np.float32), np.diff(stamps.starts))
    rows = max(1.0, tip.length)
    footprints = track_footprints(stamps.points, stamps.directions, stamps.starts, tip, plan.colours, shape,
                                  passes=max(1.0, MIN_ROWS / rows), contact=contact, stamp_relief=stamps.relief,
                                  bristle_relief=ridge_profile(tip.across, tip.radius, params.ridge_height), rows=rows)
    if plan.contact is not None and np.any(plan.contact < 1):
        factor = np.asarray(plan.contact, np.float32)
        faded = np.divide(footprints.full, factor, out=np.zeros_like(footprints.full), where=factor > 0)
        footprints.full = np.where(factor < 1, faded, footprints.full)
    return footprints


def records(plan: RoundPlan, size: int, layer: int) -> List[Stroke]:
    """The ``Stroke`` records of a plan's strokes, in order."""
    return [Stroke(layer, (int(x), int(y)), int(size), plan.paths.polyline(i), plan.anchor_colours[i])
            for i, (x, y) in enumerate(plan.anchors.tolist())]
