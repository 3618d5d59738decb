"""Every stroke visit's own random numbers (ALGORITHM §5, "Speed").

A visit (one grid of one layer, or one dab of the detail pass) draws its
random numbers (the anchor among tied pixels, the colour perturbation of
Eq. 5) from a stream keyed by the seed, the layer and the visit's index, so
the painting does not depend on how the visits are grouped into rounds or
chunks. The stream is counter based (SplitMix64 finalisers over 64-bit
integers), so a whole round's numbers come out of a few array operations.
"""

from __future__ import annotations

import numpy as np

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MIX_1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX_2 = np.uint64(0x94D049BB133111EB)
_MASK = (1 << 64) - 1


def _mix(z: np.ndarray) -> np.ndarray:
    """SplitMix64's finaliser on a uint64 array (wrapping arithmetic)."""
    z = (z ^ (z >> np.uint64(30))) * _MIX_1
    z = (z ^ (z >> np.uint64(27))) * _MIX_2
    return z ^ (z >> np.uint64(31))


def visit_uniforms(seed: int, layer: int, visits: np.ndarray, count: int) -> np.ndarray:
    """(N, count) float64 uniform numbers in [0, 1): ``count`` draws of each of N visits.

    seed: any integer (taken modulo 2^64); layer: >= 0; visits: (N,) int >= 0,
    the visits' indices in their layer. Draw j of a visit depends only on
    (seed, layer, visit, j).
    """
    with np.errstate(over="ignore"):
        key = _mix(np.array([int(seed) & _MASK], np.uint64) + _GOLDEN)
        key = _mix(key ^ np.array([int(layer) & _MASK], np.uint64))
        base = _mix(key ^ (np.asarray(visits, np.uint64).reshape(-1, 1) * _GOLDEN))
        draws = _mix(base + np.arange(1, count + 1, dtype=np.uint64)[None, :] * _GOLDEN)
    return (draws >> np.uint64(11)).astype(np.float64) * (1.0 / (1 << 53))


def frame_seed(seed: int, frame: int) -> int:
    """The seed of the strokes born on a sequence's ``frame`` (0-based index >= 0; ALGORITHM §9): ``seed`` itself on
    frame 0, which is painted as a still, else a number in [0, 2^63) mixed from (seed, frame). A stroke's stream is
    then keyed by (seed, birth frame, layer, birth index), whatever frames were painted before it in this process."""
    if frame == 0:
        return int(seed)
    with np.errstate(over="ignore"):
        key = _mix(np.array([int(seed) & _MASK], np.uint64) + _GOLDEN)
        key = _mix(key ^ (np.array([int(frame) & _MASK], np.uint64) * _MIX_1))
    return int(key[0] >> np.uint64(1))
