"""Crash points: a command of the painter ended, as SIGKILL ends it, right after each write it makes, one run per
write, then what it left read as readers read it and the same command run again.

A *write boundary* is one call that changes what is on disk under the watched folders: ``os.rename``,
``os.replace``, ``os.link``, ``os.symlink``, ``os.unlink``, ``os.remove``, ``os.mkdir``, ``os.rmdir`` (the removals
inside ``shutil.rmtree`` each count), ``os.truncate``, ``os.ftruncate``, ``os.fsync``, and a file opened for writing
(``open`` or ``os.open`` with ``O_CREAT`` or ``O_TRUNC``: the file is there, empty or cut to nothing). A process
that ends keeps every byte it wrote in the operating system's cache, so the states a crash of the process can
leave are exactly those after each of these calls (ALICE, Pillai et al. 2014, replays a recording the same way).

``run_command(arguments, watched, crash_after=k)`` runs ``python -m core ARGUMENTS`` in a child process forked from
a server that loaded the painter once (``multiprocessing``'s forkserver: a run costs its work, not the interpreter's
start), patches ``os`` and ``open`` in that child only, lets the first ``k`` boundaries under ``watched`` happen
and sends SIGKILL to the child's process group right after the ``k``-th, in whatever thread makes it: no
``finally``, no clean-up, no flush, and the processes it started (a local cluster's workers) die with it. Nothing in the shipped code knows of it. ``crash_after=None`` runs to the end and
records every boundary, which is how a matrix learns how many points it has.

Run a matrix from the command line (one line per crash point that falls short, the counts per matrix)::

    .venv/bin/python tests/crash_points.py [--only WORD] [--keep DIR]

``tests/test_crash_points.py`` runs the same matrices under pytest (``make test``).
"""

from __future__ import annotations

import argparse
import builtins
import io
import json
import multiprocessing
import os
import shutil
import signal
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Callable, Dict, List, NamedTuple, Optional, Sequence

TESTS = Path(__file__).resolve().parent
ROOT = TESTS.parent
for _path in (str(ROOT), str(TESTS)):
    if _path not in sys.path:
        sys.path.insert(0, _path)

CRASHED = -signal.SIGKILL
"""The exit code of a child ended at its crash point: killed by SIGKILL, with every process it started."""
_WRITE_FLAGS = os.O_CREAT | os.O_TRUNC


class Boundary(NamedTuple):
    """One write boundary a run made: the call's name and the paths it touched."""
    call: str
    paths: tuple

    def __str__(self) -> str:
        return f"{self.call} {' -> '.join(self.paths)}"


class Run(NamedTuple):
    """What a child run gave: its exit status, its stderr, and the boundaries it made (all of them, or up to its
    crash point)."""
    status: int
    stderr: str
    boundaries: List[Boundary]

    @property
    def crashed(self) -> bool:
        return self.status == CRASHED


# --- in the child --------------------------------------------------------------------------------------------------

class _Watch:
    """Counts the write boundaries under ``roots`` made in this process and ends it after the ``crash_after``-th."""

    def __init__(self, roots: Sequence[str], crash_after: Optional[int], record: str):
        self.roots = [os.path.realpath(r) for r in roots]
        self.crash_after = crash_after
        self.lock = threading.Lock()
        self.made: List[Boundary] = []
        self.record = record

    def under(self, path: str) -> bool:
        return any(path == root or path.startswith(root + os.sep) for root in self.roots)

    def made_one(self, call: str, paths: tuple) -> None:
        """Note a boundary just made (when it touched a watched path); end the process at the crash point."""
        if not any(self.under(p) for p in paths):
            return
        with self.lock:
            self.made.append(Boundary(call, paths))
            if self.crash_after is not None and len(self.made) >= self.crash_after:
                self.save()
                os.killpg(0, signal.SIGKILL)  # this process and all it started (a local cluster's workers)

    def save(self) -> None:
        with _ORIGINAL["open"](self.record, "w") as f:
            json.dump([list(b) for b in self.made], f)


_ORIGINAL: Dict[str, Callable] = {}


