"""The shot's fault catalogue: odd inputs and faults for ``core sequence``, ``core batch`` and the farm, each run the
way a user runs it (the command line, in a process of its own) and held to one standard.

The standard (README, "Guarantees"; docs/sequences.md):

- a command ends with exit 0, or with exit 2 and one sentence on stderr naming what is wrong (SIGTERM and SIGINT:
  143 and 130), never a traceback or a library's warning;
- a refusal leaves the output folder byte for byte as it was (or not there, when it was not);
- after any stop the folder holds complete frames only: ``ShotFolder.check`` vouches for every frame report.json
  lists, and no staging folder, temporary file or record beyond the last committed frame is left once the
  command has ended (a SIGKILL leaves what the next run repairs);
- the same command, once the cause is gone, goes on to the same bytes as a run never stopped.

Run it whole (prints one line per case and the counts per group; exit 1 when a case falls short)::

    .venv/bin/python tests/shot_faults.py [--only WORD] [--list] [--keep DIR]

``tests/test_shot_faults.py`` runs the same cases under pytest (``make test``). Cases that need what this machine
lacks (mounting a tmpfs, a second interpreter, Dask) say so and are counted as skipped.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import random
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import traceback
from pathlib import Path
from typing import Callable, Dict, List, NamedTuple, Optional

TESTS = Path(__file__).resolve().parent
ROOT = TESTS.parent
for path in (str(ROOT), str(TESTS)):
    if path not in sys.path:
        sys.path.insert(0, path)

import numpy as np  # noqa: E402
from crash_points import read_shot  # noqa: E402
from oracles import folder_bytes  # noqa: E402
from test_frames import write_multilayer  # noqa: E402
from test_sequence import write_moving_frames  # noqa: E402

from core.files import writing  # noqa: E402
from core.files.lives import FILE_HEADER, LIVES_FILE, LivesFile  # noqa: E402
from core.files.shot_files import read_report  # noqa: E402
from core.files.staging import STAGING_PREFIX, settle  # noqa: E402
from core.sequence.shot_folder import ShotFolder  # noqa: E402
from core.sequence.state import STATE_FILE  # noqa: E402

SEED, COUNT, SHAPE = 7, 5, (48, 64)
FRAME = "frame_{:04d}.png"


class Skipped(Exception):
    """The case needs what this machine does not have (its message says what)."""


class Case(NamedTuple):
    group: str
    name: str
    run: Callable[["Place"], None]
    cluster: bool = False

    @property
    def id(self) -> str:
        return f"{self.group}: {self.name}"


CASES: List[Case] = []


def case(group: str, name: str, cluster: bool = False):
    """Register the decorated function (given the ``Place``) as a case of ``group``."""
    def register(function):
        CASES.append(Case(group, name, function, cluster))
        return function
    return register


# --- where the cases work ------------------------------------------------------------------------------------------

class Place:
    """A folder holding the input frames (``frames``: 5 PNG frames of 48 x 64, never changed by a case), the shot
    painted whole from them (``whole``) and frames 1-2 painted as stills by ``core batch`` (``stills``); each case
    works in a folder of its own (``folder``)."""

    def __init__(self, root: Path):
        self.root = Path(root)
        self.frames = self.root / "in"
        write_moving_frames(self.frames, COUNT, shape=SHAPE)
        self.whole = self.root / "whole"
        painted(sequence([self.frames], self.whole))
        self.stills = self.root / "stills"
        painted(batch(self.first_two(), self.stills))
        self._cases = 0

    def first_two(self) -> List[Path]:
        return [self.frames / FRAME.format(n) for n in (1, 2)]

    def folder(self) -> Path:
        """A new folder (not yet created) for one case."""
        self._cases += 1
        return self.root / "cases" / f"{self._cases:03d}"

    def frames_copy(self, folder: Path) -> Path:
        """A copy of the input frames in ``folder`` / "in"."""
        shutil.copytree(self.frames, folder / "in")
        return folder / "in"

    def whole_copy(self, folder: Path) -> Path:
        """A copy of the shot painted whole, at ``folder`` / "out"."""
        shutil.copytree(self.whole, folder / "out")
        return folder / "out"


def core(*arguments, preexec_fn=None, timeout: float = 600) -> subprocess.CompletedProcess:
    """``python -m core ARGUMENTS`` in a process of its own, run to its end."""
    return subprocess.run(command(*arguments), capture_output=True, text=True, timeout=timeout, cwd=ROOT,
                          env=environment(), preexec_fn=preexec_fn)


def command(*arguments) -> List[str]:
    return [sys.executable, "-m", "core", *map(str, arguments)]


def environment() -> dict:
    return dict(os.environ, PYTHONPATH=str(ROOT), PYTHONDONTWRITEBYTECODE="1")


def sequence_arguments(inputs, out, *options) -> list:
    return ["sequence", *inputs, "-o", out, "-q", "--seed", SEED, *options]


def sequence(inputs, out, *options, **kwargs) -> subprocess.CompletedProcess:
    return core(*sequence_arguments(inputs, out, *options), **kwargs)


def batch(inputs, out, *options, **kwargs) -> subprocess.CompletedProcess:
    return core("batch", *inputs, "-o", out, "-q", "--seed", SEED, *options, **kwargs)


def started(arguments) -> subprocess.Popen:
    """``python -m core ARGUMENTS`` started, not waited for."""
    return subprocess.Popen(command(*arguments), cwd=ROOT, env=environment(), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)


# --- the standard --------------------------------------------------------------------------------------------------

def problem_lines(stderr: str) -> List[str]:
    """Lines of ``stderr`` that are not the painter's own one-line notices."""
    return [line for line in stderr.splitlines() if line.strip() and not line.startswith("paint-relief: ")]


def refused(run: subprocess.CompletedProcess, *words) -> str:
    """The command ended with exit 2 and one sentence on stderr holding each of ``words``; return the sentence."""
    lines = [line for line in run.stderr.splitlines() if line.strip()]
    assert run.returncode == 2, f"exit {run.returncode}, stderr: {run.stderr[-2000:]}"
    assert len(lines) == 1, f"not one line: {run.stderr[-2000:]}"
    sentence = lines[0]
    assert sentence.startswith("paint-relief: ") and sentence.endswith(".") and "Traceback" not in sentence, sentence
    for word in words:
        assert str(word) in sentence, f"{word!r} is not in: {sentence}"
    return sentence


def painted(run: subprocess.CompletedProcess) -> str:
    """The command ended with exit 0 and nothing on stderr but the painter's notices; return stderr."""
    assert run.returncode == 0, f"exit {run.returncode}, stderr: {run.stderr[-2000:]}"
    assert not problem_lines(run.stderr), run.stderr[-2000:]
    return run.stderr


def stopped(run: subprocess.CompletedProcess, out: Path, *words) -> None:
    """The command either painted the whole shot, or ended with one sentence (``words`` in it) leaving complete
    frames only in ``out``."""
    if run.returncode == 0:
        painted(run)
    else:
        refused(run, *words)
    complete(out)


