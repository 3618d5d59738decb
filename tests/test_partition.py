"""Tests of core/analysis/partition.py: Eq. 2 cuts, splitting rules, the tiling invariant."""

from __future__ import annotations

from collections import deque

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from oracles import best_cut, cut_costs

from core.analysis.partition import (
    DEFAULT_DELTA,
    detail_energy,
    detail_threshold,
    nearest_size,
    partition,
    rect_sums,
    size_limits,
    summed_area_table,
)
from core.errors import InputError, ParameterError

SIZES = (64, 32, 16, 8, 4)


# ---------------------------------------------------------------------------
# helpers and references


def energy_map(seed: int, h: int, w: int, kind: str = "uniform") -> np.ndarray:
    rng = np.random.default_rng(seed)
    if kind == "uniform":
        return rng.random((h, w)).astype(np.float32)
    if kind == "dyadic":  # multiples of 1/64: every sum is exact in float64
        return (rng.integers(0, 65, size=(h, w)) / 64.0).astype(np.float32)
    if kind == "sparse":  # mostly zero with a few hot pixels and blocks
        e = np.zeros((h, w), np.float32)
        e[rng.random((h, w)) < 0.05] = 1.0
        return e
    raise ValueError(kind)


def coverage(rects: np.ndarray, h: int, w: int) -> np.ndarray:
    count = np.zeros((h, w), np.int32)
    for x0, y0, x1, y1 in rects:
        count[y0:y1, x0:x1] += 1
    return count


def reference_partition(energy, sizes, t_e, delta=DEFAULT_DELTA, gamma=1.0, order="dfs"):
    """Plain recursive (or FIFO) partition on top of best_cut, one grid at a time."""
    h, w = energy.shape
    sat = summed_area_table(energy)
    min_side, min_area, max_area = size_limits(sizes)

    def cut_of(rect):
        x0, y0, x1, y1 = rect
        area = (x1 - x0) * (y1 - y0)
        if area > max_area:
            pass
        elif area < min_area:
            return None
        elif float(rect_sums(sat, x0, y0, x1, y1)) <= t_e:
            return None
        c = best_cut(sat, rect, min_side, delta, gamma)
        if c is None:
            return None
        if x1 - x0 >= y1 - y0:
            return (x0, y0, c, y1), (c, y0, x1, y1)
        return (x0, y0, x1, c), (x0, c, x1, y1)

    out = []
    if order == "dfs":
        def rec(rect):
            halves = cut_of(rect)
            if halves is None:
                out.append(rect)
            else:
                rec(halves[0])
                rec(halves[1])
        rec((0, 0, w, h))
    else:
        queue = deque([(0, 0, w, h)])
        while queue:
            rect = queue.popleft()
            halves = cut_of(rect)
            if halves is None:
                out.append(rect)
            else:
                queue.extend(halves)
    return np.array(out, dtype=np.int64).reshape(-1, 4)


def sorted_rows(a: np.ndarray) -> np.ndarray:
    a = np.asarray(a, dtype=np.int64).reshape(-1, 4)
    return a[np.lexsort(a.T[::-1])]


def brute_costs(energy, rect, min_side, delta, gamma):
    """Eq. 2 by plain Python loops over pixel sums (no SAT): [(absolute position, cost)]."""
    x0, y0, x1, y1 = rect
    w, h = x1 - x0, y1 - y0
    vertical = w >= h
    length = w if vertical else h
    rows = energy.astype(np.float64).tolist()

    def box_sum(a, b, c, d):
        s = 0.0
        for y in range(b, d):
            row = rows[y]
            for x in range(a, c):
                s += row[x]
        return s

    out = []
    for i in range(min_side, length - min_side + 1):
        if vertical:
            r1, r2 = (x0, y0, x0 + i, y1), (x0 + i, y0, x1, y1)
        else:
            r1, r2 = (x0, y0, x1, y0 + i), (x0, y0 + i, x1, y1)
        a1 = (r1[2] - r1[0]) * (r1[3] - r1[1])
        a2 = (r2[2] - r2[0]) * (r2[3] - r2[1])
        m1 = box_sum(*r1) / a1
        m2 = box_sum(*r2) / a2
        e_small, e_big = min(m1, m2), max(m1, m2)
        s_small, s_big = min(a1, a2), max(a1, a2)
        cost = ((e_small + delta) / (e_big + delta)) * (s_big / s_small) ** gamma
        out.append(((x0 if vertical else y0) + i, cost))
    return out