def _where(path, dir_fd=None) -> str:
    """The absolute path of ``path`` (relative to ``dir_fd`` when given; a file descriptor's file), its folder resolved."""
    if isinstance(path, int):
        return _fd_path(path)
    path = os.fsdecode(path)
    if dir_fd is not None and not os.path.isabs(path):
        path = os.path.join(_fd_path(dir_fd), path)
    head, tail = os.path.split(os.path.abspath(path))
    return os.path.join(os.path.realpath(head), tail)


def _fd_path(fd: int) -> str:
    try:
        return os.readlink(f"/proc/self/fd/{fd}")
    except OSError:
        return ""


def _install(watch: _Watch) -> None:
    """Replace the writing calls of ``os`` and ``open`` with ones that report to ``watch`` after each call."""
    def after(name, places):
        original = getattr(os, name)
        _ORIGINAL[name] = original

        def call(*args, **kwargs):
            result = original(*args, **kwargs)
            watch.made_one(name, places(*args, **kwargs))
            return result
        setattr(os, name, call)

    def one(path, *rest, dir_fd=None, **kwargs):
        return (_where(path, dir_fd),)

    def two(source, target, *rest, src_dir_fd=None, dst_dir_fd=None, **kwargs):
        return _where(source, src_dir_fd), _where(target, dst_dir_fd)

    def descriptor(fd, *rest, **kwargs):
        return (_fd_path(fd),)

    for name in ("rename", "replace", "link", "symlink"):
        after(name, two)
    for name in ("unlink", "remove", "rmdir", "mkdir", "truncate"):
        after(name, one)
    for name in ("fsync", "ftruncate"):
        after(name, descriptor)

    open_fd = os.open
    _ORIGINAL["os.open"] = open_fd

    def os_open(path, flags, *args, dir_fd=None, **kwargs):
        fd = open_fd(path, flags, *args, dir_fd=dir_fd, **kwargs)
        if flags & _WRITE_FLAGS:
            watch.made_one("open", (_where(path, dir_fd),))
        return fd
    os.open = os_open

    open_file = builtins.open
    _ORIGINAL["open"] = open_file

    def open_for(file, mode="r", *args, **kwargs):
        handle = open_file(file, mode, *args, **kwargs)
        if any(c in mode for c in "wax") and not isinstance(file, int):
            watch.made_one("open", (_where(file),))
        return handle
    builtins.open = io.open = open_for


def _child(arguments: list, roots: list, crash_after: Optional[int], record: str, stderr_path: str) -> None:
    """In the forked child: a session of its own, stderr to ``stderr_path``, the watch installed, then the painter's
    command line; the exit status is its own (or CRASHED at the crash point)."""
    os.setsid()
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, signal.SIG_DFL)
    err = os.open(stderr_path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
    os.dup2(err, 2)
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 1)
    from core.cli import main

    watch = _Watch(roots, crash_after, record)
    _install(watch)
    try:
        status = main([str(a) for a in arguments])
    except SystemExit as stop:
        status = stop.code if isinstance(stop.code, int) else 2
    except BaseException:  # an uncaught error is a finding: its traceback goes to stderr
        import traceback

        traceback.print_exc()
        status = 99
    watch.save()
    sys.stderr.flush()
    sys.stdout.flush()
    os._exit(status)


def _preload() -> None:
    """What the fork server loads once for every child: the painter's command line and its libraries."""
    import core.cli  # noqa: F401
    import core.files.reading  # noqa: F401
    import core.files.writing  # noqa: F401


# --- in the test ---------------------------------------------------------------------------------------------------

_context = None


def _server():
    global _context
    if _context is None:
        _context = multiprocessing.get_context("forkserver")
        _context.set_forkserver_preload(["crash_points"])
    return _context


