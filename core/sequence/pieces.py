"""The pieces of a shot frame's work, each declared once with the pieces it needs (ALGORITHM §9).

A piece is named by a ``PieceKey`` (its kind, the frame's 0-based index t,
a band of rows for the judging canvas) and made by a function of the
results of the pieces it needs, in the order ``Piece.needs`` lists them:

========  =====================================================  ==========================================
kind      what it makes                                          needs
========  =====================================================  ==========================================
PREPARE   frame t read, and analysed when the pieces analyse     nothing
          ahead (``Prepared``)
MOTION    the motion from frame t-1 to frame t (t >= 1)          PREPARE t-1, PREPARE t
CARRY     the life's first step (``LifeStep``): the frame's      PREPARE t; after the first frame
          strokes when that is all (the first frame, painted       BIRTH t-1 and MOTION t
          as a still; an unchanged frame), else frame t-1's
          strokes carried
JUDGE     band b of frame t's judging canvas: the carried        CARRY t
          strokes that reach its rows laid (``CanvasRows``)
BIRTH     frame t's strokes (``PaintedFrame``): births on the    CARRY t when it completed the life; else
          judging canvas, or the carry's when it completed       PREPARE t, BIRTH t-1, MOTION t, CARRY t
          the life                                               and every JUDGE band of frame t
SHOWN     frame t as shown (``ShownFrame``)                      BIRTH t
WRITE     frame t's maps (and measures, when the shot            PREPARE t, BIRTH t, SHOWN t; when measured,
          measures) in a staging folder (``WrittenFrame``)       after the first frame PREPARE t-1, SHOWN
                                                                 t-1, MOTION t
========  =====================================================  ==========================================

``piece_needs`` declares what each piece needs, ``ShotPieces.piece`` how it is made. How many JUDGE bands frame t has
is known once its CARRY is made (``judging_bands``: none when the life is
complete). The one-process loop (``shot.Run.paint_from``) makes the pieces
in frame order, the farm (``core.farm.sequence``) submits them to Dask, the
bench (``bench/farm.py``) times each; the bytes are the same.

Only PREPARE reads a frame; a piece reads ``.frame`` of a PREPARE result,
so a runner may hand it any value with a ``frame`` (the farm reads the
frame again on the worker: ``core.farm.frame_file``).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Callable, List, NamedTuple, Optional, Sequence, Set, Tuple

from ..progress import Stage
from ..strokes.stroke_list import laying_bands
from .frame_step import (
    CanvasRows,
    CarriedFrame,
    FrameAnalysis,
    FrameMotion,
    PaintedFrame,
    analyse_frame,
    born_frame,
    carried_frame,
    first_frame,
    settled_rows,
    unchanged,
)
from .frame_work import FrameInput, ShownFrame, WrittenFrame, frame_motion, read_frame, shown_frame, written_frame
from .shot_settings import ShotSettings

WORKER_STAGE = Stage(None, None)
"""The stage of a piece that reports no progress and is not cancelled (a piece on a Dask worker)."""

Rows = Tuple[int, int]
"""(first, stop): a band of a frame's rows, stop excluded."""


class PieceKind(enum.Enum):
    """The kinds of piece of a frame's work (the module docstring's table)."""

    PREPARE = "prepare"
    MOTION = "motion"
    CARRY = "carry"
    JUDGE = "judge"
    BIRTH = "birth"
    SHOWN = "shown"
    WRITE = "write"


@dataclass(frozen=True)
class PieceKey:
    """A piece: its ``kind``, the 0-based ``index`` of its frame and, for a JUDGE piece, its ``band`` (0-based)."""

    kind: PieceKind
    index: int
    band: int = 0

    def __str__(self) -> str:
        """"judge1-3", "carry-3": the kind (and band) and the frame index."""
        band = str(self.band) if self.kind is PieceKind.JUDGE else ""
        return f"{self.kind.value}{band}-{self.index}"


@dataclass(frozen=True)
class Piece:
    """A piece declared: ``make(*results of needs)`` makes it (with ``stage=`` a ``Stage`` when ``staged``)."""

    key: PieceKey
    needs: Tuple[PieceKey, ...]
    make: Callable[..., object]
    staged: bool = False


class Prepared(NamedTuple):
    """A frame read, and its analysis (None for the first frame, which the still painter analyses itself, and when
    the pieces do not analyse ahead)."""

    frame: FrameInput
    analysed: Optional[FrameAnalysis]


class LifeStep(NamedTuple):
    """The first step of a frame's life: ``lived``, the frame's strokes when the life is complete at this step (the
    first frame, an unchanged frame), else ``carried``, the frame before's strokes carried, with ``analysed``, the
    frame's analysis when this step made it."""

    lived: Optional[PaintedFrame]
    carried: Optional[CarriedFrame]
    analysed: Optional[FrameAnalysis] = None

    @property
    def complete(self) -> bool:
        """Whether the frame's life ends at this step: no judging canvas and no births."""
        return self.lived is not None


