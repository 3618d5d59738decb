"""core/motion: Vector pass conversion, bilinear warping, visibility and the measures of a sequence (§9).

Every expectation is worked out here from a known motion: frames made with
analytic functions translated by a known shift, regions with known motions
and hand-made Vector passes. Blender's own conventions are checked on a
render in tests/test_vector_pass_blender.py.
"""

import math
import warnings

import numpy as np
import pytest

from core.motion import (
    backward_motion,
    bilinear,
    forward_motion,
    inside_frame,
    mean_over_pairs,
    motion_boundary,
    motion_pair,
    normalise,
    pixel_positions,
    round_trip_consistent,
    still_pixels,
    stillness,
    value_range,
    visible_in_both,
    warp,
    warp_back,
    warping_error,
)
from core.motion.warp import reach, within_reach

H, W = 32, 48
SHIFT = (1.25, -0.5)  # px, x right, y down: frame t+1 is frame t moved by this


def smooth_scene(x, y):
    """An (..., 3) colour in [0.3, 0.7] at positions x, y (px): slow waves, so bilinear sampling is close."""
    tau = 2.0 * math.pi
    return np.stack([0.5 + 0.2 * np.sin(tau * x / 23.0 + 0.3) * np.cos(tau * y / 17.0),
                     0.5 + 0.2 * np.cos(tau * (x + y) / 29.0),
                     0.5 + 0.2 * np.sin(tau * (x - 2.0 * y) / 31.0 + 1.0)], axis=-1).astype(np.float32)


def bilinear_scene(x, y):
    """An (...) value in [0.1, 0.9] at x, y (px) that bilinear interpolation reproduces exactly: a + bx + cy + dxy."""
    return (0.1 + 0.01 * x + 0.008 * y + 0.0002 * x * y).astype(np.float32)


def translated_pair(scene, shift=SHIFT):
    """Frames t and t+1 of ``scene`` moved by ``shift``: V_{t+1}(p) = V_t(p - shift), both exact."""
    y, x = np.mgrid[0:H, 0:W].astype(np.float64)
    return scene(x, y), scene(x - shift[0], y - shift[1])


def uniform(motion, shape=(H, W)):
    return np.broadcast_to(np.asarray(motion, dtype=np.float32), (*shape, 2)).copy()


# --- the Vector pass ----------------------------------------------------------------------------------------------

def test_vector_pass_to_forward_and_backward_motion():
    vector = np.zeros((2, 3, 4), dtype=np.float32)
    vector[1, 2] = (1.5, -2.0, 3.0, 0.25)  # X, Y, Z, W at row 1, column 2
    vector[0, 0] = (-4.0, 5.0, -6.0, -7.0)
    forward, backward = forward_motion(vector), backward_motion(vector)
    assert forward.dtype == backward.dtype == np.float32 and forward.shape == (2, 3, 2)
    # Forward (t -> t+1) is (-Z, +W); backward (t -> t-1) is (X, -Y), in image axes (y down).
    assert forward[1, 2].tolist() == [-3.0, 0.25] and forward[0, 0].tolist() == [6.0, -7.0]
    assert backward[1, 2].tolist() == [1.5, 2.0] and backward[0, 0].tolist() == [-4.0, -5.0]
    assert not forward[0, 1].any() and not backward[1, 1].any()


def test_motion_pair_takes_forward_from_frame_t_and_backward_from_frame_t_plus_1():
    pass_t = np.tile(np.float32([1.0, 2.0, 3.0, 4.0]), (24, 32, 1))
    pass_next = np.tile(np.float32([10.0, 20.0, 30.0, 40.0]), (24, 32, 1))
    forward, backward = motion_pair(pass_t, pass_next)
    assert np.array_equal(forward, uniform((-3.0, 4.0), (24, 32)))
    assert np.array_equal(backward, uniform((10.0, -20.0), (24, 32)))
    with pytest.raises(ValueError, match="differ in size"):
        motion_pair(pass_t, pass_next[:3])
    with pytest.raises(ValueError, match=r"\(H, W, 4\)"):
        forward_motion(pass_t[..., :3])


# --- sampling and warping -----------------------------------------------------------------------------------------

def test_pixel_positions_are_column_and_row():
    grid = pixel_positions(2, 3)
    assert grid.shape == (2, 3, 2) and grid.dtype == np.float32
    assert grid[1, 2].tolist() == [2.0, 1.0]