def snapshot(folder: Path) -> Optional[Dict[str, bytes]]:
    """{relative path: bytes} of everything under ``folder``, hidden files included; None when it is not there."""
    if not folder.exists() and not folder.is_symlink():
        return None
    if folder.is_file():
        return {"": folder.read_bytes()}
    return {str(p.relative_to(folder)): (p.read_bytes() if p.is_file() else b"<folder>")
            for p in sorted(folder.rglob("*"))}


def untouched(folder: Path, before) -> None:
    assert snapshot(folder) == before, f"{folder} was changed"


def leftovers(out: Path) -> List[str]:
    """Staging folders, temporary files and locks left in ``out``."""
    return sorted(p.name for p in out.iterdir()
                  if p.name.startswith((STAGING_PREFIX, ".paint-relief")) or ".tmp" in p.name)


def complete(out: Path) -> None:
    """``out`` holds complete frames only: every frame report.json lists is vouched for by ``ShotFolder.check``
    with nothing to repair, the lives file ends at its committed length, and nothing is left half-written."""
    if not (out / "report.json").exists():
        assert not out.exists() or not [p for p in out.iterdir() if p.name.startswith(("painting_", "color_"))], \
            f"{out} holds maps but no report.json"
        return
    report = read_report(out)
    resume = ShotFolder(out).check(report)
    assert resume.keep == len(report["frames"]) and not resume.cut and not resume.problems, resume
    assert (out / LIVES_FILE).stat().st_size == report["lives"]["bytes"]
    assert not leftovers(out), leftovers(out)


def plain_report(folder: Path, inputs: bool = True) -> dict:
    """report.json of ``folder`` without its seconds (and without the input frames' paths unless ``inputs``)."""
    report = json.loads((folder / "report.json").read_text())
    report.pop("seconds")
    if not inputs:
        report.pop("input")
    for entry in report["per_frame"]:
        entry.pop("seconds")
        if not inputs:
            entry.pop("input")
    return report


def same_as(out: Path, reference: Path, inputs: bool = True) -> None:
    """``out`` holds the bytes of ``reference`` and the same report but for seconds (and the frames' paths when
    the frames were copied elsewhere: ``inputs`` False)."""
    mine, theirs = folder_bytes(out), folder_bytes(reference)
    differ = sorted(name for name in set(mine) | set(theirs) if mine.get(name) != theirs.get(name))
    assert not differ, f"{out} and {reference} differ in {differ}"
    assert plain_report(out, inputs) == plain_report(reference, inputs), f"{out}/report.json differs"
    assert not leftovers(out), leftovers(out)


def whole_or_as_it_was(place: Place, out: Path) -> None:
    """The shot run into ``out`` either paints to the bytes of the shot painted whole, or is refused in one
    sentence naming ``out`` and leaves it as it was."""
    before = snapshot(out)
    run = sequence([place.frames], out)
    if run.returncode == 0:
        painted(run)
        same_as(out, place.whole)
    else:
        refused(run, out)
        untouched(out, before)


def goes_on(place: Place, inputs, out: Path, reference: Optional[Path] = None, *options) -> None:
    """The same command run again paints to the bytes of the shot painted whole."""
    painted(sequence(inputs, out, *options))
    same_as(out, reference or place.whole, inputs=[str(p) for p in inputs] == [str(place.frames)])


def without_root_override():
    """In the child: drop CAP_DAC_OVERRIDE and CAP_DAC_READ_SEARCH, so root meets file permissions too."""
    import ctypes

    libc = ctypes.CDLL(None, use_errno=True)
    for capability in (1, 2):
        if libc.prctl(24, capability, 0, 0, 0) != 0:  # PR_CAPBSET_DROP
            raise OSError(ctypes.get_errno(), "prctl(PR_CAPBSET_DROP) failed")


def as_user() -> dict:
    """Keyword arguments that make a command meet file permissions as a user would, root or not."""
    return {"preexec_fn": without_root_override} if os.geteuid() == 0 else {}


def committed_frames(out: Path) -> int:
    """How many frames report.json of ``out`` lists (0 when it cannot be read)."""
    try:
        return len(json.loads((out / "report.json").read_text())["frames"])
    except (OSError, ValueError, KeyError, TypeError):
        return 0


def stop_when(process: subprocess.Popen, ready: Callable[[], bool], then: Callable[[], None],
              hang: float = 600) -> None:
    """Call ``then`` once ``ready()`` holds while ``process`` runs; do nothing when it ends first. What a case asserts
    after it holds whether ``then`` came at once or later, or never; ``hang`` seconds only guard against a hang."""
    deadline = time.monotonic() + hang
    while process.poll() is None:
        assert time.monotonic() < deadline, f"{' '.join(map(str, process.args))} ran past {hang} s"
        if ready():
            then()
            return
        time.sleep(0.01)


def finish(process: subprocess.Popen) -> subprocess.CompletedProcess:
    out, err = process.communicate(timeout=600)  # a hang guard
    return subprocess.CompletedProcess(process.args, process.returncode, out, err)


@contextlib.contextmanager
def small_disk(folder: Path, size: str):
    """A tmpfs of ``size`` mounted at ``folder`` for the block (Skipped where mounting is not permitted)."""
    folder.mkdir(parents=True, exist_ok=True)
    mount = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(folder)],
                           capture_output=True, text=True)
    if mount.returncode != 0:
        raise Skipped(f"a tmpfs cannot be mounted here ({mount.stderr.strip() or 'mount failed'})")
    try:
        yield folder
    finally:
        subprocess.run(["umount", "-l", str(folder)], capture_output=True)


def room(disk: Path, size: str = "16m") -> None:
    """Grow the tmpfs at ``disk`` to ``size``."""
    subprocess.run(["mount", "-o", f"remount,size={size}", str(disk)], check=True, capture_output=True)


# --- frames --------------------------------------------------------------------------------------------------------

def refuses_frames(place: Place, inputs, *words, options=(), **kwargs) -> None:
    """The shot of ``inputs`` is refused in one sentence and no output folder is made."""
    out = place.folder() / "out"
    refused(sequence(inputs, out, *options, **kwargs), *words)
    assert not out.exists(), f"{out} was made"


def damaged_frames(place: Place, change: Callable[[Path], None]):
    """A copy of the frames with ``change`` applied to the folder; returns (frames folder, output folder)."""
    folder = place.folder()
    frames = place.frames_copy(folder)
    change(frames)
    return frames, folder / "out"


@case("frames", "the folder of frames does not exist")
def _(place):
    refuses_frames(place, [place.root / "nowhere"], place.root / "nowhere", "does not exist")


@case("frames", "the folder of frames is empty")
def _(place):
    empty = place.folder()
    empty.mkdir(parents=True)
    refuses_frames(place, [empty], empty)