def prepare(path: Path, shot: ShotSettings, analyse: bool) -> Prepared:
    """Frame file ``path`` read (``frame_work.read_frame``) and, when ``analyse``, analysed."""
    frame = read_frame(path, shot)
    return Prepared(frame, analyse_frame(frame.image, shot.params) if analyse else None)


def motion_between(shot: ShotSettings, before, after) -> FrameMotion:
    """The motion from the frame of ``before`` to that of ``after`` (each a ``Prepared`` or any value with a
    ``frame``), from the shot's motion source."""
    return frame_motion(before.frame, after.frame, shot.motion)


def carry_step(shot: ShotSettings, index: int, prepared, previous: Optional[PaintedFrame] = None,
               motion: Optional[FrameMotion] = None, stage: Stage = WORKER_STAGE) -> LifeStep:
    """Frame ``index``'s life's first step: the first frame painted as a still; an unchanged frame
    (``frame_step.unchanged``) as the frame before, none born and none dead; any other frame's ``previous``
    strokes carried by the ``motion`` (``frame_step.carried_frame``), analysed here when ``prepared`` holds no
    analysis."""
    image = prepared.frame.image
    if previous is None:
        return LifeStep(first_frame(image, shot.params, shot.fade_frames, stage), None)
    if unchanged(previous, motion):
        return LifeStep(previous._replace(born=0, died=0, seconds={"motion": motion.seconds}), None)
    made_here = None if prepared.analysed is not None else analyse_frame(image, shot.params, stage.cancel)
    analysed = prepared.analysed or made_here
    return LifeStep(None, carried_frame(previous, image, motion, shot.params, analysed), made_here)


def judged_rows(shot: ShotSettings, rows: Rows, step: LifeStep) -> CanvasRows:
    """Rows ``rows`` of the judging canvas of a carried ``step`` (``frame_step.settled_rows``)."""
    return settled_rows(step.carried, shot.params, shot.shape, rows)


def born(shot: ShotSettings, index: int, prepared, previous: PaintedFrame, motion: FrameMotion, step: LifeStep,
         *judging_rows: CanvasRows, stage: Stage = WORKER_STAGE) -> PaintedFrame:
    """Frame ``index``'s strokes: births on the judging canvas of ``judging_rows`` (``frame_step.born_frame``),
    the seconds of the frame's analysis and of its motion first in its seconds."""
    analysed = prepared.analysed or step.analysed
    painted = born_frame(previous, index, prepared.frame.image, motion, shot.params, stage, analysed, step.carried,
                         judging_rows)
    return painted._replace(seconds={"analysis": analysed.seconds, "motion": motion.seconds, **painted.seconds})


def completed_life(step: LifeStep) -> PaintedFrame:
    """The frame's strokes of a ``step`` that completed the life."""
    return step.lived


def shown(shot: ShotSettings, painted: PaintedFrame) -> ShownFrame:
    """The frame of strokes ``painted`` as shown (``frame_work.shown_frame``)."""
    return shown_frame(painted, shot)


def write(folder: Path, number: int, shot: ShotSettings, prepared, painted: PaintedFrame, shown_now: ShownFrame,
          before=None, shown_before: Optional[ShownFrame] = None, motion: Optional[FrameMotion] = None
          ) -> WrittenFrame:
    """Frame ``number``'s maps and measures into a new staging folder of ``folder`` (``frame_work.written_frame``);
    ``before``, ``shown_before`` and ``motion``: the frame before's, None for the first frame."""
    return written_frame(folder, number, shot, painted, shown_now, prepared.frame, shown_before,
                         before.frame if before is not None else None, motion)


