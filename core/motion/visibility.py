"""Which pixels of frame t are visible in frame t+1: the forward-backward check of ALGORITHM §9.

After Sundaram, Brox and Keutzer 2010 ("Dense point trajectories by
GPU-accelerated large displacement optical flow"). A pixel x of frame t is
*visible in both* frames when

- x + w_f(x) lies in frame t+1 (``warp.inside_frame``),
- the backward motion there undoes the forward one:
  |w_f(x) + w_b(x + w_f(x))|² <= 0.01 (|w_f(x)|² + |w_b(x + w_f(x))|²) + 0.5,
- x is not on a motion boundary: |∇u|² + |∇v|² <= 0.01 |w_f(x)|² + 0.002,
  with (u, v) = w_f and its gradients by central differences (``np.gradient``).

Motions are float32 (H, W, 2) in pixels, x right, y down (``vector_pass``).
A motion no pixel that stays in the frame can have (longer than the frame's
width plus its height, infinite or NaN) is taken within reach first
(``warp.within_reach``): its pixel leaves the frame, is not visible, and
no figure overflows.
"""

from __future__ import annotations

import numpy as np

from .warp import warp_back, within_reach

CONSISTENCY_SHARE = 0.01  # of |w_f|² + |w_b|²: how far the round trip may miss, relative to the motion
CONSISTENCY_SLACK = 0.5  # px²: how far it may miss when nothing moves
BOUNDARY_SHARE = 0.01  # of |w_f|²: how steep the motion may change, relative to the motion
BOUNDARY_SLACK = 0.002  # (px / px)²: how steep it may change when nothing moves


def _squared_length(motion: np.ndarray) -> np.ndarray:
    """(H, W, 2) -> (H, W) float32: |w|² in px²."""
    return np.sum(np.square(motion, dtype=np.float32), axis=-1)


def round_trip_consistent(forward: np.ndarray, backward_there: np.ndarray) -> np.ndarray:
    """Where the backward motion at x + w_f(x) brings a pixel of frame t back to where it started.

    forward: (H, W, 2) w_f(x) of frame t; backward_there: (H, W, 2)
    w_b(x + w_f(x)), frame t+1's backward motion sampled at where frame t's
    pixels go (``warp.warp_back(backward, forward)``), both in px.
    Returns bool (H, W).
    """
    forward, backward_there = within_reach(forward), within_reach(backward_there)
    missed = _squared_length(forward + backward_there)
    allowed = CONSISTENCY_SHARE * (_squared_length(forward) + _squared_length(backward_there)) + CONSISTENCY_SLACK
    return missed <= allowed


def motion_boundary(forward: np.ndarray) -> np.ndarray:
    """Where the forward motion changes too steeply for a pixel to move with its neighbours.

    forward: (H, W, 2) w_f = (u, v) in px, H and W at least 2. Returns bool
    (H, W): |∇u|² + |∇v|² > 0.01 |w_f|² + 0.002, gradients in px per px by
    central differences (one-sided at the edges).
    """
    motion = within_reach(forward)
    steepness = np.zeros(motion.shape[:2], dtype=np.float32)
    for component in (motion[..., 0], motion[..., 1]):
        for slope in np.gradient(component):
            steepness += np.square(slope)
    return steepness > BOUNDARY_SHARE * _squared_length(motion) + BOUNDARY_SLACK


def visible_in_both(forward: np.ndarray, backward: np.ndarray) -> np.ndarray:
    """Pixels of frame t that are seen, unoccluded, in frame t+1 too.

    forward: float32 (H, W, 2) w_f, frame t -> t+1; backward: float32
    (H, W, 2) w_b, frame t+1 -> t (``vector_pass.motion_pair``), in px.
    Returns bool (H, W): in frame t+1, round trip consistent and off motion
    boundaries (module docstring).
    """
    return comes_back(forward, backward) & ~motion_boundary(forward)


def comes_back(forward: np.ndarray, backward: np.ndarray) -> np.ndarray:
    """Pixels of frame t that land inside frame t+1 and that the backward motion brings back where they started.

    forward: float32 (H, W, 2) w_f, frame t -> t+1; backward: float32 (H, W, 2) w_b, frame t+1 -> t, in px.
    Returns bool (H, W): ``visible_in_both`` without the motion-boundary test.
    """
    motion = within_reach(forward)
    backward_there, inside = warp_back(within_reach(backward), motion)
    return inside & round_trip_consistent(motion, backward_there)
