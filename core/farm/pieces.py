"""A sequence frame's pieces as Dask tasks run them: each reads the frame files it needs from their paths.

The pieces that need a picture read it themselves
(``core.sequence.tasks.read_frame``), so only what is made (an analysis, a
motion, the strokes, the frame shown) travels between workers, and no
piece waits on the worker that read a frame. A frame is read five times
(its preparing, the motion to it and from it, its writing and the next
frame's): at 1920x1080 a PNG frame reads in about 35 ms, a multilayer EXR
with its Vector pass in 0.2 to 0.4 s, against 25 MB (58 MB with the Vector
pass) to send. None of these reads is on the strokes' life chain.
"""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple, Optional, Union

from ..params import Params
from ..progress import Stage
from ..sequence.frame_step import (
    CanvasRows,
    Carried,
    FrameAnalysis,
    FrameMotion,
    PaintedFrame,
    born_frame,
    carried_frame,
    unchanged,
)
from ..sequence.tasks import (
    FrameInput,
    ShownFrame,
    WrittenFrame,
    analysed_frame,
    frame_motion,
    life,
    read_frame,
    written_frame,
)

WORKER_STAGE = Stage(None, None)


class Prepared(NamedTuple):
    """A frame read, and its analysis (None for the first frame, which the still painter analyses itself)."""

    frame: FrameInput
    analysed: Optional[FrameAnalysis]


def prepared(path: Path, params: Params, vector_pass: bool, analyse: bool) -> Prepared:
    """Frame file ``path`` read (with its Vector pass when ``vector_pass``) and, when ``analyse``, analysed."""
    frame = read_frame(path, params, vector_pass)
    return Prepared(frame, analysed_frame(frame, params) if analyse else None)


def motion_between(before: Path, after: Path, params: Params, vector_pass: bool) -> FrameMotion:
    """The motion from frame file ``before`` to frame file ``after`` (``tasks.frame_motion``)."""
    return frame_motion(read_frame(before, params, vector_pass), read_frame(after, params, vector_pass))


def carried(previous: Optional[PaintedFrame], index: int, frame: Prepared, motion: Optional[FrameMotion],
            params: Params, fade_frames: int) -> Union[PaintedFrame, Carried]:
    """The first step of frame ``index``'s life: the frame's strokes when that is all (the first frame painted
    as a still, a still stretch's frame: ``tasks.life``), else the frame before's strokes carried
    (``frame_step.carried_frame``), whose judging canvas ``settled_rows`` lays next."""
    if previous is None or unchanged(previous, motion):
        return life(previous, index, frame.frame, motion, params, fade_frames, WORKER_STAGE)
    return carried_frame(previous, frame.frame.image, motion, params, frame.analysed)


def born(previous: PaintedFrame, index: int, frame: Prepared, motion: FrameMotion, params: Params,
         carried_strokes: Carried, *judging_rows: CanvasRows) -> PaintedFrame:
    """The last step of frame ``index``'s life: births on the judging canvas (``frame_step.born_frame``), with
    the analysis's seconds."""
    painted = born_frame(previous, index, frame.frame.image, motion, params, WORKER_STAGE, frame.analysed,
                         carried_strokes, judging_rows)
    return painted._replace(seconds={"analysis": frame.analysed.seconds, **painted.seconds})


def written(folder: Path, number: int, painted: PaintedFrame, shown: ShownFrame, path: Path,
            before_shown: Optional[ShownFrame], before: Optional[Path], motion: Optional[FrameMotion],
            params: Params, normal_map: bool) -> WrittenFrame:
    """Frame ``number``'s maps and measures (``tasks.written_frame``), its frame files read from their paths."""
    frame = read_frame(path, params, False)
    before_frame = read_frame(before, params, False) if before is not None else None
    return written_frame(folder, number, painted, shown, frame, before_shown, before_frame, motion, params,
                         normal_map)
