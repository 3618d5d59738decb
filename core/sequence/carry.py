"""Carrying a frame's strokes to the next frame, and which of them die on the way (ALGORITHM §9, carry and death).

Every control point and the anchor move by the forward motion at their
position (bilinear); the curve is re-sampled from the moved control points
when the list is laid. A stroke dies at once when its anchor is not visible in
both frames (occluded, or it left the canvas), or more than a quarter of its
control points are hidden. It starts to fade out, still
moving, when its control polygon's length has changed by more than
``STRETCH`` either way since its birth, when it bends at a control point
by more than T_o otherwise than before (the surface under it folded), when the next frame's partition asks
for a size two or more steps away at its anchor, or when a stroke of its size
and layer lies less than half a width from it earlier in the order (crowding).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Dict, NamedTuple, Sequence

import numpy as np
from scipy.spatial import cKDTree

from ..motion.warp import bilinear, inside_frame
from ..strokes.layout import summed_area
from ..strokes.path import nearest_pixels, polygon_lengths
from ..strokes.smoothing import SmoothedImage
from ..strokes.stroke_list import PAINTING_BRUSH
from .living import LivingStrokes

HIDDEN_SHARE = 0.25
"""A stroke dies at once when more than this share of its control points is hidden in the next frame."""

STRETCH = 1.5
"""A stroke dies when its control polygon grows or shrinks by more than this factor since its birth."""

SIZE_STEPS = 2
"""A stroke dies when the partition asks for a stroke size this many standard sizes away from its own."""

CLOSER = 0.01
"""px: two strokes crowd each other only when they came closer by more than this (moved together, they did not)."""

SHORTEST_SEGMENT = 0.5
"""px: control polygon segments shorter than this have no direction to turn from."""


class CarrySurvivors(NamedTuple):
    """A frame's strokes carried to the next frame: the survivors and how many died on the way."""

    living: LivingStrokes       # the survivors, dying ones included, at their new fade levels
    occluded: int               # strokes gone at once: occluded or off the canvas
    faded: int                  # strokes whose fade-out ended


def carry(living: LivingStrokes, forward: np.ndarray, visible: np.ndarray, size_map: np.ndarray,
          sizes: Sequence[int], orientation_threshold: float) -> CarrySurvivors:
    """Move ``living`` by ``forward`` (H, W, 2) px (frame t to t+1) and decide which strokes die.

    visible: (H, W) bool, frame t's pixels visible in both frames. size_map: (H, W) int, the stroke size (px) frame
    t+1's partition asks for at each pixel. sizes: the standard sizes (px), descending. orientation_threshold: T_o,
    radians. Detail dabs (round-brush strokes) keep their size whatever the partition asks.
    """
    strokes = living.strokes
    h, w = visible.shape
    rows, cols = nearest_pixels((h, w), strokes.anchor[:, 0], strokes.anchor[:, 1])
    anchor = strokes.anchor + bilinear(forward, strokes.anchor)
    valid = np.arange(strokes.control.shape[1])[None, :] < strokes.control_count[:, None]
    kept = visible[rows, cols] & inside_frame(anchor, h, w) & ~hidden(strokes.control, valid, visible)
    control = np.where(valid[..., None], strokes.control + bilinear(forward, strokes.control), np.nan)
    moved = replace(strokes, anchor=anchor, control=control)
    dies = (stretched(polygon_lengths(control, strokes.control_count), living.birth_length)
            | folded(strokes.control, control, valid, orientation_threshold)
            | resized(anchor, strokes.size, strokes.brush, size_map, sizes))
    survivors = replace(living, strokes=moved).subset(kept)
    dies = dies[kept]
    dying = survivors.dying | dies | crowded(survivors.strokes, strokes.anchor[kept], survivors.dying | dies)
    level = np.where(dying, survivors.level - 1, np.minimum(survivors.level + 1, living.fade_frames))
    stepped = replace(survivors, level=level.astype(np.int32), dying=dying)
    left = level > 0
    return CarrySurvivors(stepped.subset(left).with_contact(), int(np.count_nonzero(~kept)), int(np.count_nonzero(~left)))


