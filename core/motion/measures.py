"""How steady a sequence is: the measures of ALGORITHM §9 ("Measures"), for footage and paintings alike.

- Warping error (Lai et al. 2018): E(t) is the mean, over the pixels of
  frame t visible in both frames and over channels, of
  (V_t(x) - V_{t+1}(x + w_f(x)))²; E is the mean of E(t) over t.
- Stillness: where the footage does not move (|w_f| and |w_b| both under
  0.25 px), the mean absolute change of the values from frame t to t+1.
  The painting's figure against the footage's is the caller's ratio.

Values are float32 (H, W) or (H, W, C) in [0, 1] (colours in sRGB; heights
normalised to [0, 1] over the sequence by ``normalise``); motions float32
(H, W, 2) in px, x right, y down. Each measure takes one pair of frames, so
a sequence can be measured while it is read; ``mean_over_pairs`` averages.
A pair with no pixel to measure gives NaN.
"""

from __future__ import annotations

from typing import Iterable, Tuple

import numpy as np

from .warp import warp_back, within_reach

STILL_MOTION = 0.25  # px: a pixel moving less than this both ways does not move


def _masked_mean(values: np.ndarray, mask: np.ndarray) -> float:
    """Mean of (H, W) or (H, W, C) ``values`` over the pixels where ``mask`` (H, W) holds and over channels;
    NaN when it holds nowhere."""
    chosen = values[mask]
    return float(chosen.mean(dtype=np.float64)) if chosen.size else float("nan")


def warping_error(frame: np.ndarray, next_frame: np.ndarray, forward: np.ndarray, visible: np.ndarray) -> float:
    """E(t): the mean squared difference between frame t and frame t+1 warped back onto it.

    frame, next_frame: (H, W) or (H, W, C) values of frames t and t+1, in [0, 1].
    forward: (H, W, 2) w_f, px. visible: bool (H, W), the pixels visible in
    both frames (``visibility.visible_in_both``; it holds only where
    x + w_f(x) is in frame t+1). Returns E(t) in [0, 1], NaN when no pixel is visible.
    """
    warped, _ = warp_back(next_frame, forward)
    return _masked_mean(np.square(np.asarray(frame, dtype=np.float32) - warped), np.asarray(visible, dtype=bool))


def still_pixels(forward: np.ndarray, backward: np.ndarray) -> np.ndarray:
    """Where the footage does not move between frames t and t+1.

    forward: (H, W, 2) w_f of frame t; backward: (H, W, 2) w_b of frame t+1
    (a pixel that does not move is the same pixel in both frames), px.
    Returns bool (H, W): |w_f| < 0.25 px and |w_b| < 0.25 px (a motion out of reach, ``warp.within_reach``,
    moves).
    """
    limit = np.float32(STILL_MOTION ** 2)
    moves_forward = np.sum(np.square(within_reach(forward)), axis=-1)
    moves_backward = np.sum(np.square(within_reach(backward)), axis=-1)
    return (moves_forward < limit) & (moves_backward < limit)


def stillness(frame: np.ndarray, next_frame: np.ndarray, still: np.ndarray) -> float:
    """The mean absolute change from frame t to frame t+1 where the footage does not move.

    frame, next_frame: (H, W) or (H, W, C) values in [0, 1]; still: bool
    (H, W) from ``still_pixels``. Returns a value in [0, 1] (mean over the
    still pixels and channels), NaN when no pixel is still.
    """
    change = np.abs(np.asarray(next_frame, dtype=np.float32) - np.asarray(frame, dtype=np.float32))
    return _masked_mean(change, np.asarray(still, dtype=bool))


def mean_over_pairs(values: Iterable[float]) -> float:
    """The sequence's figure from its pairs' (E from the E(t)): the mean of the finite values, NaN if none."""
    finite = [v for v in values if np.isfinite(v)]
    return float(np.mean(finite)) if finite else float("nan")


def value_range(frames: Iterable[np.ndarray]) -> Tuple[float, float]:
    """The lowest and highest finite value over every frame of a sequence (e.g. the painting's heights).

    frames: any number of arrays of any shape (read one at a time if given a
    generator). Returns (low, high); ValueError when there is no finite value.
    """
    low, high = np.inf, -np.inf
    for frame in frames:
        values = np.asarray(frame)
        values = values[np.isfinite(values)]
        if values.size:
            low, high = min(low, float(values.min())), max(high, float(values.max()))
    if low > high:
        raise ValueError("the sequence has no finite value to normalise by")
    return low, high


def normalise(values: np.ndarray, low: float, high: float) -> np.ndarray:
    """One frame's values mapped to [0, 1] by the sequence's range (``value_range``): float32, same shape;
    all zeros when the sequence is flat (low == high)."""
    data = np.asarray(values, dtype=np.float32)
    if high <= low:
        return np.zeros_like(data)
    return np.clip((data - np.float32(low)) / np.float32(high - low), 0.0, 1.0).astype(np.float32, copy=False)