size_lists = st.lists(st.integers(1, 40), min_size=1, max_size=5)


def canvases(most: int) -> dict:
    """Hypothesis strategies of whole canvases to partition: an ``energy_map`` (seed, h, w, kind) up to ``most`` px
    a side, its stroke sizes and the detail that sets its threshold."""
    return dict(seed=st.integers(0, 10_000), h=st.integers(1, most), w=st.integers(1, most), sizes=size_lists,
                kind=st.sampled_from(["uniform", "dyadic", "sparse"]), detail=st.floats(0.0, 1.0))


# ---------------------------------------------------------------------------
# summed-area table and single-grid costs


def test_summed_area_table_matches_sums():
    e = energy_map(1, 13, 17)
    sat = summed_area_table(e)
    assert sat.dtype == np.float64 and sat.shape == (14, 18)
    assert np.all(sat[0] == 0) and np.all(sat[:, 0] == 0)
    for (x0, y0, x1, y1) in [(0, 0, 17, 13), (3, 2, 9, 11), (5, 5, 5, 9), (16, 12, 17, 13)]:
        assert rect_sums(sat, x0, y0, x1, y1) == pytest.approx(e[y0:y1, x0:x1].astype(np.float64).sum(), abs=1e-9)


def test_cut_costs_axis_and_positions():
    e = energy_map(2, 20, 30)
    sat = summed_area_table(e)
    axis, pos, costs = cut_costs(sat, (2, 3, 26, 13), 4, DEFAULT_DELTA, 1.0)  # 24 wide, 10 high
    assert axis == 1
    assert pos.tolist() == list(range(6, 23))
    assert costs.shape == pos.shape and np.all(costs > 0)
    axis, pos, costs = cut_costs(sat, (2, 3, 12, 19), 4, DEFAULT_DELTA, 1.0)  # 10 wide, 16 high
    assert axis == 0
    assert pos.tolist() == list(range(7, 16))
    # square: vertical cut
    axis, pos, _ = cut_costs(sat, (0, 0, 10, 10), 5)
    assert axis == 1 and pos.tolist() == [5]
    # no admissible cut
    axis, pos, costs = cut_costs(sat, (0, 0, 9, 7), 5)
    assert pos.size == 0 and costs.size == 0 and pos.dtype == np.int64 and costs.dtype == np.float64
    assert best_cut(sat, (0, 0, 9, 7), 5) is None


def test_cut_follows_energy_edge():
    # a step whose smooth side is the smaller one: the cut lands exactly on the step
    e = np.zeros((40, 60), np.float32)
    e[:, 25:] = 1.0
    sat = summed_area_table(e)
    assert best_cut(sat, (0, 0, 60, 40), 4) == 25
    e = np.full((60, 40), 0.5, np.float32)
    e[:22, :] = 0.0
    sat = summed_area_table(e)
    assert best_cut(sat, (0, 0, 40, 60), 4) == 22
    # a step with the smooth side the larger one: with gamma = 1 the energy ratio
    # (delta / mean of the textured half) dilutes only linearly while the area
    # ratio grows, so Eq. 2 cuts at the middle; a weaker area penalty finds the step
    e = np.zeros((40, 60), np.float32)
    e[:, 37:] = 1.0
    sat = summed_area_table(e)
    assert best_cut(sat, (0, 0, 60, 40), 4, gamma=1.0) == 30
    assert best_cut(sat, (0, 0, 60, 40), 4, gamma=0.5) == 37


def test_zero_energy_cut_is_middle_first_tie():
    sat = summed_area_table(np.zeros((10, 31)))
    # odd length 31: positions 15 and 16 tie; the first wins
    assert best_cut(sat, (0, 0, 31, 10), 4) == 15
    assert best_cut(sat, (0, 0, 30, 10), 4) == 15