def run_command(arguments: list, watched: Sequence[Path], crash_after: Optional[int] = None,
                timeout: float = 600) -> Run:
    """``python -m core ARGUMENTS`` in a forked child, ended right after its ``crash_after``-th write boundary
    under ``watched`` (None: run to the end); ``timeout`` seconds only guard against a hang."""
    with tempfile.TemporaryDirectory(prefix="crash-run-") as scratch:
        record, stderr_path = os.path.join(scratch, "boundaries.json"), os.path.join(scratch, "stderr")
        child = _server().Process(target=_child, args=(list(arguments), [str(w) for w in watched], crash_after,
                                                       record, stderr_path))
        child.start()
        child.join(timeout)
        if child.exitcode is None:  # a hang: the child's session, what it started included, is ended
            os.killpg(child.pid, signal.SIGKILL)
            child.join()
            raise AssertionError(f"python -m core {' '.join(map(str, arguments))} ran past {timeout} s")
        stderr = Path(stderr_path).read_text(errors="replace") if os.path.exists(stderr_path) else ""
        try:
            made = [Boundary(call, tuple(paths)) for call, paths in json.loads(Path(record).read_text())]
        except (OSError, ValueError):
            made = []
        return Run(child.exitcode, stderr, made)


_preload()


# --- what a crash must leave ---------------------------------------------------------------------------------------

def problem_lines(stderr: str) -> List[str]:
    """Lines of ``stderr`` that are not the painter's own one-line notices."""
    return [line for line in stderr.splitlines() if line.strip() and not line.startswith("paint-relief: ")]


def leftovers(folder: Path) -> List[str]:
    """Staging folders, journals, locks and temporary files under ``folder`` (any depth)."""
    from core.files.staging import STAGING_PREFIX

    if not folder.exists():
        return []
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*")
                  if p.name.startswith((STAGING_PREFIX, ".paint-relief")) or ".tmp" in p.name)


def plain_report(folder: Path, case: Path) -> dict:
    """report.json of ``folder`` without what differs between two runs of one command: seconds, and the case's
    folder ``case`` in paths (written as "{case}")."""
    report = json.loads((folder / "report.json").read_text().replace(str(case), "{case}"))
    report.pop("seconds", None)
    for entry in report.get("per_frame", ()):
        entry.pop("seconds", None)
    return report


def same_painting(folder: Path, reference: Path, case: Path, reference_case: Path) -> None:
    """``folder`` (in the case's folder ``case``) holds the files of ``reference`` (in ``reference_case``) byte for
    byte, report.json but for seconds and the cases' folders, and nothing else."""
    from oracles import same_bytes

    same_bytes(folder, reference)
    ours, others = plain_report(folder, case), plain_report(reference, reference_case)
    assert ours == others, "report.json differs from a run never stopped in " + \
        ", ".join(sorted(k for k in set(ours) | set(others) if ours.get(k) != others.get(k)))
    assert not leftovers(folder), f"left behind: {leftovers(folder)}"


def read_still(folder: Path) -> None:
    """A still's folder read as its readers read it: ``core light`` first, as found, then the extension's map check
    and the painting's own check (each completes an interrupted commit first). A folder no painting was committed
    to yet is refused by ``core light`` in one sentence, as a folder never painted is."""
    from core.files.maps import check_maps, check_painting

    run = run_command(["light", folder, "--model", "directional", "-q"], [])
    assert not problem_lines(run.stderr), f"core light: {run.stderr[-1500:]}"
    if (folder / "report.json").exists():
        assert run.status == 0, f"core light refused the painting: {run.stderr[-1500:]}"
        check_maps(folder)
        check_painting(folder)
    else:
        assert run.status == 2 and len(run.stderr.strip().splitlines()) == 1, \
            f"core light read a folder holding no painting: exit {run.status}, {run.stderr[-1500:]}"


def read_shot(folder: Path) -> None:
    """A shot's folder read as its readers read it. As found: every frame report.json lists has its maps (the
    extension's Build Canvas looks for them before it checks any). Then, as the map check does, the folder settled
    (an interrupted commit completed): ``ShotFolder.check`` vouches for every frame it lists, and each frame's
    maps pass the map check."""
    from core.files import shot_files
    from core.files.maps import check_maps
    from core.files.staging import settle
    from core.sequence.shot_folder import ShotFolder

    if not folder.is_dir():
        return
    for number in (shot_files.read_report(folder) or {}).get("frames", []):
        for name in shot_files.frame_file_names(number, False):
            assert (folder / name).is_file(), f"report.json lists frame {number} but {name} is missing"
    settle(folder)
    report = shot_files.read_report(folder)
    if report is None:
        return
    resume = ShotFolder(folder).check(report)
    assert resume.keep == len(report["frames"]), f"ShotFolder.check keeps {resume.keep} of {report['frames']}"
    for number in report["frames"]:
        check_maps(folder, [shot_files.numbered_name(name, number) for name in ("color.exr", "height.exr",
                                                                                "opacity.exr")])


