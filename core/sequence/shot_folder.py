"""A painted shot's folder checked before a run goes on in it, and repaired to what a run never stopped would hold
(docs/sequences.md, "Guarantees").

A shot's folder is whole when report.json, the state, the lives file and
every committed frame's maps agree:

- the lives file holds exactly the frames report.json lists, ends at the
  length it records (bytes beyond it are a record of a frame never
  committed) and every record decodes whole (each section's zlib stream
  carries an Adler-32 of its bytes; ids ascend; no stroke is born twice);
- the state belongs to one of those frames: its frame index, the lives
  file's length after that frame and its strokes are that frame's record in
  the lives file, byte for byte;
- every file report.json lists under a frame's "files" has the size and
  SHA-256 listed.

``ShotFolder.check`` only reads. What it cannot vouch for it refuses with one
sentence naming the file and the problem (a damaged lives record, a state
that is not a state or belongs to no frame of the shot). What a run can
rebuild it plans as a repair (``Resume``): the frames to keep are those
before the first frame that is wrong (a map missing or damaged, the state
lagging behind report.json, the lives file or the state missing), and the
state must be that of the last frame kept. Only the last frame's state is
kept, so a repair keeps every frame when the lives file is too long, the
frames up to the state's when the state lags, and none otherwise: frame 0
on is painted again. ``ShotFolder.repair`` writes the plan: report.json
rolled back first (all-or-nothing, through the staging of
``core.files.staging``), then the lives file cut to the frames kept, so a
run stopped between the two leaves a folder the next check repairs again.
"""

from __future__ import annotations

from pathlib import Path
from typing import List, NamedTuple, Optional, Tuple

from ..errors import InputError, OutputError
from ..files.export import file_digest, run_all
from ..files.lives import LIVES_FILE, LivesFile, cut_lives, encode_record
from ..files.shot_files import REPORT_FILE
from ..files.writing import write_json
from .state import STATE_FILE, SavedState, load_state


class Resume(NamedTuple):
    """What a run goes on from in a shot's folder.

    keep: the committed frames kept (0 .. the frames report.json lists); frames from index ``keep`` on are painted
    again. lives_bytes: the lives file's length after them (0 when none is kept). cut: the lives file is longer
    than that and is cut back. problems: what was found wrong, each a clause ("painting_0004.png was missing").
    """

    keep: int
    lives_bytes: int
    cut: bool
    problems: Tuple[str, ...]


