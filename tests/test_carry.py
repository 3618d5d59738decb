"""Which carried strokes die (ALGORITHM §9, death), on control polygons worked out by hand."""

import math

import numpy as np
import pytest

from core.sequence.carry import crowded, folded, hidden, resized, stretched
from core.strokes.stroke_list import PAINTING_BRUSH, ROUND_BRUSH, StrokeList

POLYGON = np.array([[[10.0, 10.0], [20.0, 10.0], [30.0, 15.0], [40.0, 15.0]]])
VALID = np.ones((1, 4), bool)


def turned(points: np.ndarray, angle: float, scale: float = 1.0, shift=(0.0, 0.0)) -> np.ndarray:
    """``points`` (..., 2) turned by ``angle`` radians about the origin, scaled and shifted."""
    c, s = math.cos(angle), math.sin(angle)
    return scale * points @ np.array([[c, s], [-s, c]]) + np.asarray(shift)


def test_a_polygon_moved_turned_or_scaled_as_a_whole_has_not_folded():
    for angle in (0.0, 0.4, math.pi / 2, 3.0):
        assert not folded(POLYGON, turned(POLYGON, angle, 1.3, (5.0, -7.0)), VALID, math.pi / 6)[0]


def test_a_polygon_bent_at_a_control_point_by_more_than_the_threshold_has_folded():
    bent = POLYGON.copy()
    bent[0, 3] = [30.0 + 10.0 * math.cos(1.0), 15.0 + 10.0 * math.sin(1.0)]     # the last turn: 0 -> 1 rad
    assert folded(POLYGON, bent, VALID, math.pi / 6)[0]
    assert not folded(POLYGON, bent, VALID, 1.1)[0]
    padded = np.where(np.arange(4)[None, :, None] < 3, bent, np.nan)           # the bent point not in the stroke
    assert not folded(np.where(np.arange(4)[None, :, None] < 3, POLYGON, np.nan), padded,
                      np.arange(4)[None, :] < 3, math.pi / 6)[0]


def test_stretch_is_judged_against_the_length_at_birth_both_ways():
    birth = np.array([10.0, 10.0, 10.0, 10.0, 0.0])
    now = np.array([15.0, 15.1, 6.7, 6.6, 50.0])
    assert stretched(now, birth).tolist() == [False, True, False, True, False]


def test_a_stroke_dies_when_more_than_a_quarter_of_its_points_are_hidden():
    visible = np.ones((30, 50), bool)
    visible[:, 25:] = False                                         # x >= 25 hidden
    points = np.array([[[5.0, 5.0], [10.0, 5.0], [15.0, 5.0], [20.0, 5.0], [30.0, 5.0]],    # 1 of 5 hidden
                       [[5.0, 5.0], [10.0, 5.0], [15.0, 5.0], [30.0, 5.0], [35.0, 5.0]],    # 2 of 5 hidden
                       [[20.0, 5.0], [60.0, 5.0], [70.0, 5.0], [80.0, 5.0], [90.0, 5.0]]])  # off canvas: not counted
    assert hidden(points, np.ones((3, 5), bool), visible).tolist() == [False, True, False]


def strokes_at(anchors, layer, size, brush=PAINTING_BRUSH) -> StrokeList:
    """A stroke list of one-point strokes at (N, 2) ``anchors``, for the tests that read anchors, layer, size."""
    n = len(anchors)
    empty = StrokeList.empty()
    return StrokeList(np.full(n, layer, np.int32), np.full(n, size, np.int32), np.full(n, brush, np.int8),
                      np.asarray(anchors, float), np.asarray(anchors, float)[:, None, :], np.ones(n, np.int32),
                      np.zeros(n, np.int64), np.zeros(n, np.int64), np.zeros(n), empty.bristles,
                      np.zeros(n + 1, np.int64), np.zeros((n, 3), np.float32), np.ones(n, np.float32))


