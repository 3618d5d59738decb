"""A shot's frame committed: its strokes appended to the lives file, then its maps, the state and the report all
together (``staging``); a failure to write said in one sentence (ALGORITHM §9)."""

from __future__ import annotations

import shutil
import time
from pathlib import Path
from typing import List

import numpy as np

from ..errors import OutputError, plain_cause
from ..files import signals
from ..files.frames import Frames
from ..files.lives import LIVES_FILE, append_frame, cut_lives
from ..files.shot_files import REPORT_FILE
from ..files.staging import JOURNAL_NAME
from ..files.writing import write_json
from .frame_step import PaintedFrame
from .frame_work import WrittenFrame
from .shot_resume import input_digest
from .shot_settings import ShotSettings
from .shot_statistics import restate_statistics
from .state import STATE_FILE, save_state


def commit(frames: Frames, shot: ShotSettings, folder, index: int, painted: PaintedFrame, written: WrittenFrame,
           report: dict) -> None:
    """Commit frame ``index``: append its strokes to the lives file, then its maps (written into a staging
    folder), the state and the report all together; ``report`` becomes the report committed. When the commit
    fails, the lives file is cut back to the frames committed before and the exception raised."""
    clock = time.perf_counter()
    number, path = frames.numbers[index], frames.paths[index]
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
            restate_statistics(updated, len(frames.paths), shot.measures)
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


def write_fault(frames: Frames, folder: Path, report: dict, exc: Exception) -> Exception:
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
    number = frames.numbers[min(done, len(frames.numbers) - 1)]
    return OutputError(f"The output folder {folder} could not be written while frame {number} was committed "
                       f"({cause}); {frames_phrase(report['frames'])}, and the same command goes on after them "
                       f"once the folder can be written again.", folder, cause)


def frames_phrase(numbers: List[int]) -> str:
    """"frames 1-3 there are complete" of the committed frames ``numbers``; "no frame there is complete yet"
    when none is."""
    if not numbers:
        return "no frame there is complete yet"
    if len(numbers) == 1:
        return f"frame {numbers[0]} there is complete"
    return f"frames {numbers[0]}-{numbers[-1]} there are complete"
