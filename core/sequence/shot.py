"""Painting a whole shot into one folder, frame after frame, every frame committed whole, resumable (ALGORITHM §9).

``paint_sequence`` reads each frame, takes the motion from the frame before
(Blender's Vector pass when every frame has one, else optical flow), paints
it (``frame_step``) and commits the frame's maps, the sequence's report and
the state the next frame needs all together (``staging``); the strokes' lives
are appended to one file whose committed length the state records. A run
stopped anywhere leaves complete frames only, and the same command resumes
after the last of them with the same bytes as a run never stopped.

How a run knows the frames in a folder are its own: report.json records the
sequence's fingerprint (the SHA-256 of the painter's version, the parameters,
seed included, the fade and normal-map settings and the motion's source) and
every committed frame's number, file name and SHA-256 of its input file. A
run resumes only when the fingerprint is its own and each frame already
painted is the same frame of the same input; otherwise it refuses with one
sentence and touches nothing.
"""

from __future__ import annotations

import concurrent.futures
import hashlib
import json
import shutil
import time
from pathlib import Path
from typing import Callable, Dict, List, Optional, Set

import numpy as np

from ..errors import Cancelled, OutputError, plain_cause
from ..files import signals
from ..files.frames import Frames
from ..files.lives import LIVES_FILE, append_frame, cut_lives
from ..files.shot_files import REPORT_FILE, frame_file_names, is_shot_report, read_report
from ..files.staging import JOURNAL_NAME, output_folder
from ..files.writing import write_json
from ..motion.source import motion_source
from ..params import Params, SequenceSettings
from ..progress import CancelFn, ProgressFn, Stage
from ..version import __version__
from .frame_step import PaintedFrame
from .frame_work import WrittenFrame
from .pieces import Piece, PieceKey, PieceKind, ShotPieces, judging_bands
from .shot_folder import Resume, ShotFolder
from .shot_settings import ShotSettings
from .state import STATE_FILE, load_state, save_state