# --- the matrices --------------------------------------------------------------------------------------------------

class Matrix(NamedTuple):
    """A command crashed after each of its write boundaries under ``watch`` (relative to the case's folder).

    ``prepare(folder)`` makes the inputs and whatever the output holds before the command (the command's arguments
    refer to them through "{folder}"); ``reference(folder)`` paints, once, what a run never stopped leaves; ``read``
    checks a crashed output as readers read it; ``same`` checks the output after the command ran again."""
    name: str
    arguments: List[str]
    prepare: Callable[[Path], None]
    read: Callable[[Path], None]
    same: Callable[[Path, Path, Path, Path], None]
    watch: str = "out"
    cluster: bool = False
    points: Callable[[List[Boundary]], Sequence[int]] = lambda made: range(1, len(made) + 1)
    again: Optional[List[str]] = None

    def command(self, folder: Path, again: bool = False) -> List[str]:
        return [a.format(folder=folder) for a in (self.again if again and self.again else self.arguments)]


def second_commit(made: List[Boundary]) -> Sequence[int]:
    """The crash points of a shot's second frame: from the boundary after the first frame's staging folder is
    removed to the removal of the second's."""
    ends = [k for k, boundary in enumerate(made, 1) if boundary.call == "rmdir"
            and Path(boundary.paths[0]).name.startswith(".staging-")]
    return range(ends[0] + 1, ends[1] + 1)


SEED, SHAPE = 7, (48, 64)


def frames(folder: Path, count: int = 3) -> None:
    from test_sequence import write_moving_frames

    write_moving_frames(folder / "in", count, shape=SHAPE)


def damaged_shot(folder: Path) -> None:
    """Frames, the shot painted whole into out/, and its frame 2's height map deleted: a folder to repair."""
    frames(folder)
    painted = run_command([a.format(folder=folder) for a in SHOT], [])
    assert painted.status == 0, painted.stderr
    (folder / "out" / "height_0002.exr").unlink()
    shutil.copytree(folder / "out", folder / "damaged")


def read_repair(folder: Path) -> None:
    """A damaged shot's folder, its repair crashed: settled, it is the damaged folder as the user left it (the
    repair not yet committed), or a folder readers read whole (``read_shot``)."""
    from oracles import folder_bytes

    from core.files.staging import settle

    settle(folder)
    damaged = folder.parent / "damaged"
    if folder_bytes(folder, ()) != folder_bytes(damaged, ()):
        read_shot(folder)


def textured_mesh(folder: Path) -> None:
    """A mesh of two UV islands (tests/test_surface_mesh.py) and a 96 x 96 texture of 8 x 8 coloured squares."""
    import numpy as np
    from test_surface_mesh import TWO_ISLANDS

    from core.files.writing import write_png

    folder.mkdir(parents=True)
    (folder / "two.obj").write_text(TWO_ISLANDS)
    squares = np.random.default_rng(5).random((8, 8, 3))
    write_png(folder / "texture.png", np.repeat(np.repeat(squares, 12, 0), 12, 1), bits=16)


def batch_folders(out: Path, reference: Path, case: Path, reference_case: Path) -> None:
    """A batch's root holds one folder per input, each the bytes of a run never stopped, and nothing else."""
    mine = sorted(p.name for p in out.iterdir()) if out.exists() else []
    theirs = sorted(p.name for p in reference.iterdir())
    assert mine == theirs, f"holds {mine}, a run never stopped {theirs}"
    for name in mine:
        same_painting(out / name, reference / name, case, reference_case)


def read_batch(out: Path) -> None:
    if out.is_dir():
        for folder in sorted(out.iterdir()):
            read_still(folder)


STILL = ["paint", "{folder}/in/frame_0001.png", "-o", "{folder}/out", "-q", "--seed", str(SEED)]
SHOT = ["sequence", "{folder}/in", "-o", "{folder}/out", "-q", "--seed", str(SEED)]
BATCH = ["batch", "{folder}/in/frame_0001.png", "{folder}/in/frame_0002.png", "-o", "{folder}/out", "-q",
         "--seed", str(SEED)]
