"""The work on one frame of a shot apart from its strokes' life: reading it, the motion to it, the frame shown
and its maps written (ALGORITHM §9).

Each function is of its arguments alone and passes plain NumPy arrays and
named tuples, which pickle, so the pieces of a frame's work
(``core.sequence.pieces``) run them in one process or on any machine of a
cluster with the same bytes out.
"""

from __future__ import annotations

import shutil
import time
from pathlib import Path
from typing import Dict, NamedTuple, Optional

import numpy as np

from ..files import reading
from ..files.export import file_digests, map_attributes, map_tasks, run_all, write_normal_map
from ..files.frames import read_vector_pass
from ..files.shot_files import FRAME_MAPS, frame_file_names, frame_suffix
from ..files.staging import new_staging
from ..measures.metrics import psnr
from ..motion import comes_back, motion_boundary, still_pixels, stillness, warping_error
from ..motion.source import VECTOR_PASS_MOTION, two_way_motion
from ..strokes.canvas import Canvas
from .frame_step import FrameMotion, PaintedFrame, shown_canvas
from .shot_settings import ShotSettings


class FrameInput(NamedTuple):
    """A frame as read: its picture and, when the frames carry one, its Vector pass."""

    image: np.ndarray                 # float32 (H, W, 3) sRGB [0, 1]
    vectors: Optional[np.ndarray]     # float32 (H, W, 4) px, Blender's Vector pass, or None
    seconds: float                    # wall-clock seconds of reading it


class WrittenFrame(NamedTuple):
    """A frame's maps written into a staging folder of the output folder, not yet committed."""

    staging: Path                     # the staging folder (``staging.new_staging``) holding the maps
    files: Dict[str, dict]            # {file name: ``file_digest``} of the maps
    entry: dict                       # the frame's report entry: PSNR, height range and the pair's measures
    seconds: Dict[str, float]         # wall-clock seconds of laying, measuring and writing


def read_frame(path: Path, shot: ShotSettings, vectors: bool = True) -> FrameInput:
    """Frame file ``path`` read for painting, with its Vector pass when the shot's motion comes from it and
    ``vectors``."""
    clock = time.perf_counter()
    image = reading.read_image(path, shot.params.max_megapixels, shot.params.canvas_colour)
    vectors = read_vector_pass(path) if shot.vector_pass and vectors else None
    return FrameInput(image, vectors, time.perf_counter() - clock)


def frame_motion(before: FrameInput, after: FrameInput, source: str) -> FrameMotion:
    """The motion between two frames from the shot's motion ``source`` (``core.motion.source``; none between
    equal pictures by optical flow), with which pixels of each are visible in both."""
    clock = time.perf_counter()
    same_picture = np.array_equal(before.image, after.image)
    if source == VECTOR_PASS_MOTION:
        forward, backward = two_way_motion(before.vectors, after.vectors, source)
    elif same_picture:
        forward = backward = np.zeros(before.image.shape[:2] + (2,), np.float32)
    else:
        forward, backward = two_way_motion(before.image, after.image, source)
    kept = comes_back(forward, backward)
    return FrameMotion(forward, backward, kept & ~motion_boundary(forward), kept, comes_back(backward, forward),
                       same_picture, time.perf_counter() - clock)


class ShownFrame(NamedTuple):
    """A frame as shown and the seconds laying it took."""

    canvas: Canvas
    seconds: float


def shown_frame(painted: PaintedFrame, shot: ShotSettings) -> ShownFrame:
    """The frame as shown (``frame_step.shown_canvas``) at the shot's (H, W) shape."""
    clock = time.perf_counter()
    canvas = shown_canvas(painted, shot.params, shot.shape)
    return ShownFrame(canvas, time.perf_counter() - clock)


def written_frame(folder: Path, number: int, shot: ShotSettings, painted: PaintedFrame, shown: ShownFrame,
                  frame: FrameInput, before_shown: Optional[ShownFrame], before: Optional[FrameInput],
                  motion: Optional[FrameMotion]) -> WrittenFrame:
    """Frame ``number``'s maps written into a new staging folder of the output ``folder``, with its report entry:
    PSNR against the frame, the height's range and (after the first frame) the pair's measures against the frame
    before (``before_shown``, ``before``, ``motion``). A failure removes the staging folder."""
    seconds = {"reading": frame.seconds, "laying": shown.seconds}
    clock = time.perf_counter()
    if before is not None:
        measures = pair_measures(before.image, frame.image, before_shown.canvas, shown.canvas, motion)
        seconds["measures"] = time.perf_counter() - clock
    else:
        measures = {}
    clock = time.perf_counter()
    shown = shown.canvas
    entry = {"psnr": round(psnr(shown.colour, frame.image), 4),
             "height_range": [float(np.min(shown.height)), float(np.max(shown.height))], **measures}
    attributes = dict(map_attributes(shot.params), **{"paint_relief:frame": str(number)})
    names = frame_file_names(number, shot.normal_map)
    staging = new_staging(Path(folder))
    try:
        run_all(map_tasks(staging, frame_suffix(number), shown.colour, shown.height, shown.opacity,
                          painted.orientation, attributes))
        files = file_digests(staging, names[:len(FRAME_MAPS)])
        if shot.normal_map:
            write_normal_map(staging / names[-1], shown.height, attributes, files[names[2]]["sha256"])
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    seconds["writing"] = time.perf_counter() - clock
    return WrittenFrame(staging, files, entry, seconds)


def pair_measures(image: np.ndarray, next_image: np.ndarray, shown: Canvas, next_shown: Canvas,
                  motion: FrameMotion) -> dict:
    """The steadiness of a pair of frames (ALGORITHM §9, "Measures"), with the painter's own motion: the warping
    error of the footage, of the painting's colour and of its raw height (normalised over the sequence by
    ``shot_statistics.sequence_statistics``), and the mean change where the footage stands still, of the footage and
    the painting."""
    still = still_pixels(motion.forward, motion.backward) & motion.visible
    return {"warping_error": {
        "footage": warping_error(image, next_image, motion.forward, motion.visible),
        "painting": warping_error(shown.colour, next_shown.colour, motion.forward, motion.visible),
        "height_raw": warping_error(shown.height, next_shown.height, motion.forward, motion.visible)},
        "still_pixels": int(np.count_nonzero(still)),
        "stillness": {"footage": stillness(image, next_image, still),
                      "painting": stillness(shown.colour, next_shown.colour, still)}}