def fingerprint(shot: ShotSettings) -> str:
    """The SHA-256 (hex) of what makes a shot's frames: the version, the parameters, the fade and normal-map
    settings, the motion's source."""
    text = json.dumps({"version": __version__, "params": shot.params.to_dict(), "fade_frames": shot.fade_frames,
                       "normal_map": shot.normal_map, "motion": shot.motion}, sort_keys=True)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def input_digest(path: Path) -> str:
    """The SHA-256 (hex) of a frame's input file."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


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


def frames_phrase(numbers: List[int]) -> str:
    """"frames 1-3 there are complete" of the committed frames ``numbers``; "no frame there is complete yet"
    when none is."""
    if not numbers:
        return "no frame there is complete yet"
    if len(numbers) == 1:
        return f"frame {numbers[0]} there is complete"
    return f"frames {numbers[0]}-{numbers[-1]} there are complete"


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
        """The report of the frames already committed in ``folder`` when they are this run's (a new report when
        it holds none); OutputError naming the folder when it holds another sequence's frames or a still."""
        try:
            report = read_report(folder)
        except (OSError, ValueError) as exc:
            raise OutputError(f"The output folder {folder} holds a report.json that cannot be read ({exc}); "
                              f"paint into another folder.") from exc
        if report is None:
            return self.new_report()
        if not is_shot_report(report):
            raise OutputError(f"The output folder {folder} holds a still painting; paint the sequence into "
                              f"another folder.")
        if report["sequence"] != self.key:
            raise OutputError(f"The output folder {folder} holds frames painted with other settings (parameters, "
                              f"seed, fade or motion); paint into another folder, or repeat that run's command to "
                              f"go on with it.")
        for i, entry in enumerate(report["per_frame"][:len(self.frames.paths)]):
            path, number = self.frames.paths[i], self.frames.numbers[i]
            if entry["frame"] != number:
                held, mine = report["frames"], self.frames.numbers
                raise OutputError(f"The output folder {folder} holds a shot of frames {held[0]} to {held[-1]}, which "
                                  f"this run's frames {mine[0]} to {mine[-1]} do not go on from (its frame "
                                  f"{entry['frame']} is this run's frame {number}); paint into another folder, or "
                                  f"name the frames that shot was painted from.")
            if entry["input_sha256"] != input_digest(path):
                raise OutputError(f"The output folder {folder} holds frame {number} painted from another picture "
                                  f"than {path} holds now; paint into another folder.")
        return report

    def repaired(self, folder, shot_folder: ShotFolder, resume: Resume, report: dict):
        """(report, sentence): the report to go on from and the one sentence of the repair of ``folder`` (None
        when nothing was repaired), with the repair ``resume`` written (``ShotFolder.repair``). The report's
        frames beyond ``resume.keep`` are dropped; when frames were dropped or remain to paint, its "input" and
        "frame_count" become those of the frames kept and of this run's frames after them."""
        committed = len(report["per_frame"])
        dropped = report["per_frame"][resume.keep:]
        if dropped:
            report = self.rolled_back(report, resume.keep, resume.lives_bytes)
        if dropped or len(report["per_frame"]) < len(self.frames.paths):
            report["input"] = self.inputs_after(report)
            report["frame_count"] = len(report["input"])
        if not resume.problems:
            return report, None
        shot_folder.repair(folder, resume, report, dropped)
        return report, shot_folder.sentence(resume, committed, self.frames.numbers)

    def inputs_after(self, report: dict) -> List[str]:
        """The input frames' paths of the frames ``report`` holds, then this run's frames after them: what
        report.json's "input" lists once this run has painted. A frame held that this run does not name keeps the
        path ``report`` gave it."""
        mine = dict(zip(self.frames.numbers, map(str, self.frames.paths), strict=True))
        earlier = {Path(path).name: path for path in report["input"]}
        held = [mine.get(number) or earlier.get(entry["input"], entry["input"])
                for number, entry in zip(report["frames"], report["per_frame"], strict=True)]
        last = report["frames"][-1] if report["frames"] else None
        return held + [path for number, path in mine.items() if last is None or number > last]

    def rolled_back(self, report: dict, keep: int, lives_bytes: int) -> dict:
        """``report`` with its first ``keep`` frames only (a new report when ``keep`` is 0), the lives file's
        length after them ``lives_bytes``, and the figures of those frames."""
        if keep == 0:
            return self.new_report()
        rolled = json.loads(json.dumps(report))
        rolled["per_frame"], rolled["frames"] = rolled["per_frame"][:keep], rolled["frames"][:keep]
        rolled["lives"]["bytes"] = lives_bytes
        self.figure(rolled)
        return rolled

    def figure(self, report: dict) -> None:
        """Put the figures of ``report``'s frames (``sequence_figures``) into it, in place of any earlier run's."""
        for key in STEADINESS_FIGURES:
            report.pop(key, None)
        report.update(sequence_figures(report["per_frame"], len(self.frames.paths), self.shot.measures))

    def write_fault(self, folder: Path, report: dict, exc: Exception) -> Exception:
        """The OutputError of ``exc``, a failure to write frame after ``report``'s last into ``folder``: one
        sentence naming the folder and the cause. ``exc`` itself when it is a commit the next run completes."""
        if isinstance(exc, OutputError) and exc.cause is None and "the next run into that folder" in str(exc):
            return exc
        if isinstance(exc, OSError):
            cause = plain_cause(exc, folder)
        elif exc.cause is not None:
            cause = exc.cause
        else:
            text = str(exc).rstrip(".")
            cause = text[:1].lower() + text[1:]
        done = len(report["per_frame"])
        number = self.frames.numbers[min(done, len(self.frames.numbers) - 1)]
        return OutputError(f"The output folder {folder} could not be written while frame {number} was committed "
                           f"({cause}); {frames_phrase(report['frames'])}, and the same command goes on after them "
                           f"once the folder can be written again.", folder, cause)

    def new_report(self) -> dict:
        """The report of a sequence with no frame painted yet."""
        return {"version": __version__, "sequence": self.key, "input": [str(p) for p in self.frames.paths],
                "frame_count": len(self.frames.paths), "width": self.frames.width, "height": self.frames.height,
                "motion": self.shot.motion, "fade_frames": self.shot.fade_frames, "params": self.shot.params.to_dict(),
                "frames": [], "per_frame": [], "lives": {"file": LIVES_FILE, "bytes": 0}, "complete": False}

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
        """The strokes of the last frame committed in ``folder`` (its state file), to go on from."""
        return load_state(folder / STATE_FILE).frame

    def commit(self, folder, index: int, painted: PaintedFrame, written: WrittenFrame, report: dict) -> None:
        """Commit frame ``index``: append its strokes to the lives file, then its maps (written into a staging
        folder), the state and the report all together; ``report`` becomes the report committed. When the commit
        fails, the lives file is cut back to the frames committed before and the exception raised."""
        clock = time.perf_counter()
        number, path = self.frames.numbers[index], self.frames.paths[index]
        strokes = painted.living.strokes
        lives_path, committed = folder.folder / LIVES_FILE, report["lives"]["bytes"]
        entry = {"frame": number, "input": path.name, "input_sha256": input_digest(path),
                 "alive": len(painted.living), "born": painted.born, "died": painted.died,
                 "dying": int(np.count_nonzero(painted.living.dying)), **written.entry}
        try:
            lives_bytes = append_frame(lives_path, number, painted.living.ident, strokes.control,
                                       strokes.control_count, committed)
            with folder.staged(written.staging) as staging:
                save_state(staging / STATE_FILE, painted, index, lives_bytes)
                seconds = dict(painted.seconds, **written.seconds)
                seconds["writing"] += time.perf_counter() - clock
                entry["seconds"] = {name: round(value, 4) for name, value in seconds.items()}
                entry["files"] = written.files
                updated = dict(report, per_frame=report["per_frame"] + [entry], frames=report["frames"] + [number],
                               lives=dict(report["lives"], bytes=lives_bytes))
                self.figure(updated)
                write_json(staging / REPORT_FILE, updated)
        except BaseException as exc:  # a fault or a signal before the commit point: the frame never was
            committed_now = isinstance(exc, signals.Interrupted) and exc.committed
            with signals.deferred():
                if not committed_now and not (folder.folder / JOURNAL_NAME).exists():
                    shutil.rmtree(written.staging, ignore_errors=True)
                    cut_lives(lives_path, committed)
            raise
        report.clear()
        report.update(updated)


