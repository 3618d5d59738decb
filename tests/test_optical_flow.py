"""core.motion.optical_flow: known motions of synthetic frames, the form of the result, the same bytes every run."""

import numpy as np
import pytest
from threadpoolctl import threadpool_limits

from core.motion.optical_flow import optical_flow


def waves(shape, shift=(0.0, 0.0), seed=0):
    """(H, W, 3) float32 texture in [0.1, 0.9]: sums of plane waves, read at x − shift (so it moves by ``shift``).

    Waves shift exactly by any fraction of a pixel, so the true motion of the
    texture is ``shift`` (x, y) everywhere. Their periods are 5 to 40 px.
    """
    rng = np.random.default_rng(seed)
    rows, columns = np.indices(shape, dtype=np.float64)
    x, y = columns - shift[0], rows - shift[1]
    image = np.zeros(shape + (3,))
    for channel in range(3):
        for _ in range(6):
            angle, phase = rng.uniform(0.0, 2 * np.pi, 2)
            frequency = rng.uniform(1 / 40, 1 / 5)
            image[..., channel] += np.cos(2 * np.pi * frequency * (np.cos(angle) * x + np.sin(angle) * y) + phase)
    return (0.5 + 0.4 * image / 6).astype(np.float32)


def end_point_error(flow, motion):
    """(H, W) distance in pixels between ``flow`` (H, W, 2) and the motion (x, y)."""
    return np.hypot(flow[..., 0] - motion[0], flow[..., 1] - motion[1])


@pytest.mark.parametrize("motion", [(1.3, -0.7), (-5.6, 3.2)])
def test_a_translated_texture_moves_by_the_shift(motion):
    # An odd size, so that the pyramid's levels round up; 5.6 px needs the coarser levels.
    first, second = waves((75, 101)), waves((75, 101), shift=motion)
    flow = optical_flow(first, second)
    assert flow.shape == (75, 101, 2) and flow.dtype == np.float32
    interior = end_point_error(flow, motion)[8:-8, 8:-8]
    assert interior.mean() < 0.05
    assert interior.max() < 0.3


def moving_square(motion=(4, -3), size=(96, 128), box=(28, 68, 40, 80)):
    """Two frames: a still textured background, and a square of another texture moving by ``motion`` (whole px).

    Returns (first, second, square) where ``square`` is the (H, W) bool mask
    of the square in the first frame.
    """
    top, bottom, left, right = box
    dx, dy = motion
    background = waves(size, seed=1)
    inside = np.zeros(size, bool)
    inside[top:bottom, left:right] = True
    moved = np.roll(inside, (dy, dx), axis=(0, 1))
    first = np.where(inside[..., None], waves(size, seed=2), background)
    second = np.where(moved[..., None], waves(size, shift=motion, seed=2), background)
    return first, second, inside


def test_a_moving_square_and_its_still_background():
    motion = (4, -3)
    first, second, square = moving_square(motion)
    flow = optical_flow(first, second)
    # Away from the square's edges in both frames (where pixels are hidden or revealed), by 6 px.
    square_inside = np.zeros_like(square)
    square_inside[28 + 6:68 - 6, 40 + 6:80 - 6] = True
    near_edges = np.zeros_like(square)
    near_edges[28 - 3 - 6:68 + 6, 40 - 6:80 + 4 + 6] = True
    still = ~near_edges
    still[:6], still[-6:], still[:, :6], still[:, -6:] = False, False, False, False
    assert end_point_error(flow, motion)[square_inside].mean() < 0.1
    assert end_point_error(flow, (0.0, 0.0))[still].mean() < 0.1


def test_the_same_bytes_on_every_run_whatever_the_threads():
    first, second, _ = moving_square()
    once = optical_flow(first, second)
    with threadpool_limits(1):
        again = optical_flow(first, second)
    assert once.tobytes() == again.tobytes()


def test_frames_of_different_sizes_or_too_small_are_refused():
    with pytest.raises(ValueError, match="one size"):
        optical_flow(waves((20, 30)), waves((20, 31)))
    with pytest.raises(ValueError, match="2 x 2"):
        optical_flow(waves((1, 30)), waves((1, 30)))