def row_bands(height: int, parts: int) -> List[Rows]:
    """[(first, stop), ...]: ``parts`` (at least 1) consecutive runs of about equal numbers of a frame's ``height``
    rows."""
    parts = max(1, min(parts, height))
    cuts = [height * k // parts for k in range(parts + 1)]
    return list(zip(cuts[:-1], cuts[1:], strict=True))


def judging_bands(step: LifeStep, height: int, parts: int) -> List[Rows]:
    """The bands of rows a frame's JUDGE pieces lay after its carry ``step``: none when the life is complete, else
    at most ``parts`` bands about equal in the work of laying the carried strokes that reach each
    (``stroke_list.laying_bands``); one band of every row, without looking at the strokes, when ``parts`` is 1."""
    if step.complete:
        return []
    if parts <= 1:
        return row_bands(height, 1)
    return laying_bands(step.carried.living.settled().strokes, height, parts)


def piece_needs(key: PieceKey, bands: int = 0, measures: bool = False) -> Tuple[PieceKey, ...]:
    """The pieces the piece ``key`` needs, in the order its ``make`` takes their results (the module docstring's
    table): the one declaration of the frame's piece graph, which ``ShotPieces.piece``, the farm's scheduling and
    the bench follow. ``bands``: the frame's number of judging bands (0: its life completed at its carry);
    ``measures``: whether the shot measures (``ShotSettings.measures``)."""
    kind, t = key.kind, key.index
    prepared, motion = PieceKey(PieceKind.PREPARE, t), PieceKey(PieceKind.MOTION, t)
    carried, lived, lived_before = PieceKey(PieceKind.CARRY, t), PieceKey(PieceKind.BIRTH, t), \
        PieceKey(PieceKind.BIRTH, t - 1)
    if kind is PieceKind.PREPARE:
        return ()
    if kind is PieceKind.MOTION:
        return PieceKey(PieceKind.PREPARE, t - 1), prepared
    if kind is PieceKind.CARRY:
        return (prepared,) + ((lived_before, motion) if t else ())
    if kind is PieceKind.JUDGE or (kind is PieceKind.BIRTH and not bands):
        return (carried,)
    if kind is PieceKind.BIRTH:
        return (prepared, lived_before, motion, carried) + tuple(PieceKey(PieceKind.JUDGE, t, band)
                                                                 for band in range(bands))
    if kind is PieceKind.SHOWN:
        return (lived,)
    before = (PieceKey(PieceKind.PREPARE, t - 1), PieceKey(PieceKind.SHOWN, t - 1), motion) if t and measures else ()
    return (prepared, lived, PieceKey(PieceKind.SHOWN, t)) + before


class ShotPieces:
    """The declaration of a shot's pieces (module docstring): frames ``paths`` numbered ``numbers``, painted with
    ``shot`` into staging folders of ``folder``; PREPARE analyses after the first frame when ``analyse_ahead``
    (else CARRY analyses a frame that changed)."""

    def __init__(self, shot: ShotSettings, paths: Sequence[Path], numbers: Sequence[int], folder: Path,
                 analyse_ahead: bool):
        self.shot, self.paths, self.numbers, self.folder = shot, paths, numbers, folder
        self.analyse_ahead = analyse_ahead

    def piece(self, key: PieceKey, bands: Sequence[Rows] = ()) -> Piece:
        """The piece ``key``: what it needs (``piece_needs``) and how it is made; ``bands``: the frame's judging
        bands (``judging_bands``), which a JUDGE or BIRTH piece needs."""
        kind, t, shot = key.kind, key.index, self.shot
        needs = piece_needs(key, len(bands), shot.measures)
        if kind is PieceKind.PREPARE:
            return Piece(key, needs, partial(prepare, self.paths[t], shot, self.analyse_ahead and t > 0))
        if kind is PieceKind.MOTION:
            return Piece(key, needs, partial(motion_between, shot))
        if kind is PieceKind.CARRY:
            return Piece(key, needs, partial(carry_step, shot, t), staged=True)
        if kind is PieceKind.JUDGE:
            return Piece(key, needs, partial(judged_rows, shot, bands[key.band]))
        if kind is PieceKind.BIRTH and not bands:
            return Piece(key, needs, completed_life)
        if kind is PieceKind.BIRTH:
            return Piece(key, needs, partial(born, shot, t), staged=True)
        if kind is PieceKind.SHOWN:
            return Piece(key, needs, partial(shown, shot))
        return Piece(key, needs, partial(write, self.folder, self.numbers[t], shot))

    def needed_by_next(self, index: int) -> Set[PieceKey]:
        """The pieces of frame ``index`` that some piece of frame ``index`` + 1 (which must exist) needs: what a
        runner keeps of a frame once it is committed."""
        after = index + 1
        keys = [PieceKey(kind, after) for kind in PieceKind]
        return {need for key in keys for need in piece_needs(key, 1, self.shot.measures) if need.index == index}

    @staticmethod
    def life_start_keys(index: int) -> List[PieceKey]:
        """Frame ``index``'s pieces up to its carry, in an order that makes each after those it needs."""
        kinds = [PieceKind.PREPARE] + ([PieceKind.MOTION] if index else []) + [PieceKind.CARRY]
        return [PieceKey(kind, index) for kind in kinds]

    @staticmethod
    def life_end_keys(index: int, bands: Sequence[Rows]) -> List[PieceKey]:
        """Frame ``index``'s pieces after its carry, its JUDGE pieces those of ``bands``, in an order that makes
        each after those it needs."""
        judging = [PieceKey(PieceKind.JUDGE, index, band) for band in range(len(bands))]
        return judging + [PieceKey(kind, index) for kind in (PieceKind.BIRTH, PieceKind.SHOWN, PieceKind.WRITE)]
