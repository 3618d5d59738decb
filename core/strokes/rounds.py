"""Painting in rounds: every stroke of one size in a layer planned at once, then laid in order (ALGORITHM §5, "Speed").

A round's strokes are planned (bristle colours, path, stopping tests)
against the canvas as it stood when the round began, all together as
arrays; they are then laid in the round's order, each stroke's Eq. 4
contributions after the previous one's, so overlaps composite exactly as
laying them one by one would.
"""

from __future__ import annotations

from typing import List

import numpy as np

from ..params import Params
from ..workers import balanced_runs, run_all, worker_count
from .brush import BrushTip
from .canvas import Canvas, pixel_rows
from .compositing import Footprints, track_footprints
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
    solid_stroke,
)

# Curve samples (times bristles and channels, roughly) planned together at most: bounds the memory of planning.
PLAN_CHUNK_SAMPLES = 1 << 23

# Track samples (times brush columns) laid together at most: bounds the memory of a round's footprints
# (about 100 bytes each), whatever the brush size.
LAY_CHUNK_SAMPLES = 1 << 20

# Track samples (times brush columns) below which a run of strokes is not split between worker threads.
WORKER_LEAST_SAMPLES = 1 << 15
# Strokes below which a round's planning is not split between worker threads.
WORKER_LEAST_STROKES = 64


def stamp_paths(paths: PlannedPaths, angles: np.ndarray, size: int, params: Params) -> tuple:
    """Stamps one px apart along N planned paths: (stamps (M, 2), directions (M,), contact (M,), relief (M,), starts (N + 1,))."""
    stamps, arc, starts = resample_by_length(paths.samples, paths.first, paths.last)
    directions = tangent_angles(stamps, starts, angles)
    total = np.repeat(arc[starts[1:] - 1], np.diff(starts))
    contact, relief = end_profile(arc, total, size, params.taper, params.lift_buildup)
    return stamps, directions, contact, relief, starts


def paint_round(canvas: Canvas, sources: ColourSources, orientation: np.ndarray, anchors: np.ndarray, size: int,
                layer: int, tip: BrushTip, draws: np.ndarray, params: Params,
                judged: np.ndarray = None) -> List[Stroke]:
    """Plan and lay N strokes ``size`` px wide from (N, 2) int ``anchors`` (x, y); returns their records.

    draws: (N, 4) uniform numbers of each stroke's own stream (its colour
    perturbation, ``colour_jitter``). judged: optional (N,) float >= 0,
    stroke i is laid only if it mends more than judged[i] times the error
    it spoils (``improves``), judged alone on the canvas as the round found
    it; 0 lays it unjudged (all are, by the 'lines' renderer).
    """
    anchors = np.asarray(anchors, np.int64).reshape(-1, 2)
    if len(anchors) == 0:
        return []
    if judged is not None:
        judged = None if params.renderer == "lines" else np.asarray(judged, np.float64)
    plan = plan_round(canvas, sources, orientation, anchors, size, tip, draws, params)
    chunks = lay_chunks(plan["paths"], tip, size)
    if judged is not None and judged.any():
        plan["ratios"] = judged
        kept = judge_and_lay(canvas, plan, chunks, size, tip, params, sources.reference)
        return records(subset(plan, kept), size, layer)
    for first, stop in chunks:
        lay_round(canvas, subset(plan, slice(first, stop)), size, tip, params)
    return records(plan, size, layer)


def judge_and_lay(canvas: Canvas, plan: dict, chunks: list, size: int, tip: BrushTip, params: Params,
                  reference: np.ndarray) -> np.ndarray:
    """Judge a plan's strokes by their ``plan["ratios"]`` (``improves``; 0 keeps a stroke unjudged) on the canvas
    as the round found it, and lay the kept ones in order, one of ``lay_chunks``' (first, stop) ``chunks`` after
    another; returns the kept strokes' indices, ascending.

    Each chunk's footprints are made once, judged, and its kept strokes' footprints laid before the next chunk
    is made, so a round holds one chunk's footprints at a time. A round of several chunks judges against a
    copy of the canvas colour taken before its first chunk is laid (the judge reads nothing else).
    """
    found = canvas.colour.copy() if len(chunks) > 1 else canvas.colour
    kept = []
    for first, stop in chunks:
        part = subset(plan, slice(first, stop))
        footprints, mends = judged_footprints(part, size, tip, params, found, reference)
        keep = mends | (part["ratios"] == 0)
        canvas.lay(footprints, params.height_mode, params.height_build, keep)
        kept.append(first + np.flatnonzero(keep))
    return np.concatenate(kept)


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
    before = np.take(pixel_rows(colour.reshape(-1, 3)), pixel).view(np.float32).reshape(-1, 3)
    target = np.take(pixel_rows(reference.reshape(-1, 3)), pixel).view(np.float32).reshape(-1, 3)
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


