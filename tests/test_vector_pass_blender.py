"""Blender's Vector pass conventions, checked on a render of a known motion (core/motion/vector_pass.py).

tests/blender/vector_pass_render.py renders, in a subprocess with the bpy
module (``bpy`` can be imported once per process; BLENDER_USER_RESOURCES in a
temporary folder), three 48 x 32 px frames of an orthographic camera that
moves exactly RIGHT_PX pixels to the right and DOWN_PX pixels down the image
every frame over a textured plane. The plane then moves by (-RIGHT_PX,
-DOWN_PX) px in image axes (x right, y down) from one frame to the next, and
by the opposite back. The frames' Vector and Combined parts are read as
the painter reads them (``core.files``).
"""

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from core.files.frames import read_vector_pass
from core.files.reading import read_image
from core.motion import backward_motion, forward_motion, motion_pair, visible_in_both, warping_error

REPO = Path(__file__).resolve().parent.parent
SCRIPT = REPO / "tests" / "blender" / "vector_pass_render.py"
WIDTH, HEIGHT, FRAMES = 48, 32, 3
RIGHT_PX, DOWN_PX = 2, 1  # the camera's step every frame, px
FORWARD = (-RIGHT_PX, -DOWN_PX)  # the plane's motion from frame t to t+1 in image axes, px


@pytest.fixture(scope="module")
def frames(tmp_path_factory):
    """[(vector pass (H, W, 4), sRGB colour (H, W, 3) in [0, 1])] of frames 1 to FRAMES."""
    if importlib.util.find_spec("bpy") is None:
        pytest.skip("the bpy module (Blender as a Python module) is not installed")
    work = tmp_path_factory.mktemp("vector_pass")
    out = work / "out"
    run = subprocess.run([sys.executable, str(SCRIPT), str(out), *map(str, (WIDTH, HEIGHT, FRAMES, RIGHT_PX, DOWN_PX))],
                         capture_output=True, text=True, timeout=600, cwd=work,
                         env=dict(os.environ, BLENDER_USER_RESOURCES=str(work / "blender_user")))
    paths = [out / f"frame_{n:04d}.exr" for n in range(1, FRAMES + 1)]
    assert run.returncode == 0 and all(p.is_file() for p in paths), run.stdout[-3000:] + run.stderr[-3000:]
    return [(read_vector_pass(p), read_image(p)) for p in paths]


@pytest.mark.blender
def test_the_vector_pass_gives_the_known_motion_in_image_axes(frames):
    for vector, _ in frames:
        assert vector.shape == (HEIGHT, WIDTH, 4)
        forward, backward = forward_motion(vector), backward_motion(vector)
        assert np.allclose(forward, FORWARD, atol=1e-3), (forward.min(axis=(0, 1)), forward.max(axis=(0, 1)))
        assert np.allclose(backward, np.negative(FORWARD), atol=1e-3)


@pytest.mark.blender
def test_pixels_visible_in_both_are_those_that_stay_in_the_frame(frames):
    forward, backward = motion_pair(frames[0][0], frames[1][0])
    visible = visible_in_both(forward, backward)
    # x - RIGHT_PX and y - DOWN_PX must lie in the frame: the first RIGHT_PX columns and DOWN_PX rows leave it.
    expected = np.zeros((HEIGHT, WIDTH), dtype=bool)
    expected[DOWN_PX:, RIGHT_PX:] = True
    assert np.array_equal(visible, expected)


@pytest.mark.blender
def test_warping_the_next_frame_back_matches_the_frame(frames):
    for (vector_t, colour_t), (vector_next, colour_next) in zip(frames[:-1], frames[1:], strict=True):
        forward, backward = motion_pair(vector_t, vector_next)
        visible = visible_in_both(forward, backward)
        right = warping_error(colour_t, colour_next, forward, visible)
        opposite = warping_error(colour_t, colour_next, -forward, visible)
        swapped = warping_error(colour_t, colour_next, forward[..., ::-1], visible)
        still = warping_error(colour_t, colour_next, np.zeros_like(forward), visible)
        assert right < 2e-5, right
        assert min(opposite, swapped, still) > 50 * right, (right, opposite, swapped, still)
