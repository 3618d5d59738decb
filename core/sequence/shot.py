"""Painting a whole shot into one folder, frame after frame, every frame committed whole, resumable (ALGORITHM §9).

``paint_sequence`` reads each frame, takes the motion from the frame before
(Blender's Vector pass when every frame has one, else optical flow), paints
it (``frame_step``) and commits the frame's maps, the sequence's report and
the state the next frame needs all together (``staging``); the strokes' lives
are appended to one file whose committed length the state records. A run
stopped anywhere leaves complete frames only, and the same command resumes
after the last of them with the same bytes as a run never stopped.

How a run knows the frames in a folder are its own and goes on from them
is ``shot_resume``; a frame's commit, ``shot_commit``; the report's
statistics, ``shot_statistics``; the side threads beside a frame's life,
``side_threads``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable, Dict, List, Optional, Set

from ..errors import Cancelled, OutputError
from ..files.frames import Frames
from ..files.shot_files import REPORT_FILE, frame_file_names
from ..files.staging import output_folder
from ..motion.source import motion_source
from ..params import Params, SequenceSettings
from ..progress import CancelFn, ProgressFn, Stage
from . import shot_commit, shot_resume
from .frame_step import PaintedFrame
from .frame_work import WrittenFrame
from .pieces import Piece, PieceKey, PieceKind, ShotPieces, judging_bands
from .shot_folder import Resume, ShotFolder
from .shot_resume import fingerprint
from .shot_settings import ShotSettings
from .side_threads import FrameAhead, FrameBehind
from .state import STATE_FILE


def paint_sequence(frames: Frames, output_dir, params: Params, settings: Optional[SequenceSettings] = None,
                   progress: ProgressFn = None, cancel: CancelFn = None, frames_painter=None,
                   notice: Optional[Callable[[str], None]] = None) -> dict:
    """Paint ``frames`` into ``output_dir`` (module docstring) with ``settings`` (default ``SequenceSettings()``);
    return the sequence's report.

    Refusals (one sentence, the folder untouched): parameters out of range or a layout other than the paper's;
    frames of which only some carry a Vector pass; a folder holding another sequence's frames or a still
    painting; a folder whose report.json, state, lives file and maps do not agree and cannot be repaired
    (``shot_folder.ShotFolder``). A folder that can be repaired is, before painting, and the repair is said in one
    sentence: to ``notice(sentence)``, else to progress(0, sentence), and as the returned report's "repaired".
    A folder that cannot be written while a frame is (a full disk, a lost mount, a permission changed) is an
    OutputError of one sentence naming the folder and the cause; the frames committed before stay whole.
    progress(fraction, message) reports the frame and the work within it; cancel() stops between stages
    (complete frames stay). frames_painter(run, start, report, folder, progress, cancel) paints and commits the
    frames from ``start`` on elsewhere (``core.farm.sequence.ClusterFrames``); by default this process paints
    them (``Run.paint_from``), with the same bytes.
    """
    settings = settings or SequenceSettings()
    params.validate_shot()
    settings.validate()
    run = Run(frames, shot_settings(frames, params, settings))
    repaired = None
    with output_folder(output_dir) as folder:
        report = run.resumed_report(folder.folder)
        shot_folder = ShotFolder(folder.folder)
        resume = shot_folder.check(report)
        folder.check_names([name for number in frames.numbers for name in frame_file_names(number, settings.normal_map)]
                           + [REPORT_FILE, STATE_FILE])
        try:
            report, repaired = run.repaired(folder, shot_folder, resume, report)
            if repaired is not None:
                tell(repaired, notice, progress)
            done = len(report["per_frame"])
            if done < len(frames.paths):
                if frames_painter is None:
                    run.paint_from(done, report, folder, progress, cancel)
                else:
                    frames_painter(run, done, report, folder, progress, cancel)
        except Cancelled:
            raise Cancelled(f"The run was cancelled; the frames in {output_dir} are complete, and painting the "
                            f"sequence again goes on after the last of them.") from None
        except (OSError, OutputError) as exc:
            raise run.write_fault(folder.folder, report, exc) from exc
    report["output_dir"] = str(Path(output_dir).resolve())
    if repaired is not None:
        report["repaired"] = repaired
    return report


def tell(sentence: str, notice: Optional[Callable[[str], None]], progress: ProgressFn) -> None:
    """Say ``sentence`` to ``notice``, else as progress at 0."""
    if notice is not None:
        notice(sentence)
    elif progress is not None:
        progress(0.0, sentence)


def shot_settings(frames: Frames, params: Params, settings: SequenceSettings) -> ShotSettings:
    """The settings ``frames`` are painted with: ``params``, ``settings``, their motion's source (from the frames'
    headers) and their shape."""
    return ShotSettings(params, settings.fade_frames, settings.normal_map, motion_source(frames.paths),
                        (frames.height, frames.width), settings.measures)


class Run:
    """One run of ``paint_sequence``: its frames, their ``ShotSettings`` and the report it keeps up to date."""

    def __init__(self, frames: Frames, shot: ShotSettings):
        self.frames, self.shot, self.key = frames, shot, fingerprint(shot)

    def pieces(self, folder: Path, analyse_ahead: bool) -> ShotPieces:
        """The declaration of this run's pieces (``pieces.ShotPieces``), writing into staging folders of
        ``folder``."""
        return ShotPieces(self.shot, self.frames.paths, self.frames.numbers, folder, analyse_ahead)

    def resumed_report(self, folder: Path) -> dict:
        """The report to go on from in ``folder`` (``shot_resume.resumed_report``)."""
        return shot_resume.resumed_report(self.frames, self.shot, folder)

    def repaired(self, folder, shot_folder: ShotFolder, resume: Resume, report: dict):
        """(report, sentence) of the repair ``resume`` of ``folder`` (``shot_resume.repaired``)."""
        return shot_resume.repaired(self.frames, self.shot, folder, shot_folder, resume, report)

    def write_fault(self, folder: Path, report: dict, exc: Exception) -> Exception:
        """The one-sentence OutputError of ``exc``, a failure to write into ``folder``
        (``shot_commit.write_fault``)."""
        return shot_commit.write_fault(self.frames, folder, report, exc)

    def new_report(self) -> dict:
        """The report of this run with no frame painted yet (``shot_resume.new_report``)."""
        return shot_resume.new_report(self.frames, self.shot)

    def paint_from(self, start: int, report: dict, folder, progress: ProgressFn, cancel: CancelFn) -> None:
        """Paint frames ``start`` .. the last in this process, committing each in order, ``report`` kept up to date.

        Each frame's life (``pieces.ShotPieces``: read, motion, carry, the judging canvas in one band, births) is
        made here, frame after frame. Beside it, one side thread reads the next frame and finds the motion to it
        (``FrameAhead``), and another lays the frame before as shown and writes its maps (``FrameBehind``); a frame
        is committed once its life and its maps are made. When the life of a frame fails or is stopped, the frame
        before is still committed first (or its own failure raised), so the folder holds the frames that painting
        one frame after another would have left; the next frame's reading fails, if it does, only once this frame
        is committed. Every piece is a function of the pieces it needs, so the bytes are the same as making them
        one after another."""
        pieces, count = self.pieces(folder.folder, analyse_ahead=False), len(self.frames.paths)
        made: Dict[PieceKey, object] = {}
        if start > 0:
            made[PieceKey(PieceKind.BIRTH, start - 1)] = self.resumed_frame(folder.folder)
            for kind in (PieceKind.PREPARE, PieceKind.SHOWN) if self.shot.measures else (PieceKind.PREPARE,):
                self.make(pieces.piece(PieceKey(kind, start - 1)), made, None)
        with FrameBehind() as behind, FrameAhead() as ahead:
            try:
                for index in range(start, count):
                    stage = Stage(frame_progress(progress, self.frames.numbers[index], index, count), cancel,
                                  index / count, (index + 1) / count)
                    stage.report(0.0, "motion" if index else "painting")
                    made.update(ahead.finished())
                    *reading, carry = pieces.life_start_keys(index)
                    for key in reading:
                        if key not in made:
                            self.make(pieces.piece(key), made, stage)
                    if index + 1 < count:
                        ahead.start(pieces, index + 1, made)
                    self.make(pieces.piece(carry), made, stage)
                    stage.check()
                    bands = judging_bands(made[PieceKey(PieceKind.CARRY, index)], self.shot.shape[0], 1)
                    *life, shown, write = [pieces.piece(key, bands) for key in pieces.life_end_keys(index, bands)]
                    next_needs = pieces.needed_by_next(index) if index + 1 < count else set()
                    self.make_in_order(life, made, stage, next_needs | set(shown.needs) | set(write.needs))
                    self.commit_behind(folder, behind, made, report)
                    behind.start(index, made[PieceKey(PieceKind.BIRTH, index)], shown, write, made)
                    release(made, next_needs)
                    stage.check()
            except BaseException:
                self.commit_behind(folder, behind, made, report)
                raise
            self.commit_behind(folder, behind, made, report)

    def commit_behind(self, folder, behind: "FrameBehind", made: Dict[PieceKey, object], report: dict) -> None:
        """Commit the frame ``behind`` holds, if any, once its maps are written (its failure raised); its frame as
        shown stays in ``made`` for the next frame's writing."""
        done = behind.finished()
        if done is not None:
            index, painted, shown_now, written = done
            made[PieceKey(PieceKind.SHOWN, index)] = shown_now
            self.commit(folder, index, painted, written, report)

    def make_in_order(self, declared: List[Piece], made: Dict[PieceKey, object], stage: Stage,
                      keep: Set[PieceKey]) -> None:
        """Make the ``declared`` pieces in order (``make``); after each, let go of every result in ``made`` that no
        piece still to make needs and that ``keep`` does not name, so a frame holds no more than it must."""
        for position, piece in enumerate(declared):
            self.make(piece, made, stage)
            release(made, keep.union(*(later.needs for later in declared[position + 1:])))

    @staticmethod
    def make(piece, made: Dict[PieceKey, object], stage: Optional[Stage]):
        """Make ``piece`` from the results ``made`` of the pieces it needs, on ``stage`` when it takes one; keep its
        result in ``made`` and return it."""
        options = {"stage": stage} if piece.staged and stage is not None else {}
        made[piece.key] = piece.make(*(made[key] for key in piece.needs), **options)
        return made[piece.key]

    def resumed_frame(self, folder: Path) -> PaintedFrame:
        """The strokes of the last frame committed in ``folder`` (``shot_resume.resumed_frame``)."""
        return shot_resume.resumed_frame(folder)

    def commit(self, folder, index: int, painted: PaintedFrame, written: WrittenFrame, report: dict) -> None:
        """Commit frame ``index`` (``shot_commit.commit``); ``report`` becomes the report committed."""
        shot_commit.commit(self.frames, self.shot, folder, index, painted, written, report)


def release(made: Dict[PieceKey, object], needed: Set[PieceKey]) -> None:
    """Remove from ``made`` every result whose key is not in ``needed``."""
    for key in [key for key in made if key not in needed]:
        del made[key]


def frame_progress(progress: ProgressFn, number: int, index: int, count: int) -> ProgressFn:
    """A progress callback that names the frame: "Frame 16 (3/12): <message>"."""
    if progress is None:
        return None
    return lambda fraction, message: progress(fraction, f"Frame {number} ({index + 1}/{count}): {message}")
