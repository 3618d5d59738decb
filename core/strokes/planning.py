"""Where a stroke goes: its control points, curve and stopping rules (ALGORITHM §5, "The path").

Two readings of the stopping rules, chosen by ``Params.path_rule``:

- 'natural' (the default, the settled reading): control points one brush
  radius apart along the orientation field, both ways from the anchor, up to
  ``max_length`` in all. Walking outward on each side, the stroke stops
  before the first curve sample where the reference smoothed at the brush's
  scale differs from the anchor colour by more than ``edge_threshold`` (an
  edge of the stroke's own scale), checked from the first step; the colour
  test (the canvas already closer to the reference than the brush colour)
  and the orientation test (the field turned more than T_o from the anchor)
  are checked only at control points and only once the stroke has
  ``min_length`` control points, so one lucky pixel does not cut it to a dab.
- 'literal' (the paper read literally, kept for ablation): the colour and
  orientation tests at every curve sample from the anchor, no minimum length
  and no edge test.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..params import Params
from .path import axial_difference, catmull_rom, clip_path, first_failure, trace_control_points
from .smoothing import SmoothedImage


@dataclass
class PlannedPath:
    """The kept part of a stroke's curve.

    samples: float64 (M, 2) (x, y) px, about one px apart, backward end -> forward end.
    anchor_index: index of the anchor among them.
    control_index: int (K,) indices of the kept control points among them, ends included.
    """

    samples: np.ndarray
    anchor_index: int
    control_index: np.ndarray

    def polyline(self) -> np.ndarray:
        """(K, 2) float32: the kept control points with the ends (what ``strokes.json`` records)."""
        return self.samples[self.control_index].astype(np.float32)


def nearest_pixels(shape: tuple, x: np.ndarray, y: np.ndarray) -> tuple:
    """(rows, columns) int arrays of the pixels nearest float positions x, y, clamped to an (H, W) canvas."""
    h, w = shape[:2]
    ix = np.minimum(np.maximum(np.floor(x + 0.5), 0), w - 1).astype(np.intp)
    iy = np.minimum(np.maximum(np.floor(y + 0.5), 0), h - 1).astype(np.intp)
    return iy, ix


def continue_mask(points: np.ndarray, reference_at_points: np.ndarray, canvas_colour: np.ndarray,
                  orientation: np.ndarray, brush_colour: np.ndarray, anchor_angle: float,
                  max_turn: float) -> np.ndarray:
    """(N,) bool: where a stroke may go on past (N, 2) ``points`` (the colour and orientation tests).

    A point fails where (a) the canvas already matches the reference better
    than the brush colour would, |ref - canvas| < |ref - brush|, or (b) the
    orientation field turns more than ``max_turn`` from the anchor's angle.
    reference_at_points: (N, 3) the reference there; the canvas and the
    field are read at the nearest pixel.
    """
    at = nearest_pixels(canvas_colour.shape, points[:, 0], points[:, 1])
    can = canvas_colour[at]
    closer = (np.sum((reference_at_points - can) ** 2, axis=1)
              < np.sum((reference_at_points - brush_colour) ** 2, axis=1))
    turned = axial_difference(orientation[at], anchor_angle) > max_turn
    return ~(closer | turned)


def kept_controls(first: int, last: int, control_index: np.ndarray) -> np.ndarray:
    """Indices, relative to ``first``, of the control points in samples [first, last] plus both ends."""
    inner = control_index[(control_index > first) & (control_index < last)]
    return np.unique(np.concatenate(([first], inner, [last]))) - first


def plan_path(anchor: tuple, size: int, orientation: np.ndarray, canvas_colour: np.ndarray,
              brush_colour: np.ndarray, reference: np.ndarray, smoothed: SmoothedImage,
              params: Params) -> PlannedPath:
    """Plan a stroke ``size`` px wide from ``anchor`` (x, y) by ``params.path_rule``.

    reference: (H, W, 3) the bilateral reference (the literal rule reads it);
    smoothed: the reference at the brush's scale (the natural rule's edge and
    colour tests, the edge test against its colour at the anchor);
    brush_colour: (3,) the mean colour the brush lays.
    """
    step = max(1.0, 0.5 * size)
    beyond = max(0, params.max_length - 1)
    angle = float(orientation[anchor[1], anchor[0]])
    if params.path_rule == "literal":
        forward = (beyond + 1) // 2
        control, anchor_at = trace_control_points(anchor, orientation, step, forward, beyond - forward)
        samples, control_index = catmull_rom(control)
        at = nearest_pixels(reference.shape, samples[:, 0], samples[:, 1])
        keep = continue_mask(samples, reference[at], canvas_colour, orientation, brush_colour, angle,
                             params.orientation_threshold)
        start = control_index[anchor_at]
        kept, kept_anchor = clip_path(samples, start, keep)
        first = start - kept_anchor
        return PlannedPath(kept, kept_anchor, kept_controls(first, first + len(kept) - 1, control_index))

    control, anchor_at = trace_control_points(anchor, orientation, step, beyond, beyond, margin=0.5 * size)
    samples, control_index = catmull_rom(control)
    start = int(control_index[anchor_at])
    at_samples = smoothed.sample(samples[:, 0], samples[:, 1])
    edge_ok = np.sum((at_samples - at_samples[start]) ** 2, axis=1) <= params.edge_threshold ** 2
    check_ok = continue_mask(samples[control_index], at_samples[control_index], canvas_colour, orientation,
                             brush_colour, angle, params.orientation_threshold)

    # per side, walking outward: sample offsets of its control points, edge reach, test results
    sides = []
    for direction in (1, -1):
        if direction > 0:
            offsets = control_index[anchor_at + 1:] - start
            ok = edge_ok[start + 1:]
            tests = check_ok[anchor_at + 1:]
        else:
            offsets = start - control_index[:anchor_at][::-1]
            ok = edge_ok[:start][::-1]
            tests = check_ok[:anchor_at][::-1]
        reach = first_failure(ok)                       # samples kept before the edge
        reached = int(np.count_nonzero(offsets <= reach))
        sides.append([offsets, tests, reach, reached])
    need_forward = math.ceil(max(0, params.min_length - 1) / 2)
    need_backward = max(0, params.min_length - 1) - need_forward
    minimum = [need_forward + max(0, need_backward - sides[1][3]),
               need_backward + max(0, need_forward - sides[0][3])]
    points, lengths = [], []
    for (offsets, tests, reach, reached), least in zip(sides, minimum, strict=True):
        failed = np.flatnonzero(~tests[least:reached])
        if failed.size:
            count = least + int(failed[0]) + 1          # keep the control point that failed, drop the rest
            points.append(count)
            lengths.append(int(offsets[count - 1]))
        else:
            points.append(reached)
            lengths.append(reach)
    # at most max_length control points in all: a side that ends early leaves the rest to the other
    if points[0] + points[1] > beyond:
        half_forward = (beyond + 1) // 2
        if points[0] <= half_forward:
            cap = [points[0], beyond - points[0]]
        elif points[1] <= beyond - half_forward:
            cap = [beyond - points[1], points[1]]
        else:
            cap = [half_forward, beyond - half_forward]
        for i in range(2):
            if cap[i] < points[i]:
                lengths[i] = int(sides[i][0][cap[i] - 1]) if cap[i] > 0 else 0
    first, last = start - lengths[1], start + lengths[0]
    kept = samples[first:last + 1]
    return PlannedPath(kept, start - first, kept_controls(first, last, control_index))
