"""Where a round's strokes go: control points, curves and stopping rules (ALGORITHM §5, "The path").

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

Every stroke of a round is planned at once, as (strokes x samples) arrays
with masks, against the canvas as it stood when the round began.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..params import Params
from .path import axial_difference, catmull_rom, nearest_pixels, trace_control_points
from .smoothing import SmoothedImage


@dataclass
class PlannedPaths:
    """The kept part of each of N strokes' curves.

    samples: float64 (N, S, 2) (x, y) px, ``sample_spacing(size)`` apart, backward end -> forward end.
    first, last: int (N,) the kept samples of stroke i are first[i] .. last[i].
    per_segment: control points are the samples at multiples of it.
    """

    samples: np.ndarray
    first: np.ndarray
    last: np.ndarray
    per_segment: int

    def polyline(self, i: int) -> np.ndarray:
        """(K, 2) float32: stroke i's kept control points with its ends (what ``strokes.json`` records)."""
        first, last, k = int(self.first[i]), int(self.last[i]), self.per_segment
        inner = np.arange((first // k + 1) * k, last, k)
        index = np.concatenate(([first], inner, [last])) if last > first else np.array([first])
        return self.samples[i, index].astype(np.float32)


def sample_spacing(size: int) -> float:
    """Curve samples of a stroke ``size`` px wide lie about this far apart (px): 1 px up to 16 px brushes, then
    size / 16, so a stop lands within a sixteenth of the width of where the smoothed reference changes (its
    blur, 0.25 x the width, varies no faster)."""
    return max(1.0, size / 16.0)


def samples_per_segment(size: int) -> int:
    """Curve samples per control segment (one brush radius) of a stroke ``size`` px wide."""
    return max(1, math.ceil(max(1.0, 0.5 * size) / sample_spacing(size) - 1e-9))


def continue_mask(points: np.ndarray, reference_at_points: np.ndarray, canvas_colour: np.ndarray,
                  orientation: np.ndarray, brush_colours: np.ndarray, anchor_angles: np.ndarray,
                  max_turn: float) -> np.ndarray:
    """(N, P) bool: where N strokes may go on past their (N, P, 2) ``points`` (the colour and orientation tests).

    A point fails where (a) the canvas already matches the reference better
    than the brush colour would, |ref - canvas| < |ref - brush|, or (b) the
    orientation field turns more than ``max_turn`` from the anchor's angle.
    reference_at_points: (N, P, 3) the reference there; brush_colours (N, 3);
    anchor_angles (N,). The canvas and the field are read at the nearest pixel.
    """
    at = nearest_pixels(canvas_colour.shape, points[..., 0], points[..., 1])
    can = canvas_colour[at]
    closer = (np.sum((reference_at_points - can) ** 2, axis=-1)
              < np.sum((reference_at_points - brush_colours[:, None, :]) ** 2, axis=-1))
    turned = axial_difference(orientation[at], anchor_angles[:, None]) > max_turn
    return ~(closer | turned)


def first_failures(ok: np.ndarray) -> np.ndarray:
    """(N,) index of the first False in each row of (N, L) bool ``ok`` (L where none)."""
    if ok.shape[1] == 0:
        return np.zeros(len(ok), np.int64)
    bad = ~ok
    return np.where(bad.any(axis=1), np.argmax(bad, axis=1), ok.shape[1])


def plan_paths(anchors: np.ndarray, size: int, orientation: np.ndarray, canvas_colour: np.ndarray,
               brush_colours: np.ndarray, reference: np.ndarray, smoothed: SmoothedImage,
               params: Params) -> PlannedPaths:
    """Plan N strokes ``size`` px wide from (N, 2) int ``anchors`` (x, y) by ``params.path_rule``.

    canvas_colour: (H, W, 3) the canvas the round plans against;
    brush_colours: (N, 3) the mean colour each brush lays; reference: (H, W,
    3) the bilateral reference (the literal rule reads it); smoothed: the
    reference at the brush's scale (the natural rule's edge and colour
    tests, the edge test against its colour at the anchor).
    """
    anchors = np.asarray(anchors, np.int64).reshape(-1, 2)
    n = len(anchors)
    step = max(1.0, 0.5 * size)
    per_segment = samples_per_segment(size)
    beyond = max(0, params.max_length - 1)
    angles = orientation[anchors[:, 1], anchors[:, 0]].astype(np.float64)
    if params.path_rule == "literal":
        forward = (beyond + 1) // 2
        control, counts = trace_control_points(anchors, orientation, step, forward, beyond - forward)
        samples = catmull_rom(control, per_segment)
        start = (beyond - forward) * per_segment
        at = nearest_pixels(reference.shape, samples[..., 0], samples[..., 1])
        keep = continue_mask(samples, reference[at], canvas_colour, orientation, brush_colours, angles,
                             params.orientation_threshold)
        index = np.arange(samples.shape[1])[None, :]
        keep &= (index >= start - counts[:, 1:2] * per_segment) & (index <= start + counts[:, 0:1] * per_segment)
        last = start + first_failures(keep[:, start + 1:])
        first = start - first_failures(keep[:, :start][:, ::-1])
        return PlannedPaths(samples, first, last, per_segment)

    control, counts = trace_control_points(anchors, orientation, step, beyond, beyond, margin=0.5 * size)
    samples = catmull_rom(control, per_segment)
    start = beyond * per_segment
    if beyond == 0:
        return PlannedPaths(samples, np.full(n, start), np.full(n, start), per_segment)
    at_samples = smoothed.sample(samples[..., 0], samples[..., 1])                     # (N, S, 3)
    gap = at_samples - at_samples[:, start:start + 1]
    edge_ok = np.einsum("nsc,nsc->ns", gap, gap) <= np.float32(params.edge_threshold ** 2)
    controls = np.arange(2 * beyond + 1) * per_segment
    check_ok = continue_mask(samples[:, controls], at_samples[:, controls], canvas_colour, orientation,
                             brush_colours, angles, params.orientation_threshold)
    index = np.arange(beyond * per_segment)[None, :]
    reach, reached, tests = [], [], []
    for side, (ok, test) in enumerate(((edge_ok[:, start + 1:], check_ok[:, beyond + 1:]),
                                       (edge_ok[:, :start][:, ::-1], check_ok[:, :beyond][:, ::-1]))):
        ok = ok & (index < counts[:, side:side + 1] * per_segment)        # samples past the traced part fail
        reach.append(first_failures(ok))                                  # samples kept before the edge
        reached.append(reach[-1] // per_segment)                          # control points within that reach
        tests.append(test)
    need_forward = math.ceil(max(0, params.min_length - 1) / 2)
    need_backward = max(0, params.min_length - 1) - need_forward
    least = [need_forward + np.maximum(0, need_backward - reached[1]),
             need_backward + np.maximum(0, need_forward - reached[0])]
    point = np.arange(beyond)[None, :]
    points, lengths = [], []
    for side in range(2):
        failing = ~tests[side] & (point >= least[side][:, None]) & (point < reached[side][:, None])
        failed = failing.any(axis=1)
        count = np.argmax(failing, axis=1) + 1                            # keep the control point that failed
        points.append(np.where(failed, count, reached[side]))
        lengths.append(np.where(failed, count * per_segment, reach[side]))
    # at most max_length control points in all: a side that ends early leaves the rest to the other
    half_forward = (beyond + 1) // 2
    over = points[0] + points[1] > beyond
    cap_forward = np.where(points[0] <= half_forward, points[0],
                           np.where(points[1] <= beyond - half_forward, beyond - points[1], half_forward))
    caps = [cap_forward, beyond - cap_forward]
    for side in range(2):
        cut = over & (caps[side] < points[side])
        lengths[side] = np.where(cut, caps[side] * per_segment, lengths[side])
    return PlannedPaths(samples, start - lengths[1], start + lengths[0], per_segment)
