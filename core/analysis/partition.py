"""Canvas partition by energy-balanced binary cuts (ALGORITHM §2, the paper's Eq. 2).

The canvas starts as one rectangle ("grid"). A grid is cut in two across its
longer side at the integer position that minimises

    cost(i) = ((Ē_small + δ) / (Ē_big + δ)) · (S_big / S_small)^γ          (Eq. 2)

where Ē_small ≤ Ē_big are the mean energies of the two halves and
S_small ≤ S_big their areas (in pixels). Cuts therefore follow energy
boundaries (a low ratio of mean energies) while avoiding slivers (the area
ratio penalty).

Conventions
-----------
* ``energy`` is a float (H, W) array, the normalised importance map Ẽ in
  [0, 1] (dimensionless per pixel). Sums of it are in "energy·pixel" units.
* A rectangle is ``(x0, y0, x1, y1)`` in integer pixels, half-open:
  columns ``x0 <= x < x1``, rows ``y0 <= y < y1``; x is the column, y the row
  (downwards), so the grid is ``energy[y0:y1, x0:x1]``.
* A summed-area table (SAT) is float64 (H + 1, W + 1) with a zero first row
  and column: ``sat[y, x] = energy[:y, :x].sum()``.

Cut geometry
------------
If ``width >= height`` the cut is a vertical line at column ``c = x0 + i``
(halves ``(x0, y0, c, y1)`` and ``(c, y0, x1, y1)``), else a horizontal line
at row ``r = y0 + i`` (halves ``(x0, y0, x1, r)`` and ``(x0, r, x1, y1)``).
A position is admissible when both halves keep a side of at least
``min_side`` along the cut axis: ``min_side <= i <= length - min_side``.
Ties in cost go to the smallest position.

Only numpy is used; nothing here imports bpy.
"""

from __future__ import annotations

import math
from typing import Iterable, Sequence, Tuple

import numpy as np

from ..errors import InputError, ParameterError

__all__ = [
    "summed_area_table",
    "rect_sums",
    "partition",
    "nearest_size",
    "detail_threshold",
    "size_limits",
]

DEFAULT_DELTA = 0.01 / 255.0
"""δ of Eq. 2 for energy on the [0, 1] scale (the paper's 0.01 on 0-255)."""


# ---------------------------------------------------------------------------
# building blocks


def summed_area_table(energy: np.ndarray) -> np.ndarray:
    """Summed-area table of a 2-D energy map.

    energy: float (H, W), any finite values (normally [0, 1]).
    Returns float64 (H + 1, W + 1); row 0 and column 0 are zero and
    ``sat[y, x] = energy[:y, :x].sum()`` (energy·pixel units), so the sum
    over the half-open rectangle (x0, y0, x1, y1) is
    ``sat[y1, x1] - sat[y0, x1] - sat[y1, x0] + sat[y0, x0]``.
    """
    e = np.asarray(energy, dtype=np.float64)
    if e.ndim != 2:
        raise InputError(f"The energy map must be a 2-D array, got {e.ndim} dimensions.")
    h, w = e.shape
    sat = np.zeros((h + 1, w + 1), dtype=np.float64)
    np.cumsum(e, axis=0, out=sat[1:, 1:])
    np.cumsum(sat[1:, 1:], axis=1, out=sat[1:, 1:])
    return sat


def rect_sums(sat: np.ndarray, x0, y0, x1, y1) -> np.ndarray:
    """Energy sums (float64, energy·pixel) over half-open rectangles, from a SAT.

    sat: float64 (H + 1, W + 1) from :func:`summed_area_table`.
    x0, y0, x1, y1: integer scalars or broadcastable integer arrays with
    ``0 <= x0 <= x1 <= W`` and ``0 <= y0 <= y1 <= H``.
    Returns an array of the broadcast shape. The arithmetic order is fixed
    (``((a - b) - c) + d``) so every caller gets bit-identical sums.
    """
    sat = np.asarray(sat)
    stride = sat.shape[1]
    flat = sat.reshape(-1)
    x0 = np.asarray(x0, dtype=np.int64)
    y0 = np.asarray(y0, dtype=np.int64)
    x1 = np.asarray(x1, dtype=np.int64)
    y1 = np.asarray(y1, dtype=np.int64)
    r0 = y0 * stride
    r1 = y1 * stride
    return flat[r1 + x1] - flat[r0 + x1] - flat[r1 + x0] + flat[r0 + x0]