def test_bilinear_between_four_pixels():
    image = np.float32([[0.0, 1.0], [2.0, 3.0]])  # value = x + 2y at the pixel centres
    positions = np.float32([[0.25, 0.5], [1.0, 0.0], [0.5, 1.0]])
    assert bilinear(image, positions) == pytest.approx([0.25 + 1.0, 1.0, 0.5 + 2.0])
    colour = np.stack([image, 10.0 * image], axis=-1)
    assert bilinear(colour, positions[:1])[0].tolist() == pytest.approx([1.25, 12.5])


def test_positions_outside_the_frame_take_the_edge_and_are_not_in_it():
    image = np.float32([[0.0, 1.0], [2.0, 3.0]])
    positions = np.float32([[-0.5, 0.0], [1.0, 1.5], [3.0, -2.0], [np.nan, 0.5], [0.5, np.inf], [1.0, 1.0]])
    assert inside_frame(positions, 2, 2).tolist() == [False, False, False, False, False, True]
    assert bilinear(image, positions[:3]).tolist() == [0.0, 3.0, 1.0]
    assert np.isfinite(bilinear(image, positions)).all()


def test_warping_a_translated_frame_back_with_the_true_motion_gives_the_frame():
    frame, next_frame = translated_pair(bilinear_scene)
    warped, inside = warp_back(next_frame, uniform(SHIFT))
    # x + 1.25 <= W - 1 and y - 0.5 >= 0: the last two columns and the first row leave the frame.
    assert inside.sum() == (W - 2) * (H - 1) and not inside[0].any() and not inside[:, -2:].any()
    assert np.abs(warped - frame)[inside].max() < 1e-5
    with pytest.raises(ValueError, match="motion"):
        warp_back(next_frame, uniform(SHIFT, (H, W - 1)))


# --- visibility ---------------------------------------------------------------------------------------------------

def test_a_uniform_shift_is_visible_except_where_it_leaves_the_frame():
    forward, backward = uniform(SHIFT), uniform((-SHIFT[0], -SHIFT[1]))
    visible = visible_in_both(forward, backward)
    expected = np.ones((H, W), dtype=bool)
    expected[0, :] = False   # y - 0.5 < 0
    expected[:, -2:] = False  # x + 1.25 > W - 1 from column W - 2 on
    assert np.array_equal(visible, expected)
    assert not motion_boundary(forward).any()


def test_a_backward_motion_that_does_not_undo_the_forward_one_is_not_visible():
    forward = uniform((3.0, 0.0))
    assert round_trip_consistent(forward, uniform((-3.0, 0.0))).all()
    # Missing by 0.7 px: 0.49 <= 0.01 (9 + 5.29) + 0.5; by 0.9 px: 0.81 > 0.01 (9 + 4.41) + 0.5.
    assert round_trip_consistent(forward, uniform((-2.3, 0.0))).all()
    assert not round_trip_consistent(forward, uniform((-2.1, 0.0))).any()
    # The allowance grows with the motion: missing 30 px by 1.5 px passes (2.25 <= 0.01 (900 + 812.25) + 0.5),
    # by 4.5 px it does not (20.25 > 0.01 (900 + 650.25) + 0.5).
    assert round_trip_consistent(uniform((30.0, 0.0)), uniform((-28.5, 0.0))).all()
    assert not round_trip_consistent(uniform((30.0, 0.0)), uniform((-25.5, 0.0))).any()
    assert not visible_in_both(forward, uniform((3.0, 0.0))).any()


def test_an_occluding_edge_between_two_regions_moving_differently():
    # Frame t: a still background left of column 20, an object from column 20 on moving 4 px left.
    # In frame t+1 the object covers columns 16 on: its pixels there move 4 px right back to frame t.
    edge, step = 20, 4.0
    forward = np.zeros((H, W, 2), dtype=np.float32)
    forward[:, edge:, 0] = -step
    backward = np.zeros((H, W, 2), dtype=np.float32)
    backward[:, edge - int(step):, 0] = step
    # Central differences of u: -2 px/px at columns 19 and 20, 0 elsewhere; 4 > 0.002 and 4 > 0.01 * 16 + 0.002.
    assert np.flatnonzero(motion_boundary(forward)[5]).tolist() == [19, 20]
    backward_there, inside = warp_back(backward, forward)
    assert inside.all()
    # The background under the object's new place (columns 16 to 19) goes 0 forward but 4 back: occluded.
    consistent = round_trip_consistent(forward, backward_there)
    assert np.flatnonzero(~consistent[5]).tolist() == [16, 17, 18, 19]
    visible = visible_in_both(forward, backward)
    expected = np.ones(W, dtype=bool)
    expected[16:21] = False
    assert (visible == expected).all()


