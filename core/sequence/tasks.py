"""The pieces of a sequence's work on one frame, each a function of its arguments alone (ALGORITHM §9).

Frame t's work falls into pieces with fixed inputs, so the same functions
run one after another in one process (``shot``) or as tasks on any machine
of a cluster (``core.farm``), with the same bytes out:

- ``read_frame`` (frame t's file) and ``analysed_frame`` (frame t alone);
- ``frame_motion`` (frames t-1 and t);
- ``life`` (frame t-1's strokes, frame t and the motion): the only piece
  that needs the piece before it of the same kind, so the strokes' life
  runs in frame order (on a cluster in three steps, ``frame_step``'s
  ``carried_frame``, ``settled_rows`` in bands side by side, and
  ``born_frame``);
- ``shown_frame`` (frame t's strokes laid) and ``written_frame`` (the maps
  and the measures, into a staging folder of their own).

The pieces pass plain NumPy arrays and named tuples, which pickle, so a
piece's result can travel to another machine.
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
from ..files.staging import new_staging
from ..measures.metrics import psnr
from ..motion import comes_back, motion_boundary, motion_pair, optical_flow, still_pixels, stillness, warping_error
from ..motion.optical_flow import SEQUENCE_MEGAPIXELS
from ..params import Params
from ..progress import Stage
from ..strokes.canvas import Canvas
from .frame_step import (
    FrameAnalysis,
    FrameMotion,
    PaintedFrame,
    analyse_frame,
    first_frame,
    next_frame,
    shown_canvas,
    unchanged,
)


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


def frame_names(number: int, normal_map: bool) -> list:
    """The files of frame ``number``: painting_0016.png, color_0016.exr, height, opacity, orientation (and
    normal_0016.exr), as Blender numbers an image sequence (at least 4 digits)."""
    suffix = frame_suffix(number)
    names = [f"painting{suffix}.png", f"color{suffix}.exr", f"height{suffix}.exr", f"opacity{suffix}.exr",
             f"orientation{suffix}.exr"]
    return names + ([f"normal{suffix}.exr"] if normal_map else [])


def frame_suffix(number: int) -> str:
    """"_0016" for frame 16: the frame number zero-padded to 4 digits (more when it needs them)."""
    return f"_{number:04d}"


def read_frame(path: Path, params: Params, vector_pass: bool) -> FrameInput:
    """Frame file ``path`` read for painting, with its Vector pass when ``vector_pass``."""
    clock = time.perf_counter()
    image = reading.read_image(path, params.max_megapixels, params.canvas_colour)
    vectors = read_vector_pass(path) if vector_pass else None
    return FrameInput(image, vectors, time.perf_counter() - clock)


def analysed_frame(frame: FrameInput, params: Params) -> FrameAnalysis:
    """``frame_step.analyse_frame`` of a frame as read."""
    return analyse_frame(frame.image, params)


def frame_motion(before: FrameInput, after: FrameInput) -> FrameMotion:
    """The motion between two frames: from their Vector passes when they have them, else optical flow both ways
    (none between equal frames); with which pixels of each are visible in both."""
    clock = time.perf_counter()
    same_picture = np.array_equal(before.image, after.image)
    if before.vectors is not None:
        forward, backward = motion_pair(before.vectors, after.vectors)
    elif same_picture:
        forward = backward = np.zeros(before.image.shape[:2] + (2,), np.float32)
    else:
        forward = optical_flow(before.image, after.image, SEQUENCE_MEGAPIXELS)
        backward = optical_flow(after.image, before.image, SEQUENCE_MEGAPIXELS)
    kept = comes_back(forward, backward)
    return FrameMotion(forward, backward, kept & ~motion_boundary(forward), kept, comes_back(backward, forward),
                       same_picture, time.perf_counter() - clock)


def life(previous: Optional[PaintedFrame], index: int, frame: FrameInput, motion: Optional[FrameMotion],
         params: Params, fade_frames: int, stage: Stage, analysed: Optional[FrameAnalysis] = None) -> PaintedFrame:
    """Frame ``index``'s strokes: frame 0 painted as a still (``previous`` and ``motion`` None), a still stretch's
    frame as the frame before, any other frame by ``next_frame`` (with ``analysed``, the frame's analysis when made
    elsewhere)."""
    if previous is None:
        return first_frame(frame.image, params, fade_frames, stage)
    if unchanged(previous, motion):
        return previous._replace(born=0, died=0, seconds={})
    painted = next_frame(previous, index, frame.image, motion, params, stage, analysed)
    return painted if analysed is None else painted._replace(seconds={"analysis": analysed.seconds,
                                                                      **painted.seconds})


class ShownFrame(NamedTuple):
    """A frame as shown and the seconds laying it took."""

    canvas: Canvas
    seconds: float


def shown_frame(painted: PaintedFrame, params: Params, shape: tuple) -> ShownFrame:
    """The (H, W) ``shape`` frame as shown (``frame_step.shown_canvas``)."""
    clock = time.perf_counter()
    canvas = shown_canvas(painted, params, shape)
    return ShownFrame(canvas, time.perf_counter() - clock)


def written_frame(folder: Path, number: int, painted: PaintedFrame, shown: ShownFrame, frame: FrameInput,
                  before_shown: Optional[ShownFrame], before: Optional[FrameInput], motion: Optional[FrameMotion],
                  params: Params, normal_map: bool) -> WrittenFrame:
    """Frame ``number``'s maps written into a new staging folder of the output ``folder``, with its report entry:
    PSNR against the frame, the height's range and (after the first frame) the pair's measures against the frame
    before (``before_shown``, ``before``, ``motion``). A failure removes the staging folder."""
    seconds = {"reading": frame.seconds, "laying": shown.seconds, **({"motion": motion.seconds} if motion else {})}
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
    attributes = dict(map_attributes(params), **{"paint_relief:frame": str(number)})
    names = frame_names(number, normal_map)
    staging = new_staging(Path(folder))
    try:
        run_all(map_tasks(staging, frame_suffix(number), shown.colour, shown.height, shown.opacity,
                          painted.orientation, attributes))
        files = file_digests(staging, names[:5])
        if normal_map:
            write_normal_map(staging / names[5], shown.height, attributes, files[names[2]]["sha256"])
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    seconds["writing"] = time.perf_counter() - clock
    return WrittenFrame(staging, files, entry, seconds)


def pair_measures(image: np.ndarray, next_image: np.ndarray, shown: Canvas, next_shown: Canvas,
                  motion: FrameMotion) -> dict:
    """The steadiness of a pair of frames (ALGORITHM §9, "Measures"), with the painter's own motion: the warping
    error of the footage, of the painting's colour and of its raw height (normalised over the sequence by
    ``shot.sequence_figures``), and the mean change where the footage stands still, of the footage and the
    painting."""
    still = still_pixels(motion.forward, motion.backward) & motion.visible
    return {"warping_error": {
        "footage": warping_error(image, next_image, motion.forward, motion.visible),
        "painting": warping_error(shown.colour, next_shown.colour, motion.forward, motion.visible),
        "height_raw": warping_error(shown.height, next_shown.height, motion.forward, motion.visible)},
        "still_pixels": int(np.count_nonzero(still)),
        "stillness": {"footage": stillness(image, next_image, still),
                      "painting": stillness(shown.colour, next_shown.colour, still)}}