def hidden(control: np.ndarray, valid: np.ndarray, visible: np.ndarray) -> np.ndarray:
    """(N,) bool: more than HIDDEN_SHARE of a stroke's control points (N, P, 2) px, ``valid`` (N, P), lie on pixels
    of frame t that are not ``visible`` (H, W) in frame t+1 (nearest pixel; points off the canvas are not counted):
    an object that moves over a stroke hides it, though its anchor be left in sight."""
    h, w = visible.shape
    x, y = np.where(valid, control[..., 0], -1.0), np.where(valid, control[..., 1], -1.0)
    on_canvas = valid & (x > -0.5) & (x < w - 0.5) & (y > -0.5) & (y < h - 0.5)
    rows, cols = nearest_pixels((h, w), x, y)
    covered = np.count_nonzero(on_canvas & ~visible[rows, cols], axis=1)
    return covered > HIDDEN_SHARE * np.maximum(np.count_nonzero(on_canvas, axis=1), 1)


def stretched(length: np.ndarray, birth_length: np.ndarray) -> np.ndarray:
    """(N,) bool: a control polygon of ``length`` (N,) px grew or shrank by more than STRETCH since its
    ``birth_length`` (N,) px (a stroke of one control point never does)."""
    grown = length > STRETCH * birth_length
    shrunk = length * STRETCH < birth_length
    return (birth_length > 0) & (grown | shrunk)


def folded(before: np.ndarray, after: np.ndarray, valid: np.ndarray, threshold: float) -> np.ndarray:
    """(N,) bool: a control polygon bends differently: the turn at one of its control points (the angle between
    the segments on either side) changed by more than ``threshold`` radians from ``before`` (N, P, 2) to ``after``
    (N, P, 2) px; ``valid`` (N, P) marks each polygon's points. A motion that moves, turns or scales the surface
    as a whole changes no turn (a rolling ball's strokes roll with it); a surface that folds or shears under the
    stroke does. Turns next to a segment shorter than SHORTEST_SEGMENT on either frame are not judged."""
    if before.shape[1] < 3:
        return np.zeros(len(before), bool)
    turn_before, judged_before = turns(before, valid)
    turn_after, judged_after = turns(after, valid)
    change = np.abs(np.angle(np.exp(1j * (turn_after - turn_before))))
    return np.any(judged_before & judged_after & (change > threshold), axis=1)


def turns(points: np.ndarray, valid: np.ndarray) -> tuple:
    """The turn at each interior control point of N polygons ``points`` (N, P, 2) px, ``valid`` (N, P): (turn
    (N, P - 2) radians in (-pi, pi], judged (N, P - 2) bool: both segments valid and at least SHORTEST_SEGMENT
    long)."""
    steps = np.diff(points, axis=1)
    with np.errstate(invalid="ignore"):
        direction = np.arctan2(steps[..., 1], steps[..., 0])
        long_enough = np.hypot(steps[..., 0], steps[..., 1]) >= SHORTEST_SEGMENT
    turn = np.angle(np.exp(1j * np.nan_to_num(direction[:, 1:] - direction[:, :-1])))
    judged = valid[:, 2:] & long_enough[:, 1:] & long_enough[:, :-1]
    return turn, judged


def resized(anchor: np.ndarray, size: np.ndarray, brush: np.ndarray, size_map: np.ndarray,
            sizes: Sequence[int]) -> np.ndarray:
    """(N,) bool: every pixel within half a stroke's width of its anchor (N, 2) px asks for a stroke size
    SIZE_STEPS or more standard ``sizes`` (px, descending) away from its ``size`` (N,) px, by ``size_map`` (H, W)
    px; only strokes of the painting's brush (``brush`` (N,)). Looking around the anchor, not at its pixel alone,
    keeps a partition's jitter (a grid boundary moved by a pixel's motion) from killing strokes.

    The window of a stroke s px wide is the (2 floor(s / 2) + 1)-pixel square around its anchor's pixel, cut at
    the frame's edges. With r a size's rank in ``sizes`` (0 the largest), every pixel there asks for a size SIZE_STEPS
    finer when none ranks below r + SIZE_STEPS, and SIZE_STEPS coarser when all rank below r - SIZE_STEPS + 1: counted
    at the anchors alone from a summed-area table of the pixels ranking below each threshold, one at a time
    (none where no pixel or every pixel does)."""
    rank = np.zeros(max(int(np.max(size_map)), int(np.max(size, initial=0)), max(sizes)) + 1, np.int16)
    rank[np.asarray(sizes, np.int64)] = np.arange(len(sizes))
    wanted = rank[size_map]
    h, w = wanted.shape
    rows, cols = nearest_pixels((h, w), anchor[:, 0], anchor[:, 1])
    out = np.zeros(len(anchor), bool)
    painting = np.asarray(brush) == PAINTING_BRUSH
    owns = np.unique(size[painting]).tolist()
    windows = {}                                   # own size: (picked strokes, first row, stop, first column, stop)
    for own in owns:
        pick = np.flatnonzero((size == own) & painting)
        half = int(own) // 2
        windows[own] = (pick, np.maximum(rows[pick] - half, 0), np.minimum(rows[pick] + half + 1, h),
                        np.maximum(cols[pick] - half, 0), np.minimum(cols[pick] + half + 1, w))
    finer = {own: int(rank[own]) + SIZE_STEPS for own in owns}          # no pixel ranks below this
    coarser = {own: int(rank[own]) - SIZE_STEPS + 1 for own in owns}     # every pixel ranks below this
    lowest, highest = int(wanted.min()), int(wanted.max())
    for threshold in sorted(set(finer.values()) | set(coarser.values())):
        table = summed_area(wanted < threshold) if lowest < threshold <= highest else None
        for own in owns:
            pick, r0, r1, c0, c1 = windows[own]
            area = (r1 - r0) * (c1 - c0)
            if table is None:                      # no pixel ranks below the threshold, or every one does
                below = area if threshold > highest else np.zeros_like(area)
            else:
                below = table[r1, c1] - table[r0, c1] - table[r1, c0] + table[r0, c0]
            if finer[own] == threshold:
                out[pick] |= below == 0
            if coarser[own] == threshold:
                out[pick] |= below == area
    return out