def test_a_smooth_zoom_is_not_a_motion_boundary():
    # u = 0.04 (x - 24): |grad u|^2 = 0.0016 <= 0.002 everywhere. u = 0.05 (x - 24): 0.0025 exceeds
    # 0.01 (0.05 (x - 24))^2 + 0.002 only where (x - 24)^2 < 20, where the motion itself is small.
    x = pixel_positions(H, W)[..., 0]
    gentle = np.stack([0.04 * (x - 24.0), np.zeros_like(x)], axis=-1)
    steep = np.stack([0.05 * (x - 24.0), np.zeros_like(x)], axis=-1)
    assert not motion_boundary(gentle).any()
    assert np.flatnonzero(motion_boundary(steep)[7]).tolist() == list(range(20, 29))
    assert (motion_boundary(steep) == motion_boundary(steep)[0]).all()


# --- measures -----------------------------------------------------------------------------------------------------

def test_warping_error_of_a_translated_frame_is_about_zero_with_the_true_motion_only():
    frame, next_frame = translated_pair(smooth_scene)
    forward, backward = uniform(SHIFT), uniform((-SHIFT[0], -SHIFT[1]))
    visible = visible_in_both(forward, backward)
    right = warping_error(frame, next_frame, forward, visible)
    # Bilinear sampling errs by at most (max |V_xx| + max |V_yy|) / 8 px^2, here 0.2 ((2 pi / 17)^2 + (2 pi / 23)^2) / 8
    # = 0.0053 at most (the red channel's waves; the others are longer).
    assert right < 0.0053 ** 2
    for wrong in (uniform((-SHIFT[0], -SHIFT[1])), uniform(SHIFT[::-1]), uniform((0.0, 0.0))):
        assert warping_error(frame, next_frame, wrong, visible) > 100 * right
    exact, exact_next = translated_pair(bilinear_scene)
    assert warping_error(exact, exact_next, forward, visible) < 1e-11


def test_warping_error_is_the_mean_square_over_visible_pixels_and_channels():
    frame = np.zeros((4, 4, 3), dtype=np.float32)
    next_frame = frame.copy()
    next_frame[..., 0] = 0.5  # channel 0 off by 0.5 everywhere, the others exact
    visible = np.zeros((4, 4), dtype=bool)
    visible[1:3, 1:3] = True
    assert warping_error(frame, next_frame, uniform((0.0, 0.0), (4, 4)), visible) == pytest.approx(0.25 / 3)
    assert math.isnan(warping_error(frame, next_frame, uniform((0.0, 0.0), (4, 4)), np.zeros((4, 4), bool)))


def test_stillness():
    frame, _ = translated_pair(smooth_scene)
    forward = uniform((0.0, 0.0))
    forward[:, :10] = (0.3, 0.0)  # the first ten columns move forward by 0.3 px
    backward = uniform((0.0, 0.2))
    backward[:4] = (0.0, -0.25)  # the first four rows move back by 0.25 px
    still = still_pixels(forward, backward)
    expected = np.ones((H, W), dtype=bool)
    expected[:, :10] = False
    expected[:4] = False
    assert np.array_equal(still, expected)
    assert stillness(frame, frame, still) == 0.0
    changed = frame + np.where(np.indices((H, W)).sum(axis=0)[..., None] % 2 == 0, 0.1, -0.1)  # up and down
    changed[~still] = 0.9  # changes where it moves do not count
    assert stillness(frame, changed, still) == pytest.approx(0.1, abs=1e-6)
    assert math.isnan(stillness(frame, changed, np.zeros((H, W), dtype=bool)))


def test_mean_over_pairs_leaves_out_pairs_with_nothing_to_measure():
    assert mean_over_pairs([0.1, float("nan"), 0.3]) == pytest.approx(0.2)
    assert math.isnan(mean_over_pairs([float("nan")]))


def test_heights_normalised_over_the_sequence():
    heights = [np.float32([[0.0, 2.0]]), np.float32([[4.0, np.nan]]), np.float32([[-1.0, 3.0]])]
    low, high = value_range(iter(heights))
    assert (low, high) == (-1.0, 4.0)
    assert normalise(heights[0], low, high)[0].tolist() == pytest.approx([0.2, 0.6])
    assert normalise(heights[2], low, high)[0].tolist() == pytest.approx([0.0, 0.8])
    assert not normalise(heights[0], 2.0, 2.0).any()
    with pytest.raises(ValueError, match="no finite value"):
        value_range([np.float32([np.nan])])