def test_only_strokes_that_came_closer_than_half_a_width_crowd_and_the_later_one_dies():
    before = np.array([[0.0, 0.0], [10.0, 0.0], [30.0, 0.0], [33.0, 0.0], [60.0, 0.0], [70.0, 0.0]])
    now = np.array([[0.0, 0.0], [3.0, 0.0], [30.0, 0.0], [33.0, 0.0], [60.0, 0.0], [63.0, 0.0]])
    strokes = strokes_at(now, 0, 8)
    leaving = np.array([False, False, False, False, True, False])
    assert crowded(strokes, before, leaving).tolist() == [False, True, False, False, False, False]
    other_layer = StrokeList.joined([strokes_at(now[:1], 1, 8), strokes_at(now[1:2], 0, 8)])
    assert not crowded(other_layer, before[:2], np.zeros(2, bool)).any()


def test_a_stroke_dies_when_every_pixel_around_it_asks_for_a_size_two_steps_away():
    sizes = (32, 16, 8, 4)
    size_map = np.full((40, 80), 4, np.int32)
    size_map[:, :40] = 16
    anchors = np.array([[10.0, 20.0], [10.0, 20.0], [70.0, 20.0], [41.0, 20.0], [70.0, 20.0]])
    size = np.array([16, 4, 32, 16, 8])
    brush = np.array([PAINTING_BRUSH, PAINTING_BRUSH, PAINTING_BRUSH, PAINTING_BRUSH, ROUND_BRUSH])
    # 16 on 16: kept; 4 on 16: two steps; 32 on 4: three steps; 16 by the boundary sees 16 within its width;
    # a round-brush dab keeps its size whatever the partition asks
    assert resized(anchors, size, brush, size_map, sizes).tolist() == [False, True, True, False, False]


def window_ranks(size_map: np.ndarray, sizes, rows, cols, own: int) -> tuple:
    """(least, greatest) rank in ``sizes`` of the sizes ``size_map`` asks for in the (2 (own // 2) + 1)-pixel
    square around each (rows, cols) pixel, cut at the edges: looked up pixel by pixel."""
    rank = {s: k for k, s in enumerate(sizes)}
    half = own // 2
    h, w = size_map.shape
    least, greatest = [], []
    for r, c in zip(rows, cols, strict=True):
        window = size_map[max(r - half, 0):min(r + half + 1, h), max(c - half, 0):min(c + half + 1, w)]
        ranks = [rank[int(s)] for s in np.unique(window)]
        least.append(min(ranks))
        greatest.append(max(ranks))
    return np.array(least), np.array(greatest)


@pytest.mark.parametrize("asked", [(48, 24, 12, 6, 3), (24, 12), (6, 3)])
def test_resized_agrees_with_the_ranks_looked_up_around_each_anchor_on_a_jittered_partition(asked):
    rng = np.random.default_rng(3)
    sizes = (48, 24, 12, 6, 3)
    blocks = rng.choice(asked, size=(9, 14))                                   # the sizes the partition asks for
    size_map = np.kron(blocks, np.ones((7, 7), np.int32))[:60, :95]            # grids of 7 px, cut at the edge
    n = 400
    anchors = np.stack([rng.uniform(-2.0, 96.0, n), rng.uniform(-2.0, 61.0, n)], axis=1)   # a few off the frame
    size = rng.choice(sizes, size=n)
    brush = np.where(rng.random(n) < 0.9, PAINTING_BRUSH, ROUND_BRUSH)
    dies = resized(anchors, size, brush, size_map, sizes)
    rows = np.clip(np.floor(anchors[:, 1] + 0.5).astype(int), 0, 59)
    cols = np.clip(np.floor(anchors[:, 0] + 0.5).astype(int), 0, 94)
    rank = {s: k for k, s in enumerate(sizes)}
    for own in sizes:
        pick = np.flatnonzero((size == own) & (brush == PAINTING_BRUSH))
        least, greatest = window_ranks(size_map, sizes, rows[pick], cols[pick], own)
        expected = (least - rank[own] >= 2) | (rank[own] - greatest >= 2)
        assert dies[pick].tolist() == expected.tolist()
    assert not dies[brush == ROUND_BRUSH].any()
    assert 0 < dies.sum() < n                                                   # both outcomes occur