def _eq2(s1: np.ndarray, a1: np.ndarray, s2: np.ndarray, a2: np.ndarray,
         delta: float, gamma: float) -> np.ndarray:
    """Eq. 2, elementwise, from the halves' energy sums s1, s2 and areas a1, a2 (> 0).

    Shared by the generation-vectorised :func:`partition` and the tests'
    per-grid reference (``cut_costs`` in tests/oracles.py), so both produce
    identical floats.
    Returns float64 costs, each >= 0 (>= 1 in the area factor; the energy factor
    is in (0, 1] for non-negative energy).
    """
    a1 = np.asarray(a1, dtype=np.float64)
    a2 = np.asarray(a2, dtype=np.float64)
    m1 = s1 / a1
    m2 = s2 / a2
    energy_ratio = (np.minimum(m1, m2) + delta) / (np.maximum(m1, m2) + delta)
    area_ratio = np.maximum(a1, a2) / np.minimum(a1, a2)
    if gamma == 1.0:
        return energy_ratio * area_ratio
    return energy_ratio * np.power(area_ratio, gamma)


def _check_eq2_params(min_side, delta: float, gamma: float) -> None:
    if int(min_side) < 1:
        raise ParameterError(f"The smallest stroke size must be at least 1 pixel, got {min_side}.")
    if not (delta > 0 and math.isfinite(delta)):
        raise ParameterError(f"The partition delta must be positive, got {delta}.")
    if not (gamma >= 0 and math.isfinite(gamma)):
        raise ParameterError(f"The partition gamma must not be negative, got {gamma}.")


# ---------------------------------------------------------------------------
# the whole canvas


def size_limits(sizes: Iterable[float]) -> Tuple[int, int, int]:
    """(min_side px, min_area px², max_area px²) from the standard stroke sizes (px, any order).

    min_side = ceil(min(sizes)), min_area = min(sizes)², max_area = max(sizes)²
    (areas rounded up to whole pixels).
    """
    s = [float(v) for v in sizes]
    if not s:
        raise ParameterError("Stroke sizes must list at least one size.")
    if not all(math.isfinite(v) and v > 0 for v in s):
        raise ParameterError(f"Stroke sizes must all be positive, got {s}.")
    lo, hi = min(s), max(s)
    return int(math.ceil(lo)), int(math.ceil(lo * lo)), int(math.ceil(hi * hi))