# --- motions no pixel that stays in the frame can have ----------------------------------------------------------

ABSURD = (1e30, -1e30, np.inf, -np.inf, np.nan)
"""Values a Vector pass may hold that no motion can have."""


def quietly(work):
    """``work()``'s result, with every NumPy floating-point error and every warning raised instead of printed."""
    with warnings.catch_warnings(), np.errstate(all="raise"):
        warnings.simplefilter("error")
        return work()


def test_a_motion_within_reach_is_the_same_array():
    motion = uniform((W + H, -(W + H)))
    assert reach(H, W) == W + H
    assert within_reach(motion) is motion


@pytest.mark.parametrize("value", ABSURD)
def test_a_motion_out_of_reach_is_clipped_to_it_and_still_leaves_the_frame(value):
    motion = uniform((0.5, -1.0))
    motion[3, 4, 0] = value
    motion[5, 6, 1] = value
    bounded = quietly(lambda: within_reach(motion))
    limit = W + H
    expected_x = limit if np.isnan(value) or value > 0 else -limit
    assert bounded[3, 4].tolist() == [expected_x, -1.0] and bounded[5, 6].tolist() == [0.5, expected_x]
    untouched = np.ones((H, W), bool)
    untouched[3, 4] = untouched[5, 6] = False
    assert np.array_equal(bounded[untouched], motion[untouched])
    assert not inside_frame(pixel_positions(H, W) + bounded, H, W)[[3, 5], [4, 6]].any()


@pytest.mark.parametrize("value", ABSURD)
def test_a_vector_pass_out_of_reach_leaves_the_frame_quietly(value):
    """A Vector pass with values no motion can have: its pixels are not visible, not still and not a figure's;
    the rest of the frame is as it was, and nothing overflows or warns."""
    vector_pass = np.zeros((H, W, 4), np.float32)
    vector_pass[:H // 2] = value
    forward, backward = quietly(lambda: motion_pair(vector_pass, vector_pass))
    assert np.isfinite(forward).all() and np.isfinite(backward).all()
    frame, next_frame = translated_pair(smooth_scene, (0.0, 0.0))
    visible = quietly(lambda: visible_in_both(forward, backward))
    still = quietly(lambda: still_pixels(forward, backward))
    assert not visible[:H // 2].any() and not still[:H // 2].any()
    assert visible[H // 2 + 1:].all() and still[H // 2:].all()
    assert quietly(lambda: warping_error(frame, next_frame, forward, visible)) == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("value", ABSURD)
def test_visibility_of_a_motion_out_of_reach_given_directly_is_quiet(value):
    """The visibility functions take any motion: one out of reach is not visible, without a warning."""
    forward, backward = uniform((1.0, 0.0)), uniform((-1.0, 0.0))
    forward[:, :W // 2] = value
    backward[:H // 2] = value
    visible = quietly(lambda: visible_in_both(forward, backward))
    assert not visible[:, :W // 2].any()
    assert not quietly(lambda: round_trip_consistent(uniform((1.0, 0.0)), backward))[:H // 2].any()
    assert quietly(lambda: motion_boundary(forward))[:, W // 2 - 1:W // 2 + 1].all()
    assert not quietly(lambda: still_pixels(forward, backward))[:, :W // 2].any()


def test_bilinear_over_many_blocks_of_positions_is_exact_where_the_scene_is_bilinear(monkeypatch):
    monkeypatch.setattr(warp, "BLOCK_POSITIONS", 1000)
    y, x = np.mgrid[0:H, 0:W].astype(np.float64)
    rng = np.random.default_rng(4)
    places = np.stack([rng.uniform(0, W - 1, (3, 2500)), rng.uniform(0, H - 1, (3, 2500))], axis=-1)
    colour = np.stack([bilinear_scene(x, y), 1 - bilinear_scene(x, y)], axis=-1)
    got = bilinear(colour, places)
    assert got.shape == (3, 2500, 2) and got.dtype == np.float32
    want = bilinear_scene(places[..., 0], places[..., 1])
    assert np.abs(got[..., 0] - want).max() < 2e-6 and np.abs(got[..., 1] - (1 - want)).max() < 2e-6
    monkeypatch.setattr(warp, "BLOCK_POSITIONS", 1 << 20)
    assert np.array_equal(bilinear(colour, places), got)        # one block: the same bytes
