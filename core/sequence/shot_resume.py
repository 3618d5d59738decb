"""How a run knows the frames in a shot's folder are its own, and the report it goes on from (ALGORITHM §9).

report.json records the sequence's fingerprint (the SHA-256 of the painter's
version, the parameters, seed included, the fade and normal-map settings and
the motion's source) and every committed frame's number, file name and
SHA-256 of its input file. A run resumes only when the fingerprint is its own
and each frame already painted is the same frame of the same input; otherwise
it refuses with one sentence and touches nothing. A folder whose files do not
agree is repaired first when it can be (``shot_folder.ShotFolder``): the
report is rolled back to the frames kept.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import List

from ..errors import OutputError
from ..files.frames import Frames
from ..files.lives import LIVES_FILE
from ..files.shot_files import is_shot_report, read_report
from ..version import __version__
from .frame_step import PaintedFrame
from .shot_folder import Resume, ShotFolder
from .shot_settings import ShotSettings
from .shot_statistics import restate_statistics
from .state import STATE_FILE, load_state


def fingerprint(shot: ShotSettings) -> str:
    """The SHA-256 (hex) of what makes a shot's frames (``ShotSettings.key``: the version, the parameters, the fade
    and normal-map settings, the motion's source)."""
    return hashlib.sha256(json.dumps(shot.key, sort_keys=True).encode("utf-8")).hexdigest()


def input_digest(path: Path) -> str:
    """The SHA-256 (hex) of a frame's input file."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def new_report(frames: Frames, shot: ShotSettings) -> dict:
    """The report of a sequence with no frame painted yet."""
    return {"version": __version__, "sequence": fingerprint(shot), "input": [str(p) for p in frames.paths],
            "frame_count": len(frames.paths), "width": frames.width, "height": frames.height,
            "motion": shot.motion, "fade_frames": shot.fade_frames, "params": shot.params.to_dict(),
            "frames": [], "per_frame": [], "lives": {"file": LIVES_FILE, "bytes": 0}, "complete": False}


def resumed_report(frames: Frames, shot: ShotSettings, folder: Path) -> dict:
    """The report of the frames already committed in ``folder`` when they are this run's (a new report when
    it holds none); OutputError naming the folder when it holds another sequence's frames or a still."""
    try:
        report = read_report(folder)
    except (OSError, ValueError) as exc:
        raise OutputError(f"The output folder {folder} holds a report.json that cannot be read ({exc}); "
                          f"paint into another folder.") from exc
    if report is None:
        return new_report(frames, shot)
    if not is_shot_report(report):
        raise OutputError(f"The output folder {folder} holds a still painting; paint the sequence into "
                          f"another folder.")
    if report["sequence"] != fingerprint(shot):
        raise OutputError(f"The output folder {folder} holds frames painted with other settings (parameters, "
                          f"seed, fade or motion); paint into another folder, or repeat that run's command to "
                          f"go on with it.")
    for i, entry in enumerate(report["per_frame"][:len(frames.paths)]):
        path, number = frames.paths[i], frames.numbers[i]
        if entry["frame"] != number:
            held, mine = report["frames"], frames.numbers
            raise OutputError(f"The output folder {folder} holds a shot of frames {held[0]} to {held[-1]}, which "
                              f"this run's frames {mine[0]} to {mine[-1]} do not go on from (its frame "
                              f"{entry['frame']} is this run's frame {number}); paint into another folder, or "
                              f"name the frames that shot was painted from.")
        if entry["input_sha256"] != input_digest(path):
            raise OutputError(f"The output folder {folder} holds frame {number} painted from another picture "
                              f"than {path} holds now; paint into another folder.")
    return report


def repaired(frames: Frames, shot: ShotSettings, folder, shot_folder: ShotFolder, resume: Resume, report: dict):
    """(report, sentence): the report to go on from and the one sentence of the repair of ``folder`` (None
    when nothing was repaired), with the repair ``resume`` written (``ShotFolder.repair``). The report's
    frames beyond ``resume.keep`` are dropped; when frames were dropped or remain to paint, its "input" and
    "frame_count" become those of the frames kept and of this run's frames after them."""
    committed = len(report["per_frame"])
    dropped = report["per_frame"][resume.keep:]
    if dropped:
        report = rolled_back(frames, shot, report, resume.keep, resume.lives_bytes)
    if dropped or len(report["per_frame"]) < len(frames.paths):
        report["input"] = inputs_after(frames, report)
        report["frame_count"] = len(report["input"])
    if not resume.problems:
        return report, None
    shot_folder.repair(folder, resume, report, dropped)
    return report, shot_folder.sentence(resume, committed, frames.numbers)


def inputs_after(frames: Frames, report: dict) -> List[str]:
    """The input frames' paths of the frames ``report`` holds, then this run's frames after them: what
    report.json's "input" lists once this run has painted. A frame held that this run does not name keeps the
    path ``report`` gave it."""
    mine = dict(zip(frames.numbers, map(str, frames.paths), strict=True))
    earlier = {Path(path).name: path for path in report["input"]}
    held = [mine.get(number) or earlier.get(entry["input"], entry["input"])
            for number, entry in zip(report["frames"], report["per_frame"], strict=True)]
    last = report["frames"][-1] if report["frames"] else None
    return held + [path for number, path in mine.items() if last is None or number > last]


def rolled_back(frames: Frames, shot: ShotSettings, report: dict, keep: int, lives_bytes: int) -> dict:
    """``report`` with its first ``keep`` frames only (a new report when ``keep`` is 0), the lives file's
    length after them ``lives_bytes``, and the statistics of those frames."""
    if keep == 0:
        return new_report(frames, shot)
    rolled = json.loads(json.dumps(report))
    rolled["per_frame"], rolled["frames"] = rolled["per_frame"][:keep], rolled["frames"][:keep]
    rolled["lives"]["bytes"] = lives_bytes
    restate_statistics(rolled, len(frames.paths), shot.measures)
    return rolled


def resumed_frame(folder: Path) -> PaintedFrame:
    """The strokes of the last frame committed in ``folder`` (its state file), to go on from."""
    return load_state(folder / STATE_FILE).frame
