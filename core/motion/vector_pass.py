"""Blender's Vector pass -> forward and backward motion in image axes (ALGORITHM §9, "Motion").

Blender writes, per pixel of frame t, the motion to the previous frame in
channels X, Y and the motion to the next frame in Z, W, in pixels and in its
raster axes (y up). Read with OpenImageIO (row 0 at the top) and turned into
image axes (x right, y down), frame t's pass gives

    forward  t -> t+1 = (-Z, +W)
    backward t -> t-1 = (X, -Y)

(checked on a render of a known motion by tests/test_vector_pass_blender.py).
A motion field is float32 (H, W, 2) in pixels: [..., 0] = x (right),
[..., 1] = y (down); pixel x of frame t is at x + w(x) in the other frame.

A pass may hold values no motion can have (1e30 px, from a broken render
or another program): a motion longer than the frame's width plus its height
takes every pixel out of the frame, so ``motion_pair`` clips each component
to that length (``warp.within_reach``): the pixel leaves the frame as
before, while every measure of the motion stays finite and quiet.
"""

from __future__ import annotations

from typing import Tuple

import numpy as np

from .warp import within_reach


def _channels(vector_pass: np.ndarray) -> np.ndarray:
    """The pass as float32 (H, W, 4) X, Y, Z, W, or ValueError naming the shape it has."""
    data = np.asarray(vector_pass, dtype=np.float32)
    if data.ndim != 3 or data.shape[2] != 4:
        raise ValueError(f"a Vector pass is (H, W, 4) X, Y, Z, W; got shape {data.shape}")
    return data


def forward_motion(vector_pass: np.ndarray) -> np.ndarray:
    """Frame t's motion to frame t+1 from frame t's Vector pass.

    vector_pass: (H, W, 4) X, Y, Z, W in pixels, as OpenImageIO reads the
    Vector part of a Blender multilayer EXR (row 0 at the top).
    Returns float32 (H, W, 2) (x right, y down) in pixels: (-Z, +W), as stored.
    """
    data = _channels(vector_pass)
    return np.stack([-data[..., 2], data[..., 3]], axis=-1)


def backward_motion(vector_pass: np.ndarray) -> np.ndarray:
    """Frame t's motion to frame t-1 from frame t's Vector pass.

    vector_pass: (H, W, 4) X, Y, Z, W in pixels, as for ``forward_motion``.
    Returns float32 (H, W, 2) (x right, y down) in pixels: (X, -Y), as stored.
    """
    data = _channels(vector_pass)
    return np.stack([data[..., 0], -data[..., 1]], axis=-1)


def motion_pair(pass_t: np.ndarray, pass_next: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """The two motions between frames t and t+1 that §9 uses: (w_f, w_b).

    pass_t, pass_next: the (H, W, 4) Vector passes of frames t and t+1.
    w_f: float32 (H, W, 2), frame t's pixels to frame t+1 (from frame t's pass);
    w_b: float32 (H, W, 2), frame t+1's pixels to frame t (from frame t+1's pass).
    Both within reach (``warp.within_reach``): a value no motion can have leaves the frame.
    """
    forward, backward = forward_motion(pass_t), backward_motion(pass_next)
    if forward.shape != backward.shape:
        raise ValueError(f"the Vector passes of frames t and t+1 differ in size: {forward.shape[:2]} "
                         f"and {backward.shape[:2]}")
    return within_reach(forward), within_reach(backward)