OBJECT = ["object", "{folder}/texture.png", "--mesh", "{folder}/two.obj", "-o", "{folder}/out", "-q", "--seed",
          str(SEED), "--texture-size", "128", "--stroke-mm", "80,40,20"]

MATRICES = [
    Matrix("a still", STILL, lambda f: frames(f, 1), read_still, same_painting),
    Matrix("a shot of three frames", SHOT, frames, read_shot, same_painting),
    Matrix("a damaged shot repaired", SHOT, damaged_shot, read_repair, same_painting),
    Matrix("a batch of two stills", BATCH, lambda f: frames(f, 2), read_batch, batch_folders),
    Matrix("an object's texture", OBJECT, textured_mesh, read_still, same_painting),
    Matrix("the farm's commit of a frame its workers wrote", SHOT + ["--workers", "2"], frames, read_shot,
           same_painting, cluster=True, points=second_commit, again=SHOT),
]


def crash_matrix(matrix: Matrix, root: Path, log: Callable[[str], None] = lambda line: None) -> List[str]:
    """Crash ``matrix``'s command after each of its write boundaries, each in a folder of its own under ``root``;
    return one line per crash point that falls short (empty when every point meets the standard).

    At each point: the child ended at that point; what it left is read as readers read it (in a copy, so the
    command run again meets what the crash left, not what a reader settled), without a refusal or a traceback; the
    same command run again ends with exit 0 and no notice but the painter's, and leaves the bytes of a run never
    stopped with no journal, staging folder, lock or temporary file."""
    reference = root / "reference"
    matrix.prepare(reference)
    whole = run_command(matrix.command(reference), [reference / matrix.watch])
    assert whole.status == 0 and not problem_lines(whole.stderr), whole.stderr[-2000:]
    count = len(whole.boundaries)
    assert count > 0, f"{matrix.name}: no write boundary under {matrix.watch}"
    points = matrix.points(whole.boundaries)
    log(f"{matrix.name}: {count} write boundaries, crashed after {len(points)} of them")
    failures = []
    for k in points:
        folder = root / f"{k:03d}"
        matrix.prepare(folder)
        out = folder / matrix.watch
        crash = run_command(matrix.command(folder), [out], crash_after=k)
        where = f"{matrix.name}, crash after boundary {k}/{count}"
        try:
            assert crash.crashed, f"it did not reach boundary {k}: exit {crash.status}, {crash.stderr[-800:]}"
            where += f" ({crash.boundaries[-1]})" if crash.boundaries else ""
            if out.exists():
                copy = folder / "read"
                shutil.copytree(out, copy, symlinks=True)
                matrix.read(copy)
                shutil.rmtree(copy)
            again = run_command(matrix.command(folder, again=True), [])
            assert again.status == 0 and not problem_lines(again.stderr), \
                f"run again: exit {again.status}, {again.stderr[-1500:]}"
            matrix.same(out, reference / matrix.watch, folder, reference)
        except Exception as failure:  # a reader's refusal (InputError, OutputError) is a finding too
            failures.append(f"{where}: {type(failure).__name__}: {failure}")
            log(f"FAIL {where}: {type(failure).__name__}: {failure}")
        else:
            shutil.rmtree(folder)
    return failures


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", help="run the matrices whose name holds this word")
    parser.add_argument("--keep", type=Path, help="work in this folder and keep it (default: a temporary one)")
    args = parser.parse_args(argv)
    root = args.keep or Path(tempfile.mkdtemp(prefix="crash-points-"))
    failed = 0
    try:
        for k, matrix in enumerate(m for m in MATRICES if not args.only or args.only in m.name):
            began = time.monotonic()
            failures = crash_matrix(matrix, root / f"m{k}", lambda line: print(line, flush=True))
            failed += len(failures)
            print(f"{matrix.name}: {'all points go on' if not failures else f'{len(failures)} points fall short'} "
                  f"({time.monotonic() - began:.0f} s)", flush=True)
    finally:
        if not args.keep:
            shutil.rmtree(root, ignore_errors=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