class SideThread:
    """A side thread for one piece of work at a time (``pending``, its future), waited for on leaving the
    ``with`` block."""

    def __init__(self, name: str):
        self.pool = concurrent.futures.ThreadPoolExecutor(1, thread_name_prefix=name)
        self.pending = None

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.pool.shutdown(wait=True)


class FrameBehind(SideThread):
    """One frame's SHOWN and WRITE pieces made on a side thread while the next frame's life is made: ``start``
    hands it the pieces with the results they need, ``finished`` waits for them."""

    def __init__(self):
        super().__init__("paint-relief-frame")

    def start(self, index: int, painted: PaintedFrame, shown: Piece, write: Piece,
              made: Dict[PieceKey, object]) -> None:
        """Make frame ``index``'s ``shown`` then ``write`` pieces on the side thread from the results in ``made``
        now (``write`` needs ``shown``'s result, the rest from ``made``); ``painted`` is the frame's strokes."""
        shown_inputs = [made[key] for key in shown.needs]
        write_inputs = [None if key == shown.key else made[key] for key in write.needs]
        at = write.needs.index(shown.key)

        def side():
            shown_now = shown.make(*shown_inputs)
            write_inputs[at] = shown_now
            return shown_now, write.make(*write_inputs)

        self.pending = index, painted, self.pool.submit(side)

    def finished(self):
        """(index, strokes, the frame as shown, the frame written) of the frame started last, once made (its failure
        raised), or None when none is pending."""
        if self.pending is None:
            return None
        index, painted, future = self.pending
        self.pending = None
        shown_now, written = future.result()
        return index, painted, shown_now, written