def crowded(strokes, before: np.ndarray, leaving: np.ndarray) -> np.ndarray:
    """(N,) bool: a stroke came to lie less than half its width from an earlier stroke of its layer and size in
    the list's order that is staying: their anchors are that close now and were not at ``before`` (N, 2) px, the
    anchors on the frame before (strokes born close together, as a still's grids may place them, stay). Strokes
    ``leaving`` (N,) bool neither crowd nor are crowded again.

    Judged in order: a stroke that dies of crowding no longer crowds the strokes after it.
    """
    out = np.zeros(len(strokes), bool)
    staying = np.flatnonzero(~leaving)
    key = np.stack([strokes.layer[staying], strokes.size[staying]], axis=1)
    for group in np.unique(key, axis=0):
        members = staying[np.all(key == group, axis=1)]
        reach = 0.5 * float(group[1])
        pairs = cKDTree(strokes.anchor[members]).query_pairs(reach, output_type="ndarray")
        if len(pairs):
            was = distances(before, members[pairs[:, 0]], members[pairs[:, 1]])
            now = distances(strokes.anchor, members[pairs[:, 0]], members[pairs[:, 1]])
            pairs = pairs[(now < reach) & (was >= reach) & (now < was - CLOSER)]
        if len(pairs) == 0:
            continue
        pairs = np.sort(pairs, axis=1)
        pairs = pairs[np.lexsort((pairs[:, 0], pairs[:, 1]))]
        gone = np.zeros(len(members), bool)
        for earlier, later in pairs.tolist():
            if not gone[earlier]:
                gone[later] = True
        out[members[gone]] = True
    return out


def distances(points: np.ndarray, first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """(K,) px: the distances between ``points`` (N, 2) first[k] and second[k] (K,)."""
    apart = points[first] - points[second]
    return np.hypot(apart[:, 0], apart[:, 1])


def recoloured(living: LivingStrokes, anchors: Dict[int, SmoothedImage], dabs: SmoothedImage) -> LivingStrokes:
    """The strokes with their anchor colour sampled again from the new frame at their anchors and their bristles
    the new anchor colour plus their offsets (clipped to [0, 1]); a stroke whose anchor colour is unchanged keeps
    its bristles to the bit.

    anchors: {size px: the new frame's reference smoothed for the anchor colour} (``ColourSources.anchor``);
    dabs: the same for round-brush strokes (the detail pass's source).
    """
    strokes = living.strokes
    colour = np.empty_like(strokes.anchor_colour)
    for size in np.unique(strokes.size).tolist():
        for brush in np.unique(strokes.brush).tolist():
            pick = (strokes.size == size) & (strokes.brush == brush)
            if pick.any():
                source = anchors[size] if brush == PAINTING_BRUSH else dabs
                colour[pick] = source.sample(strokes.anchor[pick, 0], strokes.anchor[pick, 1])
    changed = np.any(colour != strokes.anchor_colour, axis=1)
    counts = np.diff(strokes.bristle_starts)
    mixed = np.clip(np.repeat(colour, counts, axis=0) + living.offsets, 0.0, 1.0).astype(np.float32)
    bristles = np.where(np.repeat(changed, counts)[:, None], mixed, strokes.bristles)
    return replace(living, strokes=replace(strokes, anchor_colour=colour, bristles=bristles))
