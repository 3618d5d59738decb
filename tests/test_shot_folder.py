"""A shot's folder checked on every resume (core.sequence.shot_folder): repaired to what a run never stopped would
hold, or refused in one sentence naming the file with the folder left as it was; faults while a frame is written
are one sentence and leave complete frames only; a shot that grows keeps a report of exactly its frames."""

import errno
import json
import os
import pathlib
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from oracles import folder_bytes, one_sentence, one_sentence_run, same_bytes
from test_sequence import write_moving_frames

import core.files.writing as writing
import core.sequence.shot_commit as shot_commit
from core.errors import OutputError
from core.files.frames import find_frames
from core.files.lives import FILE_HEADER, LivesFile
from core.params import Params
from core.sequence.shot import paint_sequence

ROOT = Path(__file__).resolve().parents[1]
COUNT, SHAPE, SEED = 5, (48, 64), 7
STATE, LIVES = ".sequence-state.npz", "strokes.lives"


@pytest.fixture(scope="module")
def shot_dir(tmp_path_factory) -> Path:
    """A folder holding the input frames ("in", 5 frames of 48 x 64) and the shot painted whole ("whole")."""
    root = tmp_path_factory.mktemp("shot")
    write_moving_frames(root / "in", COUNT, shape=SHAPE)
    paint_sequence(frames(root), root / "whole", Params(seed=SEED))
    return root


def frames(root: Path, frame_range=None):
    """The shot's input frames (``frame_range`` "A-B" or all)."""
    return find_frames([str(root / "in")], frame_range)


def painted_copy(shot_dir: Path, tmp_path: Path) -> Path:
    """A copy of the shot painted whole, to damage."""
    out = tmp_path / "out"
    shutil.copytree(shot_dir / "whole", out)
    return out


def resumed(shot_dir: Path, out: Path, frame_range=None) -> list:
    """Paint the shot into ``out`` again; the sentences it said (``notice``)."""
    said = []
    paint_sequence(frames(shot_dir, frame_range), out, Params(seed=SEED), notice=said.append)
    return said


def plain_report(folder: Path) -> dict:
    """report.json of ``folder`` without its seconds."""
    report = json.loads((folder / "report.json").read_text())
    report.pop("seconds")
    for entry in report["per_frame"]:
        entry.pop("seconds")
    return report


def same_shot(out: Path, shot_dir: Path) -> None:
    """``out`` holds the same bytes as the shot painted whole, and the same report but for seconds."""
    same_bytes(out, shot_dir / "whole")
    assert plain_report(out) == plain_report(shot_dir / "whole")
    assert not [p for p in os.listdir(out) if p.startswith(".staging")]


def refused(shot_dir: Path, out: Path) -> str:
    """The one sentence ``core sequence`` prints when it refuses ``out`` (exit status 2)."""
    run = subprocess.run([sys.executable, "-m", "core", "sequence", str(shot_dir / "in"), "-o", str(out), "-q",
                          "--seed", str(SEED)], cwd=ROOT, capture_output=True, text=True)
    assert run.returncode == 2, run.stderr
    return one_sentence_run(run)


# --- repairs -----------------------------------------------------------------------------------------------------