def subset(plan: dict, index) -> dict:
    """The plan of some of ``plan``'s strokes, in order: ``index`` a slice or ascending (K,) int array."""
    paths = plan["paths"]
    part = {key: value[index] for key, value in plan.items() if key != "paths"}
    part["paths"] = PlannedPaths(paths.samples[index], paths.first[index], paths.last[index], paths.per_segment)
    return part


def lay_chunks(paths: PlannedPaths, tip: BrushTip, size: int) -> list:
    """[(first, stop), ...]: runs of consecutive strokes whose track samples times brush columns stay within
    LAY_CHUNK_SAMPLES (a stroke of more is a run of its own). A stroke's track is at most its kept curve's
    length in px (curve samples ``sample_spacing`` apart) plus the brush's length."""
    n = len(paths.first)
    total = np.cumsum(track_costs(paths, tip, size))
    bounds, first = [], 0
    while first < n:
        stop = int(np.searchsorted(total, (total[first - 1] if first else 0) + LAY_CHUNK_SAMPLES, side="right"))
        stop = max(stop, first + 1)
        bounds.append((first, stop))
        first = stop
    return bounds


def track_costs(paths: PlannedPaths, tip: BrushTip, size: int) -> np.ndarray:
    """(N,) int64: an upper bound on each stroke's track samples times brush columns: its kept curve's length
    in px (curve samples ``sample_spacing`` apart) plus the brush's length, times the brush's columns."""
    length = np.ceil((paths.last - paths.first) * sample_spacing(size)).astype(np.int64)
    return (length + int(tip.length) + 3) * (int(np.ptp(tip.across)) + 1)