def partition(energy: np.ndarray, sizes: Sequence[float], detail_threshold: float,
              delta: float = DEFAULT_DELTA, gamma: float = 1.0) -> np.ndarray:
    """Split the canvas into grids by recursive Eq. 2 cuts (ALGORITHM §2).

    energy: float (H, W), normalised importance in [0, 1] (must be finite and
        non-negative).
    sizes: standard stroke sizes in px, any order. min_side = min(sizes),
        min_area = min(sizes)², max_area = max(sizes)² (see :func:`size_limits`).
    detail_threshold: T_e, absolute, in energy·pixel units (the same units as
        ``energy.sum()``); see :func:`detail_threshold` for the detail knob.
    delta: δ of Eq. 2 on the [0, 1] energy scale (> 0); gamma: γ (>= 0).

    Rules, in order, for each grid: area > max_area → must split;
    area < min_area → never split; total energy ≤ T_e → stop; otherwise
    split. A grid that should split but has no admissible cut (its longer side
    < 2·min_side) stays as it is. The cut of a grid is exactly the
    cheapest admissible position by Eq. 2, ties to the smallest (the tests
    hold it to the one-grid reference ``best_cut`` in tests/oracles.py).

    Returns int32 (N, 4) rows (x0, y0, x1, y1), half-open, non-empty, tiling
    the canvas exactly (every pixel in exactly one grid).

    Order (deterministic): breadth-first. Grids are processed one generation
    (tree depth) at a time; the grids that stop at depth d are emitted before
    any grid of depth d + 1, and within a generation in the order of their
    parents, the left/top half before the right/bottom half. This is the
    order a FIFO queue (pop from the front, push both halves to the back)
    would emit them in.

    Implementation: each generation is evaluated at once: the admissible
    positions of all grids being split are laid out in one ragged array
    (np.repeat with cumulative offsets), every Eq. 2 cost is computed in one
    expression from the SAT, and each grid's first minimum is taken with
    np.minimum.reduceat. The costs are computed by the same elementwise code
    (:func:`_eq2`) as the tests' one-grid reference, so the choice is
    bit-identical to it.
    """
    e = np.asarray(energy)
    if e.ndim != 2:
        raise InputError(f"The energy map must be a 2-D array, got {e.ndim} dimensions.")
    height, width = e.shape
    if height == 0 or width == 0:
        raise InputError(f"The energy map is empty ({height}x{width} pixels).")
    min_side, min_area, max_area = size_limits(sizes)
    _check_eq2_params(min_side, delta, gamma)
    delta = float(delta)
    gamma = float(gamma)
    t_e = float(detail_threshold)
    if math.isnan(t_e):
        raise ParameterError("The detail threshold must be a number, got NaN.")
    sat = summed_area_table(e)
    total = sat[-1, -1]
    if not np.isfinite(total):
        raise InputError("The energy map holds values that are not finite.")
    if np.any(e < 0):
        raise InputError("The energy map holds negative values; it must be in [0, 1].")

    active = np.array([[0, 0, width, height]], dtype=np.int64)
    finished = []
    while active.shape[0]:
        x0, y0, x1, y1 = active[:, 0], active[:, 1], active[:, 2], active[:, 3]
        w = x1 - x0
        h = y1 - y0
        area = w * h
        grid_sum = rect_sums(sat, x0, y0, x1, y1)
        want = (area > max_area) | ((area >= min_area) & (grid_sum > t_e))
        vertical = w >= h
        length = np.where(vertical, w, h)
        split = want & (length >= 2 * min_side)
        if not split.any():
            finished.append(active)
            break
        finished.append(active[~split])

        parents = active[split]
        px0, py0, px1, py1 = parents[:, 0], parents[:, 1], parents[:, 2], parents[:, 3]
        pv = vertical[split]
        plen = length[split]
        count = plen - 2 * min_side + 1                 # admissible positions per grid, >= 1
        starts = np.cumsum(count) - count               # offset of each grid's first candidate
        n_cand = int(count.sum())
        seg = np.repeat(np.arange(parents.shape[0]), count)
        rel = np.arange(n_cand, dtype=np.int64) - starts[seg] + min_side   # i, relative to x0/y0

        cx0, cy0, cx1, cy1 = px0[seg], py0[seg], px1[seg], py1[seg]
        cv = pv[seg]
        cut = np.where(cv, cx0, cy0) + rel              # absolute cut coordinate
        # first half: (x0, y0, cut, y1) or (x0, y0, x1, cut)
        h1x1 = np.where(cv, cut, cx1)
        h1y1 = np.where(cv, cy1, cut)
        # second half: (cut, y0, x1, y1) or (x0, cut, x1, y1)
        h2x0 = np.where(cv, cut, cx0)
        h2y0 = np.where(cv, cy0, cut)
        s1 = rect_sums(sat, cx0, cy0, h1x1, h1y1)
        s2 = rect_sums(sat, h2x0, h2y0, cx1, cy1)
        a1 = (h1x1 - cx0) * (h1y1 - cy0)
        a2 = (cx1 - h2x0) * (cy1 - h2y0)
        costs = _eq2(s1, a1, s2, a2, delta, gamma)

        seg_min = np.minimum.reduceat(costs, starts)
        index = np.arange(n_cand, dtype=np.int64)
        first = np.minimum.reduceat(np.where(costs == seg_min[seg], index, n_cand), starts)
        chosen = cut[first]

        children = np.empty((parents.shape[0], 2, 4), dtype=np.int64)
        children[:, 0, 0] = px0
        children[:, 0, 1] = py0
        children[:, 0, 2] = np.where(pv, chosen, px1)
        children[:, 0, 3] = np.where(pv, py1, chosen)
        children[:, 1, 0] = np.where(pv, chosen, px0)
        children[:, 1, 1] = np.where(pv, py0, chosen)
        children[:, 1, 2] = px1
        children[:, 1, 3] = py1
        active = children.reshape(-1, 4)

    return np.concatenate(finished, axis=0).astype(np.int32)