class FrameAhead(SideThread):
    """The next frame's PREPARE and MOTION pieces (reading it, the motion to it) made on a side thread while this
    frame's life is made: ``start`` hands it the pieces, ``finished`` waits for them. Its analysis is left to its
    CARRY: made ahead, it would overlap the life's own peak of memory (at 1920x1080 +650 MiB for a few per cent of
    time)."""

    def __init__(self):
        super().__init__("paint-relief-ahead")

    def start(self, pieces: ShotPieces, index: int, made: Dict[PieceKey, object]) -> None:
        """Make frame ``index``'s PREPARE and MOTION pieces (``index`` >= 1) on the side thread, the frame before's
        PREPARE result taken from ``made`` now."""
        prepare = pieces.piece(PieceKey(PieceKind.PREPARE, index))
        motion = pieces.piece(PieceKey(PieceKind.MOTION, index))
        before = made[PieceKey(PieceKind.PREPARE, index - 1)]

        def side() -> Dict[PieceKey, object]:
            prepared = prepare.make()
            moved = motion.make(before, prepared)
            return {prepare.key: prepared, motion.key: moved}

        self.pending = self.pool.submit(side)

    def finished(self) -> Dict[PieceKey, object]:
        """{key: result} of the pieces started last, once made (their failure raised); empty when none is
        pending."""
        if self.pending is None:
            return {}
        future, self.pending = self.pending, None
        return future.result()


def release(made: Dict[PieceKey, object], needed: Set[PieceKey]) -> None:
    """Remove from ``made`` every result whose key is not in ``needed``."""
    for key in [key for key in made if key not in needed]:
        del made[key]


def frame_progress(progress: ProgressFn, number: int, index: int, count: int) -> ProgressFn:
    """A progress callback that names the frame: "Frame 16 (3/12): <message>"."""
    if progress is None:
        return None
    return lambda fraction, message: progress(fraction, f"Frame {number} ({index + 1}/{count}): {message}")


def figure_mean(values: List[Optional[float]]) -> float:
    """The mean of the figures ``values`` that have a value (a None, as report.json's null reads back, or a NaN
    has none); NaN when none has."""
    numbers = np.array([np.nan if value is None else value for value in values], np.float64)
    return float(np.nanmean(numbers)) if (~np.isnan(numbers)).any() else float("nan")


STEADINESS_FIGURES = ("warping_error", "stillness")
"""The keys of report.json that ``steadiness_figures`` writes."""


def sequence_figures(per_frame: List[dict], frame_count: int, measures: bool) -> dict:
    """The sequence's figures from its frames' entries: stroke counts, seconds per stage and mean PSNR; with
    ``measures``, also the warping errors of the pairs measured (the height's normalised to [0, 1] over the frames
    painted: divided by their height range squared) and their ratios to the footage's, and the stillness of the
    painting against the footage's."""
    seconds: Dict[str, float] = {}
    for entry in per_frame:
        for name, value in entry["seconds"].items():
            seconds[name] = round(seconds.get(name, 0.0) + value, 4)
    figures = {"complete": len(per_frame) >= frame_count,
               "strokes": {"alive": [e["alive"] for e in per_frame], "born": [e["born"] for e in per_frame],
                           "died": [e["died"] for e in per_frame]},
               "seconds": seconds, "psnr": figure_mean([e["psnr"] for e in per_frame])}
    return dict(figures, **steadiness_figures(per_frame)) if measures else figures


def steadiness_figures(per_frame: List[dict]) -> dict:
    """The sequence's warping errors and stillness (``sequence_figures``) over the pairs ``per_frame`` measured."""
    pairs = [entry for entry in per_frame if "warping_error" in entry]
    low = min(entry["height_range"][0] for entry in per_frame)
    high = max(entry["height_range"][1] for entry in per_frame)
    footage = figure_mean([p["warping_error"]["footage"] for p in pairs])
    painting = figure_mean([p["warping_error"]["painting"] for p in pairs])
    height = figure_mean([p["warping_error"]["height_raw"] for p in pairs]) / max(high - low, 1e-12) ** 2
    still = [p for p in pairs if p["still_pixels"]]
    still_footage = figure_mean([p["stillness"]["footage"] for p in still])
    still_painting = figure_mean([p["stillness"]["painting"] for p in still])
    return {"warping_error": {"footage": footage, "painting": painting, "height": height,
                              "painting_ratio": painting / footage if footage else float("nan")},
            "stillness": {"footage": still_footage, "painting": still_painting,
                          "ratio": still_painting / still_footage if still_footage else float("nan")}}
