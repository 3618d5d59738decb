"""A painting's strokes as a list that can be laid again: everything each stroke needs, in laying order (ALGORITHM §9).

A ``StrokeList`` holds N laid strokes as arrays: layer, size, brush, anchor,
the control points of the curve and the part of it kept, the bristle
colours as laid, the anchor colour and a contact factor. ``lay_strokes``
lays a list on a canvas through the engine's own pieces (the curve re-sampled
from the control points by ``catmull_rom``, ``lay_chunks`` and ``lay_round``),
so laying a painting's list on a blank canvas gives the painting's bytes:
each frame of a sequence is a function of its stroke list alone, and a
stroke carried to the next frame is its record with moved control points.
``StrokeRecorder`` gathers the list while a painter lays its rounds.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Dict, List, Optional, Tuple

import numpy as np

from ..params import Params
from .brush import BrushTip, brush_tip, load_brush
from .canvas import Canvas
from .path import catmull_rom, polygon_lengths
from .planning import PlannedPaths, samples_per_segment
from .rounds import RoundPlan, lay_chunks, lay_round

PAINTING_BRUSH = 0
"""A stroke laid with the painting's brush (``Params.brush``), as the layers' strokes are."""

ROUND_BRUSH = 1
"""A stroke laid with the round brush, as the detail pass's dabs are whatever the painting's brush."""


@dataclass(frozen=True)
class StrokeList:
    """N laid strokes in laying order, each with what laying it again needs.

    layer: int32 (N,) 0-based layer (the detail pass is the layer after the last).
    size: int32 (N,) brush width (px).
    brush: int8 (N,) PAINTING_BRUSH or ROUND_BRUSH, the brush the stroke is laid with.
    anchor: float64 (N, 2) (x, y) px.
    control: float64 (N, P, 2) (x, y) px, the control points of each curve, backward end -> forward end; stroke
             i's are control[i, :control_count[i]], the rest NaN. The curve is ``catmull_rom`` of them with
             ``samples_per_segment(size)`` samples per segment.
    control_count: int32 (N,) >= 1.
    first, last: int64 (N,) the curve samples kept (first .. last, inclusive): the stroke's path.
    angle: float64 (N,) radians, the orientation at the anchor (the direction of a stroke of one stamp).
    bristles: float32 (M, 3) sRGB [0, 1], every bristle's colour as laid (Eq. 5), stroke after stroke; stroke
              i's are bristles[bristle_starts[i]:bristle_starts[i + 1]], one per bristle of its brush tip
              (ragged: a tip has from 2 to thousands of bristles by its width).
    bristle_starts: int64 (N + 1,).
    anchor_colour: float32 (N, 3) sRGB [0, 1], the colour at the anchor the bristle colours were mixed from.
    contact: float32 (N,) in [0, 1], the factor on the stroke's contact (1 for a still's strokes; a fading
             stroke's below 1).
    """

    layer: np.ndarray
    size: np.ndarray
    brush: np.ndarray
    anchor: np.ndarray
    control: np.ndarray
    control_count: np.ndarray
    first: np.ndarray
    last: np.ndarray
    angle: np.ndarray
    bristles: np.ndarray
    bristle_starts: np.ndarray
    anchor_colour: np.ndarray
    contact: np.ndarray

    def __len__(self) -> int:
        """The number of strokes N."""
        return len(self.layer)

    @classmethod
    def empty(cls) -> "StrokeList":
        """A list of no strokes."""
        return cls(np.zeros(0, np.int32), np.zeros(0, np.int32), np.zeros(0, np.int8), np.zeros((0, 2)),
                   np.zeros((0, 1, 2)), np.zeros(0, np.int32), np.zeros(0, np.int64), np.zeros(0, np.int64),
                   np.zeros(0), np.zeros((0, 3), np.float32), np.zeros(1, np.int64), np.zeros((0, 3), np.float32),
                   np.zeros(0, np.float32))

    @classmethod
    def from_plan(cls, plan: RoundPlan, size: int, layer: int, brush: int) -> "StrokeList":
        """The list of a round's laid strokes: ``plan`` of N strokes ``size`` px wide of ``layer``, laid with
        ``brush`` (PAINTING_BRUSH or ROUND_BRUSH) at ``plan.contact`` (full contact when None).

        The control points are the curve samples at multiples of ``per_segment`` (``catmull_rom`` passes
        through them exactly), so re-sampling them gives the plan's samples to the bit.
        """
        paths = plan.paths
        n, samples = paths.samples.shape[:2]
        if (samples - 1) % paths.per_segment:
            raise ValueError(f"{samples} curve samples are not whole segments of {paths.per_segment}")
        control = paths.samples[:, ::paths.per_segment].astype(np.float64)
        bristles = np.asarray(plan.colours, np.float32)
        contact = np.ones(n, np.float32) if plan.contact is None else np.asarray(plan.contact, np.float32)
        return cls(np.full(n, layer, np.int32), np.full(n, size, np.int32), np.full(n, brush, np.int8),
                   np.asarray(plan.anchors, np.float64).reshape(n, 2), control,
                   np.full(n, control.shape[1], np.int32), np.asarray(paths.first, np.int64),
                   np.asarray(paths.last, np.int64), np.asarray(plan.angles, np.float64),
                   bristles.reshape(-1, 3), np.arange(n + 1, dtype=np.int64) * bristles.shape[1],
                   np.asarray(plan.anchor_colours, np.float32).reshape(n, 3), contact)

    @staticmethod
    def joined(parts: List["StrokeList"]) -> "StrokeList":
        """One list of several, one after another (control points padded with NaN to the longest)."""
        if not parts:
            return StrokeList.empty()
        width = max(part.control.shape[1] for part in parts)
        control = np.concatenate([np.pad(part.control, ((0, 0), (0, width - part.control.shape[1]), (0, 0)),
                                         constant_values=np.nan) for part in parts])
        offsets = np.cumsum([0] + [len(part.bristles) for part in parts[:-1]])
        starts = np.concatenate([[0]] + [part.bristle_starts[1:] + offset
                                         for part, offset in zip(parts, offsets, strict=True)])
        join = lambda name: np.concatenate([getattr(part, name) for part in parts])  # noqa: E731
        return StrokeList(join("layer"), join("size"), join("brush"), join("anchor"), control, join("control_count"),
                          join("first"), join("last"), join("angle"), join("bristles"), starts.astype(np.int64),
                          join("anchor_colour"), join("contact"))

    def subset(self, index) -> "StrokeList":
        """The list of some of the strokes: ``index`` a slice, a (K,) int array (in its order) or an (N,) bool
        mask (in the list's order)."""
        picked = np.arange(len(self))[index]
        entries, starts = bristle_entries(self.bristle_starts, picked)
        return StrokeList(self.layer[picked], self.size[picked], self.brush[picked], self.anchor[picked],
                          self.control[picked], self.control_count[picked], self.first[picked], self.last[picked],
                          self.angle[picked], self.bristles[entries], starts, self.anchor_colour[picked],
                          self.contact[picked])

    def runs(self) -> List[Tuple[int, int]]:
        """[(first, stop), ...]: the runs of consecutive strokes of one size, brush and control point count,
        in order (each is laid as one round is)."""
        if len(self) == 0:
            return []
        key = np.stack([self.size, self.brush, self.control_count], axis=1)
        cuts = np.flatnonzero(np.any(key[1:] != key[:-1], axis=1)) + 1
        bounds = np.concatenate(([0], cuts, [len(self)])).tolist()
        return list(zip(bounds[:-1], bounds[1:], strict=True))

    def round_plan(self, first: int, stop: int) -> RoundPlan:
        """The plan of strokes first .. stop - 1, one run of ``runs``: the curves re-sampled from the control
        points, the anchors at their nearest pixels."""
        size, count = int(self.size[first]), int(self.control_count[first])
        per_segment = samples_per_segment(size)
        samples = catmull_rom(np.ascontiguousarray(self.control[first:stop, :count]), per_segment)
        entries = self.bristle_starts[first:stop + 1]
        colours = self.bristles[entries[0]:entries[-1]].reshape(stop - first, -1, 3)
        contact = self.contact[first:stop]
        return RoundPlan(np.floor(self.anchor[first:stop] + 0.5).astype(np.int64), colours,
                         self.anchor_colour[first:stop],
                         PlannedPaths(samples, self.first[first:stop], self.last[first:stop], per_segment),
                         self.angle[first:stop], None, None if np.all(contact == 1) else contact)


def bristle_entries(bristle_starts: np.ndarray, picked: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """The bristles of some strokes of a list: ``bristle_starts`` (N + 1,) the list's, ``picked`` (K,) int stroke
    indices. Returns (entries (B,) int64, the picked strokes' bristle rows in order; starts (K + 1,) int64, where
    each picked stroke's bristles begin among them)."""
    counts = np.diff(bristle_starts)[picked]
    starts = np.zeros(len(picked) + 1, np.int64)
    np.cumsum(counts, out=starts[1:])
    return np.repeat(bristle_starts[picked] - starts[:-1], counts) + np.arange(starts[-1]), starts


def reach_margins(strokes: StrokeList) -> np.ndarray:
    """(N,) float64 px: how far each stroke's paint may lie from its control polygon. The brush reaches at most
    0.62 of its width beyond its control points on the painter's strokes (half across, a little along, the
    filter's edge); a Catmull-Rom curve strays from a segment of its control polygon by less than half the longest
    step between its control points (a third of it at most); and 2 px."""
    steps = np.linalg.norm(np.diff(strokes.control, axis=1), axis=2) if strokes.control.shape[1] > 1 else \
        np.zeros((len(strokes), 1))
    return strokes.size + 0.5 * np.nanmax(np.where(np.isnan(steps), 0.0, steps), axis=1) + 2.0


def reach_boxes(strokes: StrokeList) -> np.ndarray:
    """(N, 4) float64 px: (x0, x1, y0, y1), a box around each stroke that its paint does not leave: its control
    points' box widened by its ``reach_margins``."""
    if len(strokes) == 0:
        return np.zeros((0, 4))
    margin = reach_margins(strokes)[:, None]
    low, high = np.nanmin(strokes.control, axis=1) - margin, np.nanmax(strokes.control, axis=1) + margin
    return np.stack([low[:, 0], high[:, 0], low[:, 1], high[:, 1]], axis=1)


def segment_boxes(strokes: StrokeList) -> Tuple[np.ndarray, np.ndarray]:
    """Boxes around the pieces of the strokes' paint, tighter than ``reach_boxes`` for a long or curved stroke:
    (S, 4) float64 px (x0, x1, y0, y1), one per segment of each control polygon (one per stroke of a single
    control point) widened by the stroke's ``reach_margins``, and owner (S,) int64, the stroke each belongs to, in
    order. A stroke's paint does not leave the union of its boxes."""
    if len(strokes) == 0:
        return np.zeros((0, 4)), np.zeros(0, np.int64)
    control, count = strokes.control, strokes.control_count
    segments = np.maximum(count - 1, 1)
    owner = np.repeat(np.arange(len(strokes)), segments)
    step = np.arange(len(owner)) - np.repeat(np.cumsum(segments) - segments, segments)
    start = control[owner, step]
    end = control[owner, np.minimum(step + 1, count[owner] - 1)]
    margin = reach_margins(strokes)[owner, None]
    low, high = np.minimum(start, end) - margin, np.maximum(start, end) + margin
    return np.stack([low[:, 0], high[:, 0], low[:, 1], high[:, 1]], axis=1), owner


def reaching_rows(strokes: StrokeList, first_row: int, stop_row: int) -> np.ndarray:
    """(N,) bool: the strokes whose paint may reach the canvas rows first_row .. stop_row - 1 (``reach_boxes``);
    laying the strokes this picks gives those rows exactly as laying every stroke does."""
    boxes = reach_boxes(strokes)
    return (boxes[:, 3] >= first_row) & (boxes[:, 2] < stop_row)


LAYING_SHARE = 0.4
"""The share of laying strokes that is compositing their paint onto the canvas, which a band of rows pays for its
own rows only; the rest, making each stroke's footprint, a band pays in full for every stroke that reaches it
(measured at 1920x1080: 0.54 s of 1.35 s)."""


def laying_bands(strokes: StrokeList, height: int, parts: int) -> List[Tuple[int, int]]:
    """[(first, stop), ...]: at most ``parts`` consecutive bands of a frame's ``height`` rows, none empty, whose
    largest work of laying ``strokes`` (``reaching_rows`` each) is the least any such cut gives.

    A stroke's work is its footprint, about (its control polygon's length + its width) x its width px, made in
    full by every band it reaches, and composited by each band on its own rows: a band of rows a .. b - 1 works
    (1 - LAYING_SHARE) x the work of the strokes reaching it + LAYING_SHARE x the work of all (b - a) / height.
    The least largest work is found to 1 part in 1000 by bisection, each bound tried by cutting greedily."""
    parts = max(1, min(parts, height))
    if parts == 1 or len(strokes) == 0:
        return [(0, height)]
    boxes = reach_boxes(strokes)
    work = (polygon_lengths(strokes.control, strokes.control_count) + strokes.size) * strokes.size
    total = float(work.sum())
    # reach(a, b) = total - work of strokes ending above row a - work of strokes starting at row b or below
    ends = np.clip(np.floor(boxes[:, 3]).astype(np.int64) + 1, 0, height + 1)
    ended = np.cumsum(np.bincount(ends, work, minlength=height + 2))[:height + 1]   # ended[a]: ending above row a
    starts = np.clip(np.floor(boxes[:, 2]).astype(np.int64), -1, height)
    begun = np.bincount(starts + 1, work, minlength=height + 2)
    after = np.cumsum(begun[::-1])[::-1]                      # after[r + 1]: work of strokes starting at row >= r
    rows = np.arange(height + 1)

    def cost(first: int) -> np.ndarray:
        """(height + 1,) the work of the band first .. b - 1 for every stop b (first + 1 .. height meaningful)."""
        reaching = total - ended[first] - after[np.minimum(rows, height) + 1]
        return (1 - LAYING_SHARE) * reaching + LAYING_SHARE * total * (rows - first) / height

    def cut(bound: float) -> List[Tuple[int, int]]:
        """The bands greedily as long as their work stays within ``bound`` (at least one row each)."""
        bands, first = [], 0
        while first < height:
            fits = np.flatnonzero(cost(first)[first + 1:] <= bound)
            stop = first + 1 + (int(fits[-1]) if fits.size else 0)
            bands.append((first, stop))
            first = stop
        return bands

    low, high = 0.0, total
    best = cut(high)
    while high - low > 1e-3 * total:
        middle = 0.5 * (low + high)
        bands = cut(middle)
        if len(bands) <= parts:
            best, high = bands, middle
        else:
            low = middle
    return best


def lay_strokes(canvas: Canvas, strokes: StrokeList, tips: Dict[Tuple[int, int], BrushTip], params: Params,
                report: Optional[Callable[[int], None]] = None) -> None:
    """Lay ``strokes`` on ``canvas`` in the list's order, as the painter laid them (``lay_round``, one
    ``lay_chunks`` chunk of a run after another). tips: {(brush, size): BrushTip} (``stroke_tips``); params:
    the renderer, height mode and build, taper and relief the strokes were painted with. A run's bristle
    colours must be one per bristle of its tip (ValueError). ``report`` (optional) hears the strokes laid so far
    after each chunk (it may raise, to stop)."""
    for first, stop in strokes.runs():
        size = int(strokes.size[first])
        tip = tips[int(strokes.brush[first]), size]
        if np.any(np.diff(strokes.bristle_starts[first:stop + 1]) != len(tip)):
            raise ValueError(f"strokes {first}..{stop - 1} do not have one colour per bristle of their "
                             f"{len(tip)}-bristle brush")
        plan = strokes.round_plan(first, stop)
        for start, end in lay_chunks(plan.paths, tip, size):
            lay_round(canvas, plan.subset(slice(start, end)), size, tip, params)
            if report is not None:
                report(first + end)


def stroke_tips(strokes: StrokeList, params: Params) -> Dict[Tuple[int, int], BrushTip]:
    """{(brush, size): BrushTip} of every brush and size in ``strokes``: ``Params.brush`` for PAINTING_BRUSH, the
    round brush for ROUND_BRUSH, at ``params.transparency`` (the tips the painter made)."""
    pairs = sorted(set(zip(strokes.brush.tolist(), strokes.size.tolist(), strict=True)))
    names = {PAINTING_BRUSH: params.brush, ROUND_BRUSH: "round"}
    maps = {brush: load_brush(names[brush]) for brush in {brush for brush, _ in pairs}}
    return {(brush, size): brush_tip(maps[brush], size, params.transparency) for brush, size in pairs}


class StrokeRecorder:
    """Gathers the ``StrokeList`` of the strokes a painter lays, round after round."""

    def __init__(self) -> None:
        self.parts: List[StrokeList] = []

    def round(self, size: int, layer: int, brush: int) -> Callable[[RoundPlan], None]:
        """What ``paint_round``'s ``record`` calls with the plan of a round of ``layer``'s strokes ``size`` px
        wide laid with ``brush``: keeps them."""
        return lambda plan: self.parts.append(StrokeList.from_plan(plan, size, layer, brush))

    def stroke_list(self) -> StrokeList:
        """Every stroke kept so far, in laying order."""
        return StrokeList.joined(self.parts)


def recording(recorder: Optional[StrokeRecorder], size: int, layer: int,
              brush: int) -> Optional[Callable[[RoundPlan], None]]:
    """``recorder.round(size, layer, brush)``, or None without a recorder (nothing is kept)."""
    return None if recorder is None else recorder.round(size, layer, brush)