@case("frames", "the folder holds no image")
def _(place):
    folder = place.folder()
    folder.mkdir(parents=True)
    (folder / "notes.txt").write_text("frames to come")
    refuses_frames(place, [folder], folder)


@case("frames", "a pattern that matches no file")
def _(place):
    refuses_frames(place, [place.frames / "shot_####.png"], "shot_####.png")


@case("frames", "a pattern with two runs of #")
def _(place):
    refuses_frames(place, [place.frames / "frame_##_##.png"], "frame_##_##.png")


@case("frames", "an empty frame in the middle")
def _(place):
    frames, out = damaged_frames(place, lambda f: (f / FRAME.format(3)).write_bytes(b""))
    refuses_frames(place, [frames], FRAME.format(3))


@case("frames", "a text file named as a frame")
def _(place):
    frames, out = damaged_frames(place, lambda f: (f / FRAME.format(3)).write_text("not a picture"))
    refuses_frames(place, [frames], FRAME.format(3))


@case("frames", "a frame cut short after its header")
def _(place):
    def cut(folder):
        data = (folder / FRAME.format(3)).read_bytes()
        (folder / FRAME.format(3)).write_bytes(data[:len(data) // 2])
    frames, out = damaged_frames(place, cut)
    run = sequence([frames], out)
    if run.returncode == 0:
        raise AssertionError("a frame cut short was painted")
    refused(run, FRAME.format(3))
    complete(out)
    shutil.copyfile(place.frames / FRAME.format(3), frames / FRAME.format(3))
    goes_on(place, [frames], out)


@case("frames", "a frame of another size")
def _(place):
    frames, _ = damaged_frames(place, lambda f: writing.write_png(f / FRAME.format(4), np.full((40, 64, 3), 0.5)))
    refuses_frames(place, [frames], FRAME.format(4))


@case("frames", "a frame that is a dangling link")
def _(place):
    def link(folder):
        (folder / FRAME.format(3)).unlink()
        (folder / FRAME.format(3)).symlink_to(folder / "gone.png")
    frames, _ = damaged_frames(place, link)
    refuses_frames(place, [frames], FRAME.format(3))


@case("frames", "a frame that cannot be read")
def _(place):
    frames, _ = damaged_frames(place, lambda f: os.chmod(f / FRAME.format(3), 0))
    refuses_frames(place, [frames], FRAME.format(3), **as_user())


@case("frames", "a folder named as a frame")
def _(place):
    def folder_frame(folder):
        (folder / FRAME.format(6)).mkdir()
    frames, out = damaged_frames(place, folder_frame)
    run = sequence([frames], out)
    if run.returncode == 0:
        painted(run)
        same_as(out, place.whole, inputs=False)
    else:
        refused(run, FRAME.format(6))
        assert not out.exists()


@case("frames", "grey frames")
def _(place):
    def grey(folder):
        for n in range(1, COUNT + 1):
            rgb = read_png(folder / FRAME.format(n))
            writing.write_png(folder / FRAME.format(n), rgb.mean(axis=2))
    frames, out = damaged_frames(place, grey)
    painted(sequence([frames], out))
    complete(out)


@case("frames", "frames with an alpha channel")
def _(place):
    def rgba(folder):
        for n in range(1, COUNT + 1):
            rgb = read_png(folder / FRAME.format(n))
            writing.write_png(folder / FRAME.format(n), np.dstack([rgb, np.full(rgb.shape[:2], 0.5)]))
    frames, out = damaged_frames(place, rgba)
    painted(sequence([frames], out))
    complete(out)


@case("frames", "a gap in the frame numbers")
def _(place):
    frames, out = damaged_frames(place, lambda f: (f / FRAME.format(3)).unlink())
    run = sequence([frames], out)
    stopped(run, out, "3")
    if run.returncode == 0:
        assert read_report(out)["frames"] == [1, 2, 4, 5]


@case("frames", "two files of one frame number")
def _(place):
    frames, out = damaged_frames(place, lambda f: shutil.copyfile(f / FRAME.format(2), f / "frame_2.png"))
    run = sequence([frames], out)
    if run.returncode == 0:
        raise AssertionError("two frames numbered 2 were painted")
    refused(run)
    assert not out.exists()


@case("frames", "a frame number of 20 digits")
def _(place):
    frames, _ = damaged_frames(place, lambda f: shutil.copyfile(f / FRAME.format(5), f / f"frame_{10**19}.png"))
    refuses_frames(place, [frames], str(10**19))


for _name, _word, _option, _value in (("--frames beyond the last frame", "--frames", "--frames", "9-12"),
                                      ("--frames backwards", "--frames", "--frames", "4-2"),
                                      ("--frames not a range", "--frames", "--frames", "abc"),
                                      ("--fade-frames 0", "fade", "--fade-frames", "0"),
                                      ("--sizes 0", "sizes", "--sizes", "0")):
    case("frames", _name)(lambda place, w=_word, o=_option, v=_value:
                          refuses_frames(place, [place.frames], w, options=(o, v)))


@case("frames", "a negative seed")
def _(place):
    out = place.folder() / "out"
    refused(core("sequence", place.frames, "-o", out, "-q", "--seed", "-1"), "seed")
    assert not out.exists()


@case("frames", "a method given to the shot")
def _(place):
    refuses_frames(place, [place.frames], "--method", options=("--method", "hertzmann98"))


@case("frames", "frames larger than --max-megapixels")
def _(place):
    refuses_frames(place, [place.frames], options=("--max-megapixels", "0.001"))


@case("frames", "one frame only")
def _(place):
    out = place.folder() / "out"
    painted(sequence([place.frames], out, "--frames", "3"))
    complete(out)
    assert read_report(out)["frames"] == [3]


@case("frames", "folders and names with spaces and accents")
def _(place):
    folder = place.folder() / "plan séquence 01"
    shutil.copytree(place.frames, folder / "prises de vue")
    out = folder / "peinture finie"
    painted(sequence([folder / "prises de vue"], out))
    same_as(out, place.whole, inputs=False)


@case("frames", "a frame whose header claims a huge image")
def _(place):
    def bomb(folder):
        import struct
        import zlib

        def chunk(kind, data):
            return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
        header = struct.pack(">IIBBBBB", 100_000, 100_000, 8, 2, 0, 0, 0)
        (folder / FRAME.format(2)).write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
                                               + chunk(b"IDAT", zlib.compress(b"\0" * 1000)) + chunk(b"IEND", b""))
    frames, _ = damaged_frames(place, bomb)
    refuses_frames(place, [frames], FRAME.format(2), "MB")  # its size from its header, before anything is read


def vector_frames(folder: Path, value: float) -> Path:
    """Three 48 x 64 multilayer EXR frames whose Vector pass holds ``value`` on the upper half and a motion of 2 px
    to the right below."""
    folder.mkdir(parents=True)
    rng = np.random.default_rng(0)
    for number in (1, 2, 3):
        rgba = np.ones(SHAPE + (4,), np.float32)
        rgba[..., :3] = rng.random(SHAPE + (3,), dtype=np.float32)
        vector = np.zeros(SHAPE + (4,), np.float32)
        vector[: SHAPE[0] // 2] = value
        vector[SHAPE[0] // 2:, :, 0] = vector[SHAPE[0] // 2:, :, 2] = -2.0
        write_multilayer(folder / f"frame_{number:04d}.exr", [("ViewLayer.Combined", "RGBA", rgba),
                                                              ("ViewLayer.Vector", "XYZW", vector)])
    return folder


@case("frames", "a Vector pass of 1e30 px")
def _(place):
    folder = place.folder()
    out = folder / "out"
    painted(core("sequence", vector_frames(folder / "in", 1e30), "-o", out, "-q"))
    assert not problem_lines(sequence([folder / "in"], folder / "again").stderr)
    complete(out)


@case("frames", "a Vector pass holding NaN and infinities")
def _(place):
    folder = place.folder()
    frames = vector_frames(folder / "in", float("nan"))
    out = folder / "out"
    stopped(sequence([frames], out), out, "Vector")
    inf = vector_frames(folder / "inf", float("inf"))
    stopped(sequence([inf], folder / "out_inf"), folder / "out_inf", "Vector")


@case("frames", "tiny frames of 6 x 8")
def _(place):
    folder = place.folder()
    (folder / "in").mkdir(parents=True)
    for n in (1, 2, 3):
        writing.write_png(folder / "in" / FRAME.format(n), np.random.default_rng(n).random((6, 8, 3)))
    out = folder / "out"
    run = sequence([folder / "in"], out)
    if run.returncode == 0:
        painted(run)
        complete(out)
    else:
        refused(run)
        assert not out.exists()


@case("frames", "one file given twice")
def _(place):
    one = place.frames / FRAME.format(1)
    out = place.folder() / "out"
    run = sequence([one, one], out)
    if run.returncode == 0:
        painted(run)
        complete(out)
    else:
        refused(run, FRAME.format(1))
        assert not out.exists()


@case("frames", "a frame changed after it was painted")
def _(place):
    folder = place.folder()
    frames = place.frames_copy(folder)
    out = folder / "out"
    painted(sequence([frames], out, "--frames", "1-3"))
    writing.write_png(frames / FRAME.format(2), read_png(frames / FRAME.format(2))[::-1])
    before = snapshot(out)
    run = sequence([frames], out)
    if run.returncode == 0:
        painted(run)
        complete(out)
        assert read_report(out)["per_frame"][1]["input_sha256"] != json.loads(
            before["report.json"])["per_frame"][1]["input_sha256"], "frame 2 was not painted again"
    else:
        refused(run, FRAME.format(2))
        untouched(out, before)


def read_png(path: Path) -> np.ndarray:
    from core.files.reading import read_image

    return read_image(str(path))


# --- output folders ------------------------------------------------------------------------------------------------

@case("output", "-o is a file")
def _(place):
    out = place.folder()
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("a file")
    refused(sequence([place.frames], out), out)
    assert out.read_text() == "a file"


@case("output", "-o inside a file")
def _(place):
    blocker = place.folder()
    blocker.parent.mkdir(parents=True, exist_ok=True)
    blocker.write_text("a file")
    refused(sequence([place.frames], blocker / "out"), blocker)
    assert blocker.read_text() == "a file"


@case("output", "-o is the folder of frames")
def _(place):
    folder = place.folder()
    frames = place.frames_copy(folder)
    before = snapshot(frames)
    refused(sequence([frames], frames), frames)
    untouched(frames, before)


@case("output", "-o inside the folder of frames, run twice")
def _(place):
    folder = place.folder()
    frames = place.frames_copy(folder)
    painted(sequence([frames], frames / "painted"))
    painted(sequence([frames], frames / "painted"))
    same_as(frames / "painted", place.whole, inputs=False)


@case("output", "-o empty")
def _(place):
    refused(sequence([place.frames], ""), "output")


@case("output", "-o a folder that cannot be written")
def _(place):
    out = place.folder()
    out.mkdir(parents=True)
    (out / "notes.txt").write_text("mine")
    os.chmod(out, 0o555)
    try:
        before = snapshot(out)
        refused(sequence([place.frames], out, **as_user()), out)
        untouched(out, before)
    finally:
        os.chmod(out, 0o755)


@case("output", "-o holds a still painting")
def _(place):
    out = place.folder()
    painted(core("paint", place.frames / FRAME.format(1), "-o", out, "-q"))
    before = snapshot(out)
    refused(sequence([place.frames], out), out, "still")
    untouched(out, before)


@case("output", "-o holds the shot painted with another seed")
def _(place):
    out = place.folder() / "out"
    painted(core(*sequence_arguments([place.frames], out)[:-2], "--seed", "8"))
    before = snapshot(out)
    refused(sequence([place.frames], out), out)
    untouched(out, before)


@case("output", "-o holds the shot painted with other sizes")
def _(place):
    out = place.folder() / "out"
    painted(sequence([place.frames], out, "--sizes", "32,16,8"))
    before = snapshot(out)
    refused(sequence([place.frames], out), out)
    untouched(out, before)


@case("output", "-o holds another shot's frames")
def _(place):
    folder = place.folder()
    other = place.frames_copy(folder)
    for n in range(1, COUNT + 1):
        writing.write_png(other / FRAME.format(n), read_png(other / FRAME.format(n))[:, ::-1])
    out = folder / "out"
    painted(sequence([other], out, "--frames", "1-3"))
    whole_or_as_it_was(place, out)


@case("output", "-o holds files of the user's")
def _(place):
    out = place.folder() / "out"
    out.mkdir(parents=True)
    (out / "notes.txt").write_text("mine")
    (out / "painting_0001.txt").write_text("also mine")
    painted(sequence([place.frames], out))
    assert (out / "notes.txt").read_text() == "mine" and (out / "painting_0001.txt").read_text() == "also mine"
    (out / "notes.txt").unlink()
    (out / "painting_0001.txt").unlink()
    same_as(out, place.whole)


@case("output", "-o holds a staging folder left by a killed run")
def _(place):
    out = place.folder() / "out"
    staging = out / f"{STAGING_PREFIX}12345-abcdef"
    staging.mkdir(parents=True)
    (staging / "painting_0001.png").write_bytes(b"half")
    painted(sequence([place.frames], out))
    same_as(out, place.whole)


@case("output", "a folder where frame 3's painting goes")
def _(place):
    out = place.folder() / "out"
    (out / "painting_0003.png").mkdir(parents=True)
    before = snapshot(out)
    run = sequence([place.frames], out)
    refused(run, "painting_0003.png")
    untouched(out, before)


@case("output", "a complete shot run again")
def _(place):
    out = place.whole_copy(place.folder())
    before = snapshot(out)
    painted(sequence([place.frames], out))
    untouched(out, before)


@case("output", "a narrower --frames after a complete shot")
def _(place):
    out = place.whole_copy(place.folder())
    before = snapshot(out)
    painted(sequence([place.frames], out, "--frames", "1-3"))
    refused(sequence([place.frames], out, "--frames", "2-3"), out, "frames 1 to 5", "frames 2 to 3")
    untouched(out, before)


@case("damage", "the state of frame 3 and a run of frames 1-3")
def _(place):
    folder = place.folder()
    out = place.whole_copy(folder)
    painted(sequence([place.frames], folder / "part", "--frames", "1-3"))
    shutil.copyfile(folder / "part" / STATE_FILE, out / STATE_FILE)
    said = painted(sequence([place.frames], out, "--frames", "1-3"))
    assert "the frames after frame 3 are dropped" in said, said
    same_as(out, folder / "part")


@case("output", "-o a link to a folder")
def _(place):
    folder = place.folder()
    (folder / "real").mkdir(parents=True)
    (folder / "link").symlink_to(folder / "real")
    painted(sequence([place.frames], folder / "link"))
    same_as(folder / "real", place.whole)


@case("output", "the folder made read-only mid-shot")
def _(place):
    out = place.folder() / "out"
    out.mkdir(parents=True)
    process = subprocess.Popen(command(*sequence_arguments([place.frames], out)), cwd=ROOT, env=environment(),
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **as_user())
    try:
        stop_when(process, lambda: committed_frames(out) >= 2, lambda: os.chmod(out, 0o555))
        run = finish(process)
    finally:
        os.chmod(out, 0o755)
    settle(out)  # as a reader finds it: what the read-only folder kept of its last commit finished, its lock gone
    stopped(run, out, out, "permission denied")
    goes_on(place, [place.frames], out)


@case("output", "the folder deleted mid-shot")
def _(place):
    out = place.folder() / "out"
    process = started(sequence_arguments([place.frames], out))
    stop_when(process, lambda: committed_frames(out) >= 2, lambda: shutil.rmtree(out, ignore_errors=True))
    run = finish(process)
    if out.exists():
        stopped(run, out, out)
    elif run.returncode != 0:
        refused(run, out)
    goes_on(place, [place.frames], out)


@case("output", "the disk unmounted mid-shot")
def _(place):
    disk = place.folder() / "disk"
    with small_disk(disk, "16m"):
        out = disk / "out"
        process = started(sequence_arguments([place.frames], out))
        stop_when(process, lambda: committed_frames(out) >= 2,
                  lambda: subprocess.run(["umount", "-l", str(disk)], capture_output=True))
        run = finish(process)
    if run.returncode != 0:
        refused(run, out)
    if out.exists():
        complete(out)
    goes_on(place, [place.frames], out)


@case("output", "two runs into one folder at once")
def _(place):
    out = place.folder() / "out"
    first = started(sequence_arguments([place.frames], out))
    stop_when(first, lambda: (out / "report.json").exists() or any(out.glob(f"{STAGING_PREFIX}*")),
              lambda: None)
    second = sequence([place.frames], out)
    first_run = finish(first)
    for run in (first_run, second):
        if run.returncode != 0:
            refused(run, out)
    complete(out)
    goes_on(place, [place.frames], out)


# --- kills ---------------------------------------------------------------------------------------------------------

def killed_at(place: Place, fraction: float, signum: int = signal.SIGKILL) -> None:
    """Start the shot, send ``signum`` at ``fraction`` of a whole run's time, then check what is left and go on.

    Where the signal lands changes from run to run, so what is asserted holds at every moment: after SIGTERM or
    SIGINT the folder holds complete frames only and nothing half-written; after SIGKILL the folder is read as
    its readers read it (``crash_points.read_shot``: the maps of every frame report.json lists, then, settled, a
    folder ``ShotFolder.check`` vouches for whole). Every write boundary of the shot is crashed one by one in
    ``tests/crash_points.py``."""
    out = place.folder() / "out"
    began = time.monotonic()
    painted(sequence([place.frames], place.folder() / "timing"))
    whole_seconds = time.monotonic() - began
    process = started(sequence_arguments([place.frames], out))
    time.sleep(fraction * whole_seconds)
    process.send_signal(signum)
    run = finish(process)
    if signum != signal.SIGKILL and run.returncode not in (0,):
        lines = [line for line in run.stderr.splitlines() if line.strip()]
        assert run.returncode in (2, 128 + signum, -signum), (run.returncode, run.stderr)
        assert len(lines) <= 1 and not problem_lines(run.stderr), run.stderr
        if out.exists():
            complete(out)
    elif signum == signal.SIGKILL:
        read_shot(out)
    goes_on(place, [place.frames], out)


_moments = random.Random(11)
for _fraction in [_moments.uniform(0.3 + 0.12 * k, 0.42 + 0.12 * k) for k in range(6)]:  # one in each sixth
    case("kills", f"SIGKILL at {_fraction:.3f} of a run")(lambda place, f=_fraction: killed_at(place, f))

case("kills", "SIGTERM mid-shot")(lambda place: killed_at(place, 0.7, signal.SIGTERM))
case("kills", "SIGINT mid-shot")(lambda place: killed_at(place, 0.7, signal.SIGINT))


@case("kills", "SIGKILL while a damaged folder is repaired")
def _(place):
    out = place.whole_copy(place.folder())
    (out / "height_0002.exr").unlink()
    process = started(sequence_arguments([place.frames], out))
    time.sleep(0.9)
    process.kill()
    finish(process)
    goes_on(place, [place.frames], out)


@case("kills", "SIGKILL of a batch")
def _(place):
    out = place.folder() / "out"
    process = started(["batch", *place.first_two(), "-o", out, "-q", "--seed", SEED])
    stop_when(process, lambda: any(p.name.endswith("_001") for p in out.glob("*")) if out.exists() else False,
              process.kill)
    finish(process)
    said = painted(batch(place.first_two(), out))
    assert "paint-relief: batch: kept " in said, said
    assert sorted(p.name for p in out.iterdir()) == ["frame_0001_001", "frame_0002_001"], \
        "the batch run again painted into new folders"
    for folder in sorted(out.iterdir()):
        assert folder_bytes(folder) == folder_bytes(place.stills / folder.name), folder
        assert not leftovers(folder), leftovers(folder)


@case("kills", "SIGKILL of a batch holding a shot, after its second frame")
def _(place):
    out = place.folder() / "out"
    shot = out / f"{place.frames.name}_001"
    arguments = ["batch", place.frames / FRAME.format(1), place.frames, "-o", out, "-q", "--seed", SEED]
    process = started(arguments)
    stop_when(process, lambda: committed_frames(shot) >= 2, process.kill)
    finish(process)
    said = painted(core(*arguments))
    assert "went on with 1" in said or "kept 2" in said, said
    assert sorted(p.name for p in out.iterdir()) == ["frame_0001_001", shot.name], sorted(out.iterdir())
    assert folder_bytes(out / "frame_0001_001") == folder_bytes(place.stills / "frame_0001_001")
    same_as(shot, place.whole)


# --- damaged and stale files ---------------------------------------------------------------------------------------

def repaired(place: Place, damage: Callable[[Path], None], *words) -> None:
    """The shot painted whole, damaged by ``damage``: the next run says in one line what it repaired (``words`` in
    it) and paints to the bytes of the shot painted whole."""
    out = place.whole_copy(place.folder())
    damage(out)
    run = sequence([place.frames], out)
    said = painted(run).strip()
    assert said.count("\n") == 0 and said.startswith("paint-relief: Repaired"), said
    for word in words:
        assert word in said, (word, said)
    same_as(out, place.whole)


def refused_folder(place: Place, damage: Callable[[Path], None], *words) -> None:
    """The shot painted whole, damaged by ``damage``: refused in one sentence naming the file, folder unchanged."""
    out = place.whole_copy(place.folder())
    damage(out)
    before = snapshot(out)
    refused(sequence([place.frames], out), *words)
    untouched(out, before)


def flip(path: Path, at: float = 0.5) -> None:
    data = bytearray(path.read_bytes())
    data[int(len(data) * at)] ^= 0x20
    path.write_bytes(bytes(data))


def cut(path: Path, keep: float = 0.5) -> None:
    path.write_bytes(path.read_bytes()[: int(path.stat().st_size * keep)])


case("damage", "a painting deleted")(lambda p: repaired(p, lambda o: (o / "painting_0004.png").unlink(),
                                                        "painting_0004.png"))
case("damage", "a height map cut short")(lambda p: repaired(p, lambda o: cut(o / "height_0002.exr"),
                                                            "height_0002.exr"))
case("damage", "a byte flipped in a colour map")(lambda p: repaired(p, lambda o: flip(o / "color_0003.exr"),
                                                                    "color_0003.exr"))
case("damage", "frame 1's painting put in place of frame 5's")(
    lambda p: repaired(p, lambda o: shutil.copyfile(o / "painting_0001.png", o / "painting_0005.png"),
                       "painting_0005.png"))
case("damage", "an orientation map emptied")(
    lambda p: repaired(p, lambda o: (o / "orientation_0001.exr").write_bytes(b""), "orientation_0001.exr"))
case("damage", "the lives file deleted")(lambda p: repaired(p, lambda o: (o / LIVES_FILE).unlink(), LIVES_FILE))
case("damage", "bytes after the lives file's last record")(
    lambda p: repaired(p, lambda o: (o / LIVES_FILE).write_bytes((o / LIVES_FILE).read_bytes() + b"\x07" * 999),
                       LIVES_FILE))
case("damage", "the state deleted")(lambda p: repaired(p, lambda o: (o / STATE_FILE).unlink(), STATE_FILE))


def earlier_state(place: Place):
    def damage(out: Path) -> None:
        early = out.parent / "early"
        painted(sequence([place.frames], early, "--frames", "1-3"))
        shutil.copyfile(early / STATE_FILE, out / STATE_FILE)
    return damage


case("damage", "the state of an earlier frame")(lambda p: repaired(p, earlier_state(p), STATE_FILE))


def first_record_flipped(out: Path) -> None:
    path = out / LIVES_FILE
    start, end = FILE_HEADER.size + 48, int(LivesFile(path).ends()[0]) - 4
    data = bytearray(path.read_bytes())
    data[(start + end) // 2] ^= 0x40
    path.write_bytes(bytes(data))


case("damage", "a byte flipped in the lives file's first record")(
    lambda p: refused_folder(p, first_record_flipped, LIVES_FILE))
case("damage", "the lives file cut inside a record")(
    lambda p: refused_folder(p, lambda o: cut(o / LIVES_FILE, 0.6), LIVES_FILE))
case("damage", "the lives file emptied")(
    lambda p: refused_folder(p, lambda o: (o / LIVES_FILE).write_bytes(b""), LIVES_FILE))
case("damage", "the lives file's header damaged")(
    lambda p: refused_folder(p, lambda o: flip(o / LIVES_FILE, 0.0), LIVES_FILE))
case("damage", "a state of garbage")(
    lambda p: refused_folder(p, lambda o: (o / STATE_FILE).write_bytes(b"\x80\x04garbage" * 300), STATE_FILE))
case("damage", "a state cut short")(lambda p: refused_folder(p, lambda o: cut(o / STATE_FILE), STATE_FILE))
case("damage", "an empty state")(lambda p: refused_folder(p, lambda o: (o / STATE_FILE).write_bytes(b""),
                                                          STATE_FILE))


def other_state(place: Place):
    def damage(out: Path) -> None:
        other = out.parent / "other"
        painted(core(*sequence_arguments([place.frames], other)[:-2], "--seed", "8"))
        shutil.copyfile(other / STATE_FILE, out / STATE_FILE)
    return damage


case("damage", "the state of a shot painted with another seed")(
    lambda p: refused_folder(p, other_state(p), STATE_FILE))
case("damage", "report.json of garbage")(
    lambda p: refused_folder(p, lambda o: (o / "report.json").write_text("{not json"), "report.json"))
case("damage", "report.json a list")(
    lambda p: refused_folder(p, lambda o: (o / "report.json").write_text("[1, 2]"), "report.json"))
case("damage", "report.json cut short")(
    lambda p: refused_folder(p, lambda o: cut(o / "report.json"), "report.json"))
case("damage", "report.json emptied")(
    lambda p: refused_folder(p, lambda o: (o / "report.json").write_text(""), "report.json"))


def report_edit(change: Callable[[dict], None]) -> Callable[[Path], None]:
    def damage(out: Path) -> None:
        report = json.loads((out / "report.json").read_text())
        change(report)
        (out / "report.json").write_text(json.dumps(report))
    return damage


case("damage", "report.json listing a frame twice")(
    lambda p: refused_folder(p, report_edit(lambda r: r["frames"].append(5)), "report.json"))
case("damage", "report.json with a committed length beyond the lives file")(
    lambda p: refused_folder(p, report_edit(lambda r: r["lives"].update(bytes=r["lives"]["bytes"] + 10_000)),
                             LIVES_FILE))


@case("damage", "report.json deleted, the maps kept")
def _(place):
    out = place.whole_copy(place.folder())
    (out / "report.json").unlink()
    whole_or_as_it_was(place, out)


@case("damage", "the maps of frames 4-5 deleted")
def _(place):
    def damage(out):
        for path in out.glob("*_000[45].*"):
            path.unlink()
    repaired(place, damage, "0004")


@case("damage", "a lock left by a killed run")
def _(place):
    out = place.whole_copy(place.folder())
    painted(sequence([place.frames], out, "--frames", "1-2"))
    lock = out / ".paint-relief.lock"
    lock.write_text("99999999")
    run = sequence([place.frames], out)
    painted(run)
    same_as(out, place.whole)


# --- full disks ----------------------------------------------------------------------------------------------------

def full_disk(place: Place, size: str) -> None:
    """The shot painted onto a tmpfs of ``size``: whole, or one sentence naming the folder and that no space is
    left, with complete frames only; given room, the same command goes on to the same bytes."""
    disk = place.folder() / "disk"
    with small_disk(disk, size):
        out = disk / "out"
        run = sequence([place.frames], out)
        if run.returncode != 0:
            refused(run, out, "no space")
        if out.exists():
            complete(out)
        room(disk)
        goes_on(place, [place.frames], out)


for _size in ("24k", "120k", "400k", "650k", "900k", "1200k"):
    case("disk", f"a disk of {_size}")(lambda place, s=_size: full_disk(place, s))


@case("disk", "a batch onto a disk of 60k")
def _(place):
    disk = place.folder() / "disk"
    with small_disk(disk, "60k"):
        out = disk / "out"
        refused(batch(place.first_two(), out), "no space")
        painted_now = sorted(p.name for p in out.iterdir()) if out.exists() else []
        assert not [name for name in painted_now if name.startswith(STAGING_PREFIX)], painted_now
        room(disk)
        painted(batch(place.first_two(), out))
        for folder in out.iterdir():
            stem = folder.name.rsplit("_", 1)[0]
            assert folder_bytes(folder) == folder_bytes(place.stills / f"{stem}_001"), folder


# --- batches -------------------------------------------------------------------------------------------------------

@case("batch", "an input that does not exist")
def _(place):
    out = place.folder()
    refused(batch([place.frames / FRAME.format(1), place.root / "nope.png"], out), "nope.png", "does not exist")
    assert not out.exists()


@case("batch", "an input that is not an image")
def _(place):
    folder = place.folder()
    folder.mkdir(parents=True)
    (folder / "notes.png").write_text("words")
    refused(batch([place.frames / FRAME.format(1), folder / "notes.png"], folder / "out"), "notes.png")
    assert not (folder / "out").exists()


@case("batch", "OUTROOT is a file")
def _(place):
    out = place.folder()
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("a file")
    refused(batch(place.first_two(), out), out)
    assert out.read_text() == "a file"


@case("batch", "one image given twice")
def _(place):
    out = place.folder()
    one = place.frames / FRAME.format(1)
    painted(batch([one, one], out))
    for name in ("frame_0001_001", "frame_0001_002"):
        assert folder_bytes(out / name) == folder_bytes(place.stills / "frame_0001_001")


@case("batch", "run twice into one OUTROOT, then with another seed and with --fresh")
def _(place):
    out = place.folder()
    painted(batch(place.first_two(), out))
    before = snapshot(out)
    said = painted(batch(place.first_two(), out))
    assert "paint-relief: batch: kept 2, went on with 0, painted 0." in said, said
    untouched(out, before)
    painted(core("batch", *place.first_two(), "-o", out, "-q", "--seed", SEED + 1))
    painted(batch(place.first_two(), out, "--fresh"))
    assert sorted(p.name for p in out.iterdir()) == [f"frame_000{n}_00{k}" for n in (1, 2) for k in (1, 2, 3)]
    for name in ("frame_0001_003", "frame_0002_003"):
        assert folder_bytes(out / name) == folder_bytes(place.stills / name.replace("_003", "_001")), name
    assert {p: before[p] for p in before} == {p: v for p, v in snapshot(out).items() if p in before}


@case("batch", "an image cut short")
def _(place):
    folder = place.folder()
    shutil.copytree(place.frames, folder / "in")
    cut(folder / "in" / FRAME.format(2))
    out = folder / "out"
    run = batch([folder / "in" / FRAME.format(1), folder / "in" / FRAME.format(2)], out)
    refused(run, FRAME.format(2))
    if out.exists():
        for painting in out.iterdir():
            assert painting.name == "frame_0001_001", painting
            assert folder_bytes(painting) == folder_bytes(place.stills / "frame_0001_001")


@case("batch", "-o empty")
def _(place):
    refused(batch(place.first_two(), ""), "output")


@case("batch", "a negative seed")
def _(place):
    out = place.folder()
    refused(core("batch", *place.first_two(), "-o", out, "-q", "--seed", "-3"), "seed")
    assert not out.exists()


@case("batch", "a folder of frames as an input is a shot")
def _(place):
    out = place.folder()
    painted(batch([place.frames], out))
    same_as(out / "in_001", place.whole)


@case("batch", "OUTROOT that cannot be written")
def _(place):
    out = place.folder()
    out.mkdir(parents=True)
    os.chmod(out, 0o555)
    try:
        refused(batch(place.first_two(), out, **as_user()), out)
        assert not list(out.iterdir())
    finally:
        os.chmod(out, 0o755)


# --- the farm ------------------------------------------------------------------------------------------------------

def refused_by_address(place: Place, address: str, *words) -> None:
    """The shot on the scheduler at ``address`` is refused in one sentence holding ``words``, and nothing is
    painted. Whether the refusal waits for a timeout (a port that says nothing) is the farm's; the command's own
    timeout only guards against a hang."""
    out = place.folder() / "out"
    refused(sequence([place.frames], out, "--scheduler", address), *words)
    assert not out.exists() or not any(out.iterdir())


def need_dask() -> None:
    try:
        import distributed  # noqa: F401
    except ImportError:
        raise Skipped("Dask's distributed is not installed") from None


@contextlib.contextmanager
def listening(respond: bytes = b""):
    """A TCP server on 127.0.0.1 that is no Dask scheduler: it answers ``respond`` and closes; yields its port."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen()
    stop = threading.Event()

    def serve():
        server.settimeout(0.2)
        while not stop.is_set():
            try:
                connection, _ = server.accept()
            except OSError:
                continue
            with connection:
                with contextlib.suppress(OSError):
                    connection.sendall(respond)
    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    try:
        yield server.getsockname()[1]
    finally:
        stop.set()
        thread.join()
        server.close()


def a_closed_port(place: Place) -> None:
    from dask_cluster import closed_port

    with closed_port() as port:
        refused_by_address(place, f"tcp://127.0.0.1:{port}", "refused")


case("farm", "an address with a port that is no number", True)(
    lambda p: refused_by_address(p, "tcp://127.0.0.1:notaport", "notaport"))
case("farm", "an address with spaces", True)(lambda p: refused_by_address(p, "my render box", "my render box"))
case("farm", "an address with a port beyond 65535", True)(
    lambda p: refused_by_address(p, "tcp://127.0.0.1:70000", "70000"))
case("farm", "an address of another protocol", True)(
    lambda p: refused_by_address(p, "http://127.0.0.1:8786", "http://127.0.0.1:8786"))
case("farm", "a closed port", True)(a_closed_port)
case("farm", "a host that does not exist", True)(
    lambda p: refused_by_address(p, "tcp://no-such-host.invalid:8786", "no-such-host.invalid"))


@case("farm", "a port where a web server listens", True)
def _(place):
    with listening(b"HTTP/1.0 200 OK\r\n\r\nhello") as port:
        refused_by_address(place, f"tcp://127.0.0.1:{port}", str(port))


@case("farm", "a port that accepts and says nothing", True)
def _(place):
    with listening() as port:
        refused_by_address(place, f"tcp://127.0.0.1:{port}", str(port))


@case("farm", "--workers 0")
def _(place):
    refuses_frames(place, [place.frames], "workers", options=("--workers", "0"))


@case("farm", "--workers and --scheduler together")
def _(place):
    refuses_frames(place, [place.frames], "--scheduler", options=("--workers", "2", "--scheduler", "x:1"))


@case("farm", "two local workers paint the bytes of one process", True)
def _(place):
    need_dask()
    out = place.folder() / "out"
    painted(sequence([place.frames], out, "--workers", "2"))
    same_as(out, place.whole)


def dask_cluster(place: Place, **options):
    need_dask()
    from dask_cluster import cluster

    return cluster(place.folder() / "cluster", **options)


@case("farm", "a scheduler of two workers paints the bytes of one process", True)
def _(place):
    with dask_cluster(place, workers=2) as dask:
        out = place.folder() / "out"
        painted(sequence([place.frames], out, "--scheduler", dask.address))
    same_as(out, place.whole)


@case("farm", "a worker without the painter", True)
def _(place):
    from dask_cluster import Worker

    with dask_cluster(place, workers=1, worker=Worker(painter=False)) as dask:
        out = place.folder() / "out"
        refused(sequence([place.frames], out, "--scheduler", dask.address), "cannot import the painter",
                "pip install")
    assert not out.exists() or not any(out.iterdir())


@case("farm", "a worker with another NumPy", True)
def _(place):
    from dask_cluster import Worker

    oldest = ROOT / ".venv-numpy1" / "bin" / "python"
    if not oldest.exists():
        raise Skipped(f"{oldest} is not made (make .venv-numpy1/.installed)")
    theirs = subprocess.run([str(oldest), "-c", "import distributed, numpy; print(numpy.__version__)"],
                            capture_output=True, text=True, timeout=600)
    if theirs.returncode != 0 or theirs.stdout.strip() == np.__version__:
        raise Skipped(f"{oldest} runs the NumPy of this interpreter, or no Dask")
    with dask_cluster(place, workers=1, worker=Worker(python=str(oldest))) as dask:
        out = place.folder() / "out"
        refused(sequence([place.frames], out, "--scheduler", dask.address), "NumPy")
    assert not out.exists() or not any(out.iterdir())


@case("farm", "a worker killed mid-shot", True)
def _(place):
    with dask_cluster(place, workers=2) as dask:
        out = place.folder() / "out"
        process = started(sequence_arguments([place.frames], out, "--scheduler", dask.address))
        stop_when(process, lambda: committed_frames(out) >= 1, lambda: dask.workers[0].kill())
        run = finish(process)
        stopped(run, out, out)
        painted(sequence([place.frames], out, "--scheduler", dask.address))
    same_as(out, place.whole)


@case("farm", "the farm's command killed, then resumed in one process", True)
def _(place):
    need_dask()
    out = place.folder() / "out"
    process = started(sequence_arguments([place.frames], out, "--workers", "2"))
    stop_when(process, lambda: committed_frames(out) >= 2, process.kill)
    finish(process)
    goes_on(place, [place.frames], out)


@case("farm", "a batch on two local workers", True)
def _(place):
    need_dask()
    out = place.folder()
    painted(batch(place.first_two(), out, "--workers", "2"))
    for name in ("frame_0001_001", "frame_0002_001"):
        assert folder_bytes(out / name) == folder_bytes(place.stills / name), name


@case("farm", "SIGTERM of a batch of two shots painted at once", True)
def _(place):
    need_dask()
    out = place.folder() / "out"
    first = out / f"{Path(place.frames).name}_001"
    process = started(["batch", place.frames, place.frames, "-o", out, "-q", "--seed", SEED, "--workers", "2"])
    stop_when(process, lambda: (first / "report.json").exists(), lambda: process.send_signal(signal.SIGTERM))
    run = finish(process)
    if run.returncode != 0:
        lines = [line for line in run.stderr.splitlines() if line.strip()]
        assert run.returncode == 128 + signal.SIGTERM, (run.returncode, run.stderr)
        assert len(lines) == 1 and "the same command goes on" in lines[0] and not problem_lines(run.stderr), \
            run.stderr
    for folder in (first, out / f"{Path(place.frames).name}_002"):
        complete(folder)
        goes_on(place, [place.frames], folder)


# --- running the catalogue -----------------------------------------------------------------------------------------

def run_case(place: Place, one: Case) -> None:
    """Run ``one``; AssertionError when it falls short of the standard, Skipped when it cannot run here."""
    one.run(place)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", help="run the cases whose group or name holds this word")
    parser.add_argument("--list", action="store_true", help="list the cases and stop")
    parser.add_argument("--keep", type=Path, help="work in this folder and keep it (default: a temporary one)")
    args = parser.parse_args(argv)
    chosen = [c for c in CASES if not args.only or args.only in c.id]
    if args.list:
        for one in chosen:
            print(one.id)
        print(f"{len(chosen)} cases")
        return 0
    root = args.keep or Path(tempfile.mkdtemp(prefix="shot-faults-"))
    root.mkdir(parents=True, exist_ok=True)
    counts: Dict[str, List[int]] = {}
    try:
        place = Place(root / "place")
        for one in chosen:
            began = time.monotonic()
            tally = counts.setdefault(one.group, [0, 0, 0])
            try:
                run_case(place, one)
                verdict = "ok  "
                tally[0] += 1
            except Skipped as why:
                verdict = f"skip ({why})"
                tally[2] += 1
            except Exception as failure:  # the catalogue reports every case, failing or not
                verdict = f"FAIL {type(failure).__name__}: {str(failure)[:300]}"
                tally[1] += 1
                if not isinstance(failure, AssertionError):
                    traceback.print_exc()
            print(f"{verdict[:4]} {one.id} ({time.monotonic() - began:.1f} s){verdict[4:] and ': ' + verdict[4:]}",
                  flush=True)
    finally:
        if not args.keep:
            shutil.rmtree(root, ignore_errors=True)
    print(f"{'group':<8} {'cases':>5} {'meet':>5} {'fail':>5} {'skip':>5}")
    for group, (ok, failed, skipped) in counts.items():
        print(f"{group:<8} {ok + failed + skipped:>5} {ok:>5} {failed:>5} {skipped:>5}")
    totals = [sum(t[i] for t in counts.values()) for i in range(3)]
    print(f"{'all':<8} {sum(totals):>5} {totals[0]:>5} {totals[1]:>5} {totals[2]:>5}")
    return 1 if totals[1] else 0


if __name__ == "__main__":
    sys.exit(main())