def plan_round(canvas: Canvas, sources: ColourSources, orientation: np.ndarray, anchors: np.ndarray, size: int,
               tip: BrushTip, draws: np.ndarray, params: Params) -> dict:
    """Everything N strokes need to be laid, planned against ``canvas`` as it is now.

    Returns {"anchors" (N, 2), "colours" (N, B, 3) bristle colours,
    "anchor_colours" (N, 3), "paths" PlannedPaths, "angles" (N,)}. The
    strokes are planned in runs on the worker threads (the canvas does not
    change in between), as many runs as a multiple of the workers,
    PLAN_CHUNK_SAMPLES curve samples at a time in all, which bounds the
    memory of the tests.
    """
    workers = worker_count()
    samples = (2 * max(0, params.max_length - 1) * samples_per_segment(size) + 1) * (len(tip) + 8)
    step = max(1, PLAN_CHUNK_SAMPLES // (samples * workers))
    n = len(anchors)
    count = max(-(-n // step), min(workers, n // WORKER_LEAST_STROKES))
    if count > 1:
        count = min(n, -(-count // workers) * workers)                 # every worker busy to the last run
    bounds = np.linspace(0, n, max(count, 1) + 1).astype(np.int64).tolist()
    runs = [slice(a, b) for a, b in zip(bounds[:-1], bounds[1:], strict=True)]
    parts = run_all(lambda run: plan_strokes(canvas, sources, orientation, anchors[run], size, tip, draws[run],
                                             params), runs)
    if len(parts) == 1:
        return parts[0]
    paths = [part["paths"] for part in parts]
    plan = {key: np.concatenate([part[key] for part in parts]) for key in ("anchors", "colours", "anchor_colours",
                                                                            "angles")}
    plan["paths"] = PlannedPaths(np.concatenate([p.samples for p in paths]), np.concatenate([p.first for p in paths]),
                                 np.concatenate([p.last for p in paths]), paths[0].per_segment)
    return plan


def plan_strokes(canvas: Canvas, sources: ColourSources, orientation: np.ndarray, anchors: np.ndarray, size: int,
                 tip: BrushTip, draws: np.ndarray, params: Params) -> dict:
    """``plan_round`` of one chunk of strokes."""
    angles = orientation[anchors[:, 1], anchors[:, 0]].astype(np.float64)
    shift, offset = colour_jitter(draws, params.perturbation, params.hue_perturbation)
    deviation = params.bristle_deviation if sources.deviation is None else sources.deviation
    colours, anchor_colours = bristle_colours(sources, anchors, angles, tip, params.bristle_alpha, deviation, shift,
                                              offset, lightness=params.perturbation > 0)
    if params.renderer == "lines":
        brush = anchor_colours
    else:
        brush = np.einsum("b,nbc->nc", tip.intensity, colours) / tip.intensity.sum()
    paths = plan_paths(anchors, size, orientation, canvas.colour, brush, sources.reference, sources.edges, params)
    return {"anchors": anchors, "colours": colours, "anchor_colours": anchor_colours, "paths": paths,
            "angles": angles}


def lay_round(canvas: Canvas, plan: dict, size: int, tip: BrushTip, params: Params) -> None:
    """Lay a plan's strokes on ``canvas`` in order."""
    paths = plan["paths"]
    if params.renderer == "lines":
        every = max(1, int(size) // 4)
        for i in range(len(paths.first)):
            kept = paths.samples[i, paths.first[i]:paths.last[i] + 1]
            line = kept[np.unique(np.append(np.arange(0, len(kept), every), len(kept) - 1))]
            solid_stroke(canvas, line, 0.5 * size, plan["anchor_colours"][i], 1.0, params.height_mode,
                         params.height_build)
        return
    canvas.lay(footprint_runs(plan, size, tip, params, canvas.height.shape), params.height_mode,
               params.height_build)


def footprint_runs(plan: dict, size: int, tip: BrushTip, params: Params, shape: tuple) -> List[Footprints]:
    """The ``Footprints`` of consecutive runs of a plan's strokes on a canvas of ``shape`` (H, W), made on the
    worker threads."""
    return in_runs(plan, size, tip, lambda part: strokes_footprints(part, size, tip, params, shape))


def judged_footprints(plan: dict, size: int, tip: BrushTip, params: Params, colour: np.ndarray,
                      reference: np.ndarray) -> tuple:
    """(``footprint_runs`` of a plan's N strokes, (N,) bool whether each ``improves`` the canvas ``colour``
    (H, W, 3) by its ``plan["ratios"]``), runs of strokes made and judged on the worker threads."""
    def made_and_judged(part: dict) -> tuple:
        footprints = strokes_footprints(part, size, tip, params, colour.shape[:2])
        judged = part["ratios"] > 0                                      # 0: laid unjudged
        mends = np.zeros(len(judged), bool)
        if judged.any():
            mends[judged] = improves(colour, footprints, reference, part["ratios"][judged],
                                     None if judged.all() else judged)
        return footprints, mends

    parts = in_runs(plan, size, tip, made_and_judged)
    return [part[0] for part in parts], np.concatenate([part[1] for part in parts])


def in_runs(plan: dict, size: int, tip: BrushTip, work) -> list:
    """[work(plan of a run of strokes), ...] over runs of a plan's strokes of about equal track samples, in order,
    on the worker threads."""
    runs = balanced_runs(track_costs(plan["paths"], tip, size), worker_count(), WORKER_LEAST_SAMPLES)
    return run_all(lambda run: work(subset(plan, slice(*run))), runs)


def strokes_footprints(plan: dict, size: int, tip: BrushTip, params: Params, shape: tuple) -> Footprints:
    """The ``Footprints`` of a plan's strokes on a canvas of ``shape`` (H, W), made together."""
    stamps, directions, contact, relief, starts = stamp_paths(plan["paths"], plan["angles"], size, params)
    rows = max(1.0, tip.length)
    return track_footprints(stamps, directions, starts, tip, plan["colours"], shape,
                            passes=max(1.0, MIN_ROWS / rows), contact=contact, stamp_relief=relief,
                            bristle_relief=ridge_profile(tip.across, tip.radius, params.ridge_height), rows=rows)


def records(plan: dict, size: int, layer: int) -> List[Stroke]:
    """The ``Stroke`` records of a plan's strokes, in order."""
    paths = plan["paths"]
    return [Stroke(layer, (int(x), int(y)), int(size), paths.polyline(i), plan["anchor_colours"][i])
            for i, (x, y) in enumerate(plan["anchors"].tolist())]