# ---------------------------------------------------------------------------
# sizes and threshold


def nearest_size(rects: np.ndarray, sizes: Sequence[float]) -> np.ndarray:
    """Standard stroke size (px) closest to sqrt(area) of each grid.

    rects: int (N, 4) rows (x0, y0, x1, y1), half-open.
    sizes: standard stroke sizes in px, any order (whole pixels).
    Returns int32 (N,) sizes taken from ``sizes``; when sqrt(area) lies
    exactly halfway between two sizes, the larger size wins.
    """
    r = np.asarray(rects, dtype=np.int64).reshape(-1, 4)
    s = np.asarray(sorted({float(v) for v in sizes}, reverse=True), dtype=np.float64)
    if s.size == 0:
        raise ParameterError("Stroke sizes must list at least one size.")
    if not np.all(s > 0):
        raise ParameterError(f"Stroke sizes must all be positive, got {list(sizes)}.")
    side = np.sqrt(((r[:, 2] - r[:, 0]) * (r[:, 3] - r[:, 1])).astype(np.float64))
    # descending sizes: argmin takes the first minimum, i.e. the larger size on a tie
    pick = np.argmin(np.abs(side[:, None] - s[None, :]), axis=1)
    return np.rint(s[pick]).astype(np.int32)


DETAIL_PERCENTILE = 95.0
"""ē_detail is this percentile of the local mean energy over s₂ × s₂ windows (ALGORITHM §2)."""


def detail_energy(energy: np.ndarray, window: int) -> float:
    """ē_detail: the 95th percentile of the mean energy of ``window`` × ``window`` squares (energy per pixel).

    energy: float (H, W) normalised importance in [0, 1]; window: side in px
    (clipped to the image). The squares are laid every ``max(1, window // 4)``
    px in both directions (the percentile of overlapping windows, without a
    full-size filtered copy); the image's own mean when it is smaller than
    one window.
    """
    e = np.asarray(energy, dtype=np.float64)
    h, w = e.shape
    if h == 0 or w == 0:
        return 0.0
    sy, sx = max(1, min(int(window), h)), max(1, min(int(window), w))
    step = max(1, min(sy, sx) // 4)
    sat = summed_area_table(e)
    y0 = np.arange(0, h - sy + 1, step)
    x0 = np.arange(0, w - sx + 1, step)
    yy, xx = np.meshgrid(y0, x0, indexing="ij")
    sums = sat[yy + sy, xx + sx] - sat[yy, xx + sx] - sat[yy + sy, xx] + sat[yy, xx]
    return float(np.percentile(sums / (sy * sx), DETAIL_PERCENTILE))


def detail_threshold(energy: np.ndarray, detail: float, sizes: Sequence[float]) -> float:
    """T_e for :func:`partition` from the image's detailed areas and the detail knob (ALGORITHM §2).

    energy: float (H, W) normalised importance in [0, 1]; detail: in [0, 1],
    0 = coarse, 1 = fine; sizes: the standard stroke sizes in px (scaled to
    the image).
    Returns T_e = q · ē_detail · s₂², in energy·pixel units, with s₂ the
    second-smallest size (the only one when there is one), ē_detail from
    :func:`detail_energy` over s₂ × s₂ windows and q = 16^(1 − detail): a grid
    of mean energy ē stops near area T_e / ē, so the most detailed areas
    (ē ≈ ē_detail) stop near side √q · s₂, near the small sizes, and smoother
    areas, with a smaller ē, at sides larger by √(ē_detail / ē). q = 16 at
    detail 0, 4 at 0.5, 2 at 0.75, 1 at 1. Sizes scale with √pixels and energy
    is normalised, so the knob means the same at any image
    size. An image with no energy gives T_e = 0, and its grids stop at max_area.
    """
    d = float(detail)
    if not (0.0 <= d <= 1.0):
        raise ParameterError(f"Detail must be between 0 and 1, got {detail}.")
    ordered = sorted(float(v) for v in sizes)
    if not ordered:
        raise ParameterError("Stroke sizes must list at least one size.")
    s2 = ordered[1] if len(ordered) > 1 else ordered[0]
    return 16.0 ** (1.0 - d) * detail_energy(energy, int(round(s2))) * s2 * s2
