"""What painting a shot is for (ALGORITHM §9): its frames flicker less than the same frames painted one by one.

The shot is a window of the sample photograph moved by a whole number of
pixels a frame, so its motion is known exactly, with no resampling: pixel x
of frame t is pixel x + STEP of frame t+1. The shot is painted as a sequence
(the painter finds the motion itself, by optical flow) and each frame alone
as a still with the same seed; each is then measured with the known motion,
not with anything the painter reports: the warping error (ALGORITHM §9
"Measures"), the mean over pixels visible in both frames and channels of
(V_t(x) - V_{t+1}(x + w_f(x)))², averaged over the shot's pairs of frames.
"""

from pathlib import Path

import numpy as np

import core
from core.files.reading import read_image
from core.files.writing import write_png
from core.motion import visible_in_both, warping_error
from core.params import Params, SequenceSettings

PHOTO = Path(__file__).resolve().parents[1] / "sample_scenes" / "chelsea.png"
HEIGHT, WIDTH, FRAMES = 64, 96, 3
STEP = (2, 1)
"""(x, y) px the content moves from one frame to the next."""
CORNER = (100, 50)
"""(x, y) of the first frame's window in the photograph."""


def moving_window(folder: Path) -> list:
    """FRAMES PNG frames frame_0001.png... in ``folder``: windows of the photograph whose content moves STEP px a
    frame (the window moves by -STEP); returns the frames as read back."""
    folder.mkdir(parents=True)
    photo = read_image(PHOTO)
    for t in range(FRAMES):
        x, y = CORNER[0] - STEP[0] * t, CORNER[1] - STEP[1] * t
        write_png(folder / f"frame_{t + 1:04d}.png", photo[y:y + HEIGHT, x:x + WIDTH])
    return [read_image(folder / f"frame_{t + 1:04d}.png") for t in range(FRAMES)]


def mean_warping_error(frames: list) -> float:
    """The mean over consecutive pairs of ``frames`` of their warping error with the known motion."""
    forward = np.broadcast_to(np.float32(STEP), (HEIGHT, WIDTH, 2)).copy()
    visible = visible_in_both(forward, -forward)
    return float(np.mean([warping_error(a, b, forward, visible) for a, b in zip(frames[:-1], frames[1:], strict=True)]))


def test_a_painted_shot_flickers_less_than_its_frames_painted_as_stills(tmp_path):
    frames = moving_window(tmp_path / "frames")
    params = Params(seed=0)
    # The motion is the one the frames were made with: every visible pixel lands on its own value.
    assert mean_warping_error(frames) == 0.0
    core.paint_sequence_files([str(tmp_path / "frames" / "frame_####.png")], tmp_path / "shot", params,
                              SequenceSettings())
    shot = [read_image(tmp_path / "shot" / f"painting_{t + 1:04d}.png") for t in range(FRAMES)]
    stills = []
    for t in range(FRAMES):
        core.paint_file(tmp_path / "frames" / f"frame_{t + 1:04d}.png", tmp_path / f"still_{t + 1}", params)
        stills.append(read_image(tmp_path / f"still_{t + 1}" / "painting.png"))
    shot_error, stills_error = mean_warping_error(shot), mean_warping_error(stills)
    assert 0 < shot_error < 0.5 * stills_error, (shot_error, stills_error)