@settings(max_examples=60, deadline=None)
@given(
    seed=st.integers(0, 10_000),
    h=st.integers(1, 14),
    w=st.integers(1, 14),
    min_side=st.integers(1, 5),
    kind=st.sampled_from(["dyadic", "sparse"]),
    gamma=st.sampled_from([1.0, 0.5, 2.0, 0.0]),
    delta=st.sampled_from([DEFAULT_DELTA, 0.25]),
    data=st.data(),
)
def test_best_cut_equals_brute_force(seed, h, w, min_side, kind, gamma, delta, data):
    e = energy_map(seed, 16, 16, kind)
    x0 = data.draw(st.integers(0, 16 - w))
    y0 = data.draw(st.integers(0, 16 - h))
    rect = (x0, y0, x0 + w, y0 + h)
    sat = summed_area_table(e)
    brute = brute_costs(e, rect, min_side, delta, gamma)
    axis, pos, costs = cut_costs(sat, rect, min_side, delta, gamma)
    assert pos.tolist() == [p for p, _ in brute]
    assert axis == (1 if w >= h else 0)
    got = best_cut(sat, rect, min_side, delta, gamma)
    if not brute:
        assert got is None
        return
    bc = np.array([c for _, c in brute])
    np.testing.assert_allclose(costs, bc, rtol=1e-12)
    best_pos = brute[int(np.argmin(bc))][0]
    if gamma in (1.0, 0.0):
        # dyadic energies: sums are exact, so the floats agree bit for bit
        assert got == best_pos
    else:
        # powers may differ by an ulp between numpy and Python: the choice must be a minimum
        assert dict(brute)[got] <= bc.min() * (1 + 1e-12)


# ---------------------------------------------------------------------------
# whole-canvas partition


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(**canvases(120))
def test_tiling_and_size_rules(seed, h, w, sizes, kind, detail):
    e = energy_map(seed, h, w, kind)
    t_e = detail_threshold(e, detail, sizes)
    rects = partition(e, sizes, t_e)
    assert rects.dtype == np.int32 and rects.ndim == 2 and rects.shape[1] == 4
    x0, y0, x1, y1 = (rects[:, k].astype(np.int64) for k in range(4))
    # non-empty, inside the canvas
    assert np.all(x0 >= 0) and np.all(y0 >= 0) and np.all(x1 <= w) and np.all(y1 <= h)
    assert np.all(x1 > x0) and np.all(y1 > y0)
    # every pixel exactly once
    assert np.all(coverage(rects, h, w) == 1)

    min_side, min_area, max_area = size_limits(sizes)
    gw, gh = x1 - x0, y1 - y0
    area = gw * gh
    longer = np.maximum(gw, gh)
    # no grid above max_area unless it cannot be cut
    assert np.all((area <= max_area) | (longer < 2 * min_side))
    # cuts keep every side >= min_side, unless the canvas side itself is shorter
    assert np.all(gw >= min(min_side, w)) and np.all(gh >= min(min_side, h))
    # every final grid satisfies a stop condition
    sat = summed_area_table(e)
    sums = rect_sums(sat, x0, y0, x1, y1)
    stops = (area < min_area) | ((area <= max_area) & (sums <= t_e)) | (longer < 2 * min_side)
    assert np.all(stops)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(**canvases(90), gamma=st.sampled_from([1.0, 0.5, 2.0]))
def test_vectorised_equals_recursive_best_cut(seed, h, w, sizes, kind, detail, gamma):
    e = energy_map(seed, h, w, kind)
    t_e = detail_threshold(e, detail, sizes)
    got = partition(e, sizes, t_e, gamma=gamma)
    dfs = reference_partition(e, sizes, t_e, gamma=gamma, order="dfs")
    assert np.array_equal(sorted_rows(got), sorted_rows(dfs))
    # and the documented order is exactly the FIFO (breadth-first) order
    bfs = reference_partition(e, sizes, t_e, gamma=gamma, order="bfs")
    assert np.array_equal(got.astype(np.int64), bfs)


def test_vectorised_equals_recursive_on_larger_image():
    from scipy.ndimage import gaussian_filter

    rng = np.random.default_rng(7)
    e = gaussian_filter(rng.random((300, 420)), 3)
    e = ((e - e.min()) / (e.max() - e.min())).astype(np.float32)
    t_e = detail_threshold(e, 0.7, SIZES)
    got = partition(e, SIZES, t_e)
    ref = reference_partition(e, SIZES, t_e, order="bfs")
    assert len(got) > 200
    assert np.array_equal(got.astype(np.int64), ref)


def test_textured_half_gets_more_smaller_grids():
    rng = np.random.default_rng(3)
    h, w = 256, 256
    e = np.zeros((h, w), np.float32)
    e[:, :128] = 0.002 * rng.random((h, 128))
    e[:, 128:] = rng.random((h, 128))
    sizes = (32, 16, 8, 4)
    rects = partition(e, sizes, detail_threshold(e, 0.6, sizes)).astype(np.int64)
    assert np.all(coverage(rects, h, w) == 1)
    cx = (rects[:, 0] + rects[:, 2]) / 2.0
    area = (rects[:, 2] - rects[:, 0]) * (rects[:, 3] - rects[:, 1])
    right = cx >= 128
    assert right.sum() >= 4 * (~right).sum()
    assert area[right].mean() < area[~right].mean()
    # the first cut lands on the texture boundary, so no grid straddles it
    assert np.all((rects[:, 2] <= 128) | (rects[:, 0] >= 128))