class ShotFolder:
    """The painted shot in ``folder``: its report.json, ``STATE_FILE``, ``LIVES_FILE`` and frames' maps."""

    def __init__(self, folder):
        self.folder = Path(folder)
        self.lives_path = self.folder / LIVES_FILE
        self.state_path = self.folder / STATE_FILE

    def check(self, report: dict) -> Resume:
        """The frames of ``report`` (report.json as read, the shot's own) a run can go on from, with what must be
        repaired; OutputError (one sentence naming the file and the problem) when the folder cannot be vouched
        for. Reads only."""
        committed = self._committed(report)
        frames = report["frames"]
        if not frames:
            return Resume(0, 0, False, ())
        problems: List[str] = []
        keep = len(frames)
        lives = self._lives(frames, committed)
        if lives is None:
            problems.append(f"{LIVES_FILE} was missing")
            keep = 0
        state = self._state(frames, lives)
        if state is None:
            problems.append(f"{STATE_FILE} was missing")
            keep = 0
        elif state.index < len(frames) - 1:
            problems.append(f"{STATE_FILE} was that of frame {frames[state.index]}, not of frame {frames[-1]}")
            keep = min(keep, state.index + 1)
        damaged = self._first_damaged(report["per_frame"][:keep])
        if damaged is not None:
            problems.append(damaged[1])
            keep = damaged[0]
        if keep and (state is None or state.index != keep - 1):
            keep = 0
        size = self.lives_path.stat().st_size if lives is not None else 0
        lives_bytes = int(lives.ends()[keep - 1]) if keep else 0
        cut = lives is not None and size > (lives_bytes or committed)
        if cut and keep == len(frames):
            problems.append(f"{LIVES_FILE} held {size - committed} bytes beyond its last committed frame")
        return Resume(keep, lives_bytes, cut, tuple(problems))

    def _committed(self, report: dict) -> int:
        """The lives file's committed length report.json records; OutputError when report.json does not list its
        frames consistently."""
        try:
            committed = int(report["lives"]["bytes"])
            consistent = ([entry["frame"] for entry in report["per_frame"]] == report["frames"]
                          and committed >= 0 and all(isinstance(e.get("files"), dict) for e in report["per_frame"]))
        except (KeyError, TypeError, ValueError):
            consistent = False
        if not consistent:
            raise OutputError(f"The report {self.folder / REPORT_FILE} does not list its frames, their files and the "
                              f"lives file's length consistently; paint the sequence into another folder.")
        return committed

    def _lives(self, frames: List[int], committed: int) -> Optional[LivesFile]:
        """The lives file indexed to its ``committed`` length, every record checked whole and its frames those of
        report.json (``frames``); None when there is none. OutputError (one sentence) when it is damaged,
        shorter than committed or holds other frames."""
        if not self.lives_path.exists() and not self.lives_path.is_symlink():
            return None
        try:
            size = self.lives_path.stat().st_size
            if size < committed:
                raise InputError(f"The lives file {self.lives_path} is {size} bytes, shorter than the {committed} "
                                 f"bytes report.json records for its frames.")
            lives = LivesFile(self.lives_path, committed)
            if lives.frames.tolist() != list(frames):
                raise InputError(f"The lives file {self.lives_path} holds frames {lives.frames.tolist()}, not the "
                                 f"frames {list(frames)} report.json lists.")
            lives.check()
        except OSError as exc:
            raise OutputError(f"The lives file {self.lives_path} cannot be read ({exc.strerror or exc}); paint the "
                              f"sequence into another folder.") from None
        except InputError as exc:
            raise OutputError(f"{str(exc).rstrip('.')}; paint the sequence into another folder.") from None
        return lives

    def _state(self, frames: List[int], lives: Optional[LivesFile]) -> Optional[SavedState]:
        """The state, checked to be that of one of ``frames`` (its index, the lives length after it and its
        strokes, against ``lives`` when there is one); None when there is none. OutputError (one sentence)
        when it is not a state or belongs to no frame of the shot."""
        if not self.state_path.exists() and not self.state_path.is_symlink():
            return None
        try:
            state = load_state(self.state_path)
        except InputError as exc:
            raise OutputError(str(exc)) from None
        if state.index >= len(frames):
            raise OutputError(f"The sequence state {self.state_path} is that of a frame after the last one "
                              f"report.json lists (frame {frames[-1]}); paint the sequence into another folder.")
        if lives is not None and not self._state_is_record(state, frames[state.index], lives):
            raise OutputError(f"The sequence state {self.state_path} is not that of frame {frames[state.index]}, "
                              f"whose strokes and length {self.lives_path.name} records otherwise; paint the "
                              f"sequence into another folder.")
        return state

    @staticmethod
    def _state_is_record(state: SavedState, frame: int, lives: LivesFile) -> bool:
        """Whether ``state``'s strokes, encoded as frame ``frame``'s lives record, are the bytes of that record
        in ``lives``, and its lives length is where that record ends."""
        index = state.index
        if int(lives.ends()[index]) != state.lives_bytes:
            return False
        living = state.frame.living
        try:
            record = encode_record(frame, living.ident, living.strokes.control, living.strokes.control_count)
        except ValueError:
            return False
        return record == lives.record_bytes(index)

    def _first_damaged(self, per_frame: List[dict]) -> Optional[Tuple[int, str]]:
        """(index, clause) of the first of the frames' entries ``per_frame`` whose listed files are not all there
        with their sizes and SHA-256; None when every one is."""
        for index, entry in enumerate(per_frame):
            problem = self._frame_problem(entry["files"])
            if problem is not None:
                return index, problem
        return None

    def _frame_problem(self, files: dict) -> Optional[str]:
        """A clause saying what is wrong with the first of ``files`` ({name: {"bytes", "sha256"}}) that is missing
        or whose size or SHA-256 differs; None when all agree."""
        paths = [self.folder / name for name in files]
        for path in paths:
            if not path.is_file():
                return f"{path.name} was missing"
            if path.stat().st_size != files[path.name]["bytes"]:
                return f"{path.name} was damaged (its size is not the one report.json lists)"
        digests = run_all([lambda p=path: file_digest(p)["sha256"] for path in paths])
        for path, digest in zip(paths, digests, strict=True):
            if digest != files[path.name]["sha256"]:
                return f"{path.name} was damaged (its SHA-256 is not the one report.json lists)"
        return None

    def repair(self, output, resume: Resume, report: dict, dropped: List[dict]) -> None:
        """Write the repair ``resume`` plans into the locked ``output`` folder (``staging.OutputFolder``): when
        frames are ``dropped`` (report.json's entries of the frames not kept), ``report`` (report.json with the
        frames kept) is committed first, then the dropped frames' maps are removed and, with no frame kept, the
        state and the lives file; then the lives file is cut to the frames kept."""
        if dropped:
            with output.staged() as staging:
                write_json(staging / REPORT_FILE, report)
            for entry in dropped:
                for name in entry.get("files", {}):
                    if Path(name).name == name and name not in (REPORT_FILE, LIVES_FILE, STATE_FILE):
                        (self.folder / name).unlink(missing_ok=True)
            if resume.keep == 0:
                self.state_path.unlink(missing_ok=True)
        if dropped or resume.cut:
            cut_lives(self.lives_path, resume.lives_bytes if resume.keep else 0)

    def sentence(self, resume: Resume, committed: int, numbers: List[int]) -> str:
        """The one sentence of the repair ``resume`` of a folder of ``committed`` frames by a run of the frames
        ``numbers``."""
        problems = "; ".join(resume.problems)
        if resume.keep == committed:
            return f"Repaired {self.folder}: {problems}, which are cut off."
        if resume.keep >= len(numbers):
            return f"Repaired {self.folder}: {problems}; the frames after frame {numbers[resume.keep - 1]} are dropped."
        again = numbers[resume.keep:]
        frames = f"frame {again[0]} is" if len(again) == 1 else f"frames {again[0]}-{again[-1]} are"
        return f"Repaired {self.folder}: {problems}; {frames} painted again."