def test_the_command_says_what_it_repaired_in_one_line_even_when_quiet(shot_dir, tmp_path):
    out = painted_copy(shot_dir, tmp_path)
    (out / "painting_0004.png").unlink()
    run = subprocess.run([sys.executable, "-m", "core", "sequence", str(shot_dir / "in"), "-o", str(out), "-q",
                          "--seed", str(SEED)], cwd=ROOT, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    lines = [line for line in run.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith(f"paint-relief: Repaired {out}: ") and "painting_0004.png" in lines[0]
    same_shot(out, shot_dir)


@pytest.mark.parametrize("name, damage", [("painting_0004.png", "delete"), ("height_0002.exr", "flip"),
                                          ("color_0005.exr", "shorten")])
def test_a_committed_frames_map_deleted_or_damaged_is_painted_again_to_the_same_bytes(shot_dir, tmp_path, name,
                                                                                     damage):
    out = painted_copy(shot_dir, tmp_path)
    path = out / name
    if damage == "delete":
        path.unlink()
    elif damage == "flip":
        data = bytearray(path.read_bytes())
        data[len(data) // 2] ^= 0x10
        path.write_bytes(bytes(data))
    else:
        path.write_bytes(path.read_bytes()[:-10])
    (said,) = resumed(shot_dir, out)
    assert one_sentence(said).startswith(f"Repaired {out}: {name} was ")
    assert said.endswith("; frames 1-5 are painted again.")
    same_shot(out, shot_dir)


@pytest.mark.parametrize("name", [LIVES, STATE])
def test_a_deleted_lives_file_or_state_is_painted_again_from_the_first_frame(shot_dir, tmp_path, name):
    out = painted_copy(shot_dir, tmp_path)
    (out / name).unlink()
    (said,) = resumed(shot_dir, out)
    assert one_sentence(said) == f"Repaired {out}: {name} was missing; frames 1-5 are painted again."
    same_shot(out, shot_dir)


def test_a_lives_file_longer_than_committed_is_cut_back(shot_dir, tmp_path):
    out = painted_copy(shot_dir, tmp_path)
    with open(out / LIVES, "ab") as stream:
        stream.write(b"\x01" * 77)
    (said,) = resumed(shot_dir, out)
    assert one_sentence(said) == (f"Repaired {out}: {LIVES} held 77 bytes beyond its last committed frame, which "
                                  f"are cut off.")
    same_shot(out, shot_dir)
    assert resumed(shot_dir, out) == []


def test_a_state_that_lags_the_report_is_rolled_back_to_and_painted_on_from(shot_dir, tmp_path):
    out = tmp_path / "out"
    paint_sequence(frames(shot_dir, "1-2"), out, Params(seed=SEED))
    backup = (out / STATE).read_bytes()
    paint_sequence(frames(shot_dir), out, Params(seed=SEED))
    (out / STATE).write_bytes(backup)
    (said,) = resumed(shot_dir, out)
    assert one_sentence(said) == (f"Repaired {out}: {STATE} was that of frame 2, not of frame 5; frames 3-5 are "
                                  f"painted again.")
    same_shot(out, shot_dir)


def test_frames_dropped_by_a_repair_leave_no_maps_behind(shot_dir, tmp_path):
    """The state lags at frame 3 and the run asks for frames 1-3: frames 4-5 are dropped, maps and all, and the
    folder holds what a run of frames 1-3 never stopped holds."""
    out, part = tmp_path / "out", tmp_path / "part"
    paint_sequence(frames(shot_dir, "1-3"), part, Params(seed=SEED))
    shutil.copytree(shot_dir / "whole", out)
    shutil.copyfile(part / STATE, out / STATE)
    (said,) = resumed(shot_dir, out, "1-3")
    assert one_sentence(said) == (f"Repaired {out}: {STATE} was that of frame 3, not of frame 5; the frames after "
                                  f"frame 3 are dropped.")
    same_bytes(out, part)
    assert plain_report(out) == plain_report(part)


# --- refusals ----------------------------------------------------------------------------------------------------

def damage_first_record(out: Path) -> None:
    """Flip a byte inside the lives file's first record's sections (its header's checksum still holds)."""
    path = out / LIVES
    lives = LivesFile(path)
    start, end = FILE_HEADER.size + 48, int(lives.ends()[0]) - 4
    data = bytearray(path.read_bytes())
    data[(start + end) // 2] ^= 0x40
    path.write_bytes(bytes(data))


def state_of_another_shot(shot_dir: Path, out: Path, tmp_path: Path) -> None:
    """The state of frame 5 of the shot painted with another seed, copied in."""
    paint_sequence(frames(shot_dir), tmp_path / "other", Params(seed=SEED + 1))
    shutil.copyfile(tmp_path / "other" / STATE, out / STATE)


def state_of_a_later_frame(shot_dir: Path, out: Path, tmp_path: Path) -> None:
    """The folder holds frames 1-3 and the state of frame 5."""
    shutil.rmtree(out)
    paint_sequence(frames(shot_dir, "1-3"), out, Params(seed=SEED))
    shutil.copyfile(shot_dir / "whole" / STATE, out / STATE)


@pytest.mark.parametrize("case, words", [
    ("lives record", f"{LIVES} is damaged: the record of frame 1 at byte 12 has a section that does not decompress"),
    ("garbage state", f"{STATE} cannot be used: it is not an archive of arrays that Paint Relief wrote"),
    ("another shot's state", f"{STATE} is not that of frame 5"),
    ("later state", f"{STATE} is that of a frame after the last one report.json lists (frame 3)"),
    ("short lives", f"{LIVES} is 100 bytes, shorter than the"),
])
def test_a_folder_that_cannot_be_vouched_for_is_refused_naming_the_file_and_left_as_it_was(shot_dir, tmp_path, case,
                                                                                          words):
    out = painted_copy(shot_dir, tmp_path)
    if case == "lives record":
        damage_first_record(out)
    elif case == "garbage state":
        (out / STATE).write_bytes(b"\x80\x04garbage" * 200)
    elif case == "another shot's state":
        state_of_another_shot(shot_dir, out, tmp_path)
    elif case == "later state":
        state_of_a_later_frame(shot_dir, out, tmp_path)
    else:
        (out / LIVES).write_bytes((out / LIVES).read_bytes()[:100])
    before = folder_bytes(out, leave_out=())
    line = refused(shot_dir, out)
    assert words in line and str(out) in line, line
    assert "allow_pickle" not in line and "pickle" not in line
    assert folder_bytes(out, leave_out=()) == before


# --- faults while a frame is written -----------------------------------------------------------------------------

def no_space() -> OSError:
    return OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def fail_maps(monkeypatch):
    """Frame 3's height map cannot be written."""
    real = writing.write_exr

    def write_exr(path, *args, **kwargs):
        if Path(path).name == "height_0003.exr":
            raise no_space()
        return real(path, *args, **kwargs)
    monkeypatch.setattr(writing, "write_exr", write_exr)


def fail_state(monkeypatch):
    """Frame 3's state is cut short by a full disk (after its lives record was appended)."""
    real = shot_commit.save_state

    def save_state(path, frame, index, lives_bytes):
        if index == 2:
            Path(path).write_bytes(b"PK\x03\x04 half")
            raise no_space()
        return real(path, frame, index, lives_bytes)
    monkeypatch.setattr(shot_commit, "save_state", save_state)


def fail_lives(monkeypatch):
    """Frame 3's lives record is written but cannot be flushed (the disk filled)."""
    real, calls = os.fsync, []

    def fsync(fd):
        if os.readlink(f"/proc/self/fd/{fd}").endswith(f"/{LIVES}"):
            calls.append(fd)
            if len(calls) == 2:
                raise no_space()
        return real(fd)
    monkeypatch.setattr(os, "fsync", fsync)


def fail_report(monkeypatch):
    """Frame 3's report.json cannot be written."""
    real, calls = pathlib.Path.write_text, []

    def write_text(self, *args, **kwargs):
        if self.name.startswith(".report.tmp-"):
            calls.append(self)
            if len(calls) == 3:
                raise no_space()
        return real(self, *args, **kwargs)
    monkeypatch.setattr(pathlib.Path, "write_text", write_text)


@pytest.mark.parametrize("fail", [fail_maps, fail_state, fail_lives, fail_report])
def test_a_full_disk_at_any_write_of_a_frame_is_one_sentence_and_the_same_command_goes_on(shot_dir, tmp_path,
                                                                                          monkeypatch, fail):
    out = tmp_path / "out"
    with monkeypatch.context() as patch:
        fail(patch)
        with pytest.raises(OutputError) as caught:
            paint_sequence(frames(shot_dir), out, Params(seed=SEED))
    assert one_sentence(str(caught.value)) == (
        f"The output folder {out} could not be written while frame 3 was committed (no space is left on the "
        f"device); frames 1-2 there are complete, and the same command goes on after them once the folder can be "
        f"written again.")
    report = json.loads((out / "report.json").read_text())
    assert report["frames"] == [1, 2]
    assert (out / LIVES).stat().st_size == report["lives"]["bytes"]
    assert not (out / "painting_0003.png").exists()
    assert not [p for p in os.listdir(out) if p.startswith(".") and p != STATE]
    assert resumed(shot_dir, out) == []
    same_shot(out, shot_dir)


def signal_at(monkeypatch, where):
    """SIGTERM sent to this process during frame 3's commit: in its state's writing (``where`` "state", before the
    commit point) or right after its files were renamed into place ("renamed", inside the commit's deferred
    section, so it takes effect once the frame is committed)."""
    import signal as signals_module

    from core.files import staging

    if where == "state":
        real_save = shot_commit.save_state

        def save_state(path, frame, index, lives_bytes):
            if index == 2:
                os.kill(os.getpid(), signals_module.SIGTERM)
            return real_save(path, frame, index, lives_bytes)
        monkeypatch.setattr(shot_commit, "save_state", save_state)
    else:
        real_commit, calls = staging.OutputFolder._commit, []

        def commit(self, staging_folder, names):
            real_commit(self, staging_folder, names)
            calls.append(names)
            if len(calls) == 3:
                os.kill(os.getpid(), signals_module.SIGTERM)
        monkeypatch.setattr(staging.OutputFolder, "_commit", commit)


@pytest.mark.parametrize("where, committed", [("state", [1, 2]), ("renamed", [1, 2, 3])])
def test_a_signal_while_a_frame_is_committed_leaves_no_record_beyond_the_frames_committed(shot_dir, tmp_path,
                                                                                          monkeypatch, where,
                                                                                          committed):
    from core.files import signals

    out = tmp_path / "out"
    restore = signals.install()
    try:
        with monkeypatch.context() as patch:
            signal_at(patch, where)
            with pytest.raises(signals.Interrupted):
                paint_sequence(frames(shot_dir), out, Params(seed=SEED))
    finally:
        restore()
    report = json.loads((out / "report.json").read_text())
    assert report["frames"] == committed
    assert (out / LIVES).stat().st_size == report["lives"]["bytes"]
    assert not [p for p in os.listdir(out) if p.startswith(".") and p != STATE]
    assert resumed(shot_dir, out) == []
    same_shot(out, shot_dir)


@pytest.fixture
def small_disk(tmp_path):
    """A 600 kB tmpfs at tmp_path / "disk" (skipped where mounting is not permitted); unmounted afterwards."""
    disk = tmp_path / "disk"
    disk.mkdir()
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=600k", "none", str(disk)], capture_output=True)
    if mounted.returncode != 0:
        pytest.skip("mounting a tmpfs is not permitted here")
    yield disk
    subprocess.run(["umount", str(disk)], check=False)


def test_a_disk_that_fills_midway_is_one_sentence_and_the_shot_goes_on_once_there_is_room(shot_dir, tmp_path,
                                                                                         small_disk):
    out = small_disk / "out"
    command = [sys.executable, "-m", "core", "sequence", str(shot_dir / "in"), "-o", str(out), "-q", "--seed",
               str(SEED)]
    run = subprocess.run(command, cwd=ROOT, capture_output=True, text=True)
    line = one_sentence_run(run)
    assert run.returncode == 2 and f"The output folder {out} could not be written" in line, line
    assert "no space is left on the device" in line
    report = json.loads((out / "report.json").read_text())
    assert 1 <= len(report["frames"]) < COUNT
    assert (out / LIVES).stat().st_size == report["lives"]["bytes"]
    subprocess.run(["mount", "-o", "remount,size=8m", str(small_disk)], check=True)
    run = subprocess.run(command, cwd=ROOT, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    same_bytes(out, shot_dir / "whole")


# --- a shot that grows -------------------------------------------------------------------------------------------

def test_a_shot_painted_in_part_then_whole_has_the_report_of_a_run_never_stopped(shot_dir, tmp_path):
    out = tmp_path / "out"
    paint_sequence(frames(shot_dir, "1-2"), out, Params(seed=SEED))
    assert plain_report(out)["frame_count"] == 2
    assert resumed(shot_dir, out) == []
    same_shot(out, shot_dir)


def test_a_shot_given_a_fifth_frame_after_a_complete_run_of_four_has_the_report_of_five(shot_dir, tmp_path):
    (tmp_path / "in").mkdir()
    for number in range(1, COUNT):
        shutil.copyfile(shot_dir / "in" / f"frame_{number:04d}.png", tmp_path / "in" / f"frame_{number:04d}.png")
    out = tmp_path / "out"
    paint_sequence(find_frames([str(tmp_path / "in")]), out, Params(seed=SEED))
    shutil.copyfile(shot_dir / "in" / f"frame_{COUNT:04d}.png", tmp_path / "in" / f"frame_{COUNT:04d}.png")
    paint_sequence(find_frames([str(tmp_path / "in")]), out, Params(seed=SEED))
    same_bytes(out, shot_dir / "whole")
    report, whole = plain_report(out), plain_report(shot_dir / "whole")
    assert report["frame_count"] == COUNT and report["complete"]
    assert report["input"] == [str(tmp_path / "in" / f"frame_{n:04d}.png") for n in range(1, COUNT + 1)]
    report["input"] = whole["input"]
    assert report == whole