@pytest.mark.parametrize("shape,sizes", [((200, 130), (32, 8)), ((64, 64), (16, 4)), ((97, 251), (40, 10, 20)),
                                         ((3, 500), (16, 4))])
def test_zero_energy_only_max_area_splits(shape, sizes):
    h, w = shape
    e = np.zeros(shape, np.float32)
    rects = partition(e, sizes, 1e-9).astype(np.int64)
    assert np.all(coverage(rects, h, w) == 1)
    min_side, _, max_area = size_limits(sizes)
    area = (rects[:, 2] - rects[:, 0]) * (rects[:, 3] - rects[:, 1])
    assert np.all(area <= max_area)

    # zero energy: the cost is the area ratio alone, so every cut is at the middle (first tie)
    def halves(rect):
        x0, y0, x1, y1 = rect
        gw, gh = x1 - x0, y1 - y0
        if gw * gh <= max_area or max(gw, gh) < 2 * min_side:
            return [rect]
        if gw >= gh:
            c = x0 + gw // 2
            return halves((x0, y0, c, y1)) + halves((c, y0, x1, y1))
        c = y0 + gh // 2
        return halves((x0, y0, x1, c)) + halves((x0, c, x1, y1))

    expected = np.array(halves((0, 0, w, h)))
    assert np.array_equal(sorted_rows(rects), sorted_rows(expected))


def test_blank_canvas_stops_at_the_largest_size():
    # A grid holding no more than T_e stops once it is within max_area, even when T_e = 0.
    e = np.zeros((64, 64), np.float32)
    rects = partition(e, (16, 4), detail_threshold(e, 0.5, (16, 4))).astype(np.int64)
    assert len(rects) == 16
    assert np.all((rects[:, 2] - rects[:, 0]) == 16) and np.all((rects[:, 3] - rects[:, 1]) == 16)


def test_zero_threshold_splits_textured_grids_to_min_area():
    # With T_e = 0 every grid holding any energy splits down to the smallest size.
    e = np.full((64, 64), 0.5, np.float32)
    rects = partition(e, (16, 4), 0.0).astype(np.int64)
    assert len(rects) == 256
    assert np.all((rects[:, 2] - rects[:, 0]) == 4) and np.all((rects[:, 3] - rects[:, 1]) == 4)


def test_detail_is_monotonic():
    from scipy.ndimage import gaussian_filter

    rng = np.random.default_rng(11)
    e = gaussian_filter(rng.random((240, 320)), 2)
    e = ((e - e.min()) / (e.max() - e.min())).astype(np.float32)
    counts = [len(partition(e, SIZES, detail_threshold(e, d, SIZES))) for d in np.linspace(0, 1, 11)]
    assert all(a <= b for a, b in zip(counts, counts[1:], strict=False))
    assert counts[-1] > counts[0]


def test_single_pixel_and_tiny_canvases():
    for shape in [(1, 1), (1, 7), (7, 1), (3, 3)]:
        e = np.ones(shape, np.float32)
        rects = partition(e, SIZES, 0.0)
        assert rects.tolist() == [[0, 0, shape[1], shape[0]]]


def test_sizes_in_any_order_give_same_partition():
    e = energy_map(5, 70, 90)
    t_e = detail_threshold(e, 0.5, SIZES)
    a = partition(e, (4, 32, 8, 16), t_e)
    b = partition(e, (32, 16, 8, 4), t_e)
    assert np.array_equal(a, b)


def test_bad_inputs_raise():
    e = energy_map(0, 10, 10)
    with pytest.raises(InputError):
        partition(np.zeros((0, 5)), SIZES, 0.0)
    with pytest.raises(InputError):
        partition(np.zeros((4, 4, 3)), SIZES, 0.0)
    bad = e.copy()
    bad[2, 2] = np.nan
    with pytest.raises(InputError):
        partition(bad, SIZES, 0.0)
    with pytest.raises(InputError):
        partition(-e, SIZES, 0.0)
    with pytest.raises(ParameterError):
        partition(e, (), 0.0)
    with pytest.raises(ParameterError):
        partition(e, (8, 0), 0.0)
    with pytest.raises(ParameterError):
        partition(e, SIZES, 0.0, delta=0.0)
    with pytest.raises(ParameterError):
        partition(e, SIZES, 0.0, gamma=-1.0)
    with pytest.raises(ParameterError):
        detail_threshold(e, 1.5, SIZES)


# ---------------------------------------------------------------------------
# sizes and threshold


def test_nearest_size_hand_worked():
    sizes = (64, 32, 16, 8, 4)
    rects = np.array([
        [0, 0, 64, 64],     # sqrt = 64          -> 64
        [0, 0, 4, 4],       # 4                  -> 4
        [0, 0, 24, 24],     # 24: tie 16 / 32    -> 32 (larger)
        [0, 0, 12, 12],     # 12: tie 8 / 16     -> 16
        [0, 0, 6, 6],       # 6: tie 4 / 8       -> 8
        [10, 20, 33, 43],   # 23 x 23 = 529 -> 23 -> 16 (|23-16|=7 < 9)
        [0, 0, 100, 4],     # 400 -> 20          -> 16
        [0, 0, 200, 30],    # 6000 -> 77.5       -> 64
        [0, 0, 1, 1],       # 1                  -> 4
        [5, 5, 30, 30],     # 25                 -> 32 (7 < 9)
        [0, 0, 2, 8],       # 16 -> 4            -> 4
    ])
    got = nearest_size(rects, sizes)
    assert got.dtype == np.int32
    assert got.tolist() == [64, 4, 32, 16, 8, 16, 16, 64, 4, 32, 4]
    # order of the size list does not matter
    assert nearest_size(rects, (4, 16, 64, 8, 32)).tolist() == got.tolist()
    assert nearest_size(np.zeros((0, 4), np.int32), sizes).shape == (0,)
    assert nearest_size(rects, (10,)).tolist() == [10] * len(rects)


def test_detail_threshold_mapping():
    # A uniform energy: every window's mean is 0.5, so T_e = q * 0.5 * s2^2 with s2 = 8 (the second-smallest).
    e = np.full((40, 60), 0.5, np.float32)
    sizes = (64, 32, 16, 8, 4)
    assert detail_threshold(e, 0.0, sizes) == pytest.approx(16 * 0.5 * 64)
    assert detail_threshold(e, 0.5, sizes) == pytest.approx(4 * 0.5 * 64)
    assert detail_threshold(e, 0.75, sizes) == pytest.approx(2 * 0.5 * 64)
    assert detail_threshold(e, 1.0, sizes) == pytest.approx(0.5 * 64)
    assert detail_threshold(e, 0.5, (12,)) == pytest.approx(4 * 0.5 * 144)   # one size: s2 is that size
    assert detail_threshold(np.zeros((5, 5)), 0.3, sizes) == 0.0


def test_detail_energy_is_the_95th_percentile_of_window_means():
    # Left 90 % of the columns at 0.1, right 10 % at 0.9: windows of 4 x 4 px fully inside the bright band
    # are the top 5 % or so, so the 95th percentile is the bright band's energy, not the image's mean.
    e = np.full((40, 200), 0.1, np.float32)
    e[:, 180:] = 0.9
    assert detail_energy(e, 4) == pytest.approx(0.9)
    assert float(e.mean()) == pytest.approx(0.18)
    assert detail_energy(np.full((3, 3), 0.4), 8) == pytest.approx(0.4)   # smaller than one window


def test_detail_keeps_its_meaning_across_image_sizes():
    """The same photo at 1 MP and at 4 MP: sizes scale with the side, and the grids per size stay in proportion."""
    from scipy.ndimage import gaussian_filter, zoom

    rng = np.random.default_rng(3)
    small = gaussian_filter(rng.random((250, 400)), 1.5)
    small[:, :200] *= 0.05                               # a smooth half and a detailed half
    small = (small / small.max()).astype(np.float32)
    large = np.clip(zoom(small, 2, order=1), 0, 1).astype(np.float32)
    shares = []
    for e, scale in ((small, 1), (large, 2)):
        sizes = tuple(s * scale for s in (32, 16, 8, 4))
        rects = partition(e, sizes, detail_threshold(e, 0.75, sizes))
        got = nearest_size(rects, sizes)
        shares.append([float(np.mean(got == s)) for s in sizes])
    assert np.allclose(shares[0], shares[1], atol=0.12), shares
