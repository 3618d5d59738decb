"""A sequence painted on a real Dask cluster (a ``dask scheduler`` and ``dask worker`` processes on loopback): the
same bytes as one process through lost workers, a lost scheduler and resumed runs; one sentence for what cannot
be reached or seen."""

import errno
import os
import re
import signal
import subprocess
import sys
import threading
from pathlib import Path

import pytest

pytest.importorskip("distributed")

from dask_cluster import (  # noqa: E402
    HANG_SECONDS,
    ROOT,
    START_SECONDS,
    Worker,
    closed_port,
    cluster,
    hang_guard,
    joining_worker,
    painter_command,
    painter_environment,
)
from oracles import folder_bytes, one_sentence, one_sentence_run  # noqa: E402
from tiny_shot import shot  # noqa: E402

from core import paint_sequence_files  # noqa: E402
from core.api import paint_batch  # noqa: E402
from core.errors import Cancelled, OutputError  # noqa: E402
from core.farm.cluster import Farm, FarmError  # noqa: E402
from core.params import Params, SequenceSettings  # noqa: E402
from core.sequence.pieces import write as written_maps  # noqa: E402

pytestmark = pytest.mark.cluster

FRAMES = 8
PARAMS = dict(seed=4)


@pytest.fixture(autouse=True)
def time_limit():
    """A farm test that hangs (a piece waiting for a worker that never comes) fails instead."""
    with hang_guard():
        yield


@pytest.fixture(scope="module")
def footage(tmp_path_factory):
    """The tiny shot's 8 frames and the files one process paints from them."""
    folder = tmp_path_factory.mktemp("farm")
    frames = shot(folder / "frames", frames=FRAMES)
    paint_sequence_files([frames], folder / "alone", Params(**PARAMS))
    return frames, folder_bytes(folder / "alone")


def once_done(count: int, action, happened: list):
    """A progress callback that calls ``action()`` once, when at least ``count`` frames (or stills) are done (the
    message "k/n ..." with k >= count: two stills may finish between two looks), and appends the progress message
    to ``happened``."""
    def progress(fraction, message):
        done = message.split("/", 1)[0]
        if not happened and done.isdigit() and int(done) >= count:
            action()
            happened.append(message)
    return progress


def killing_after(committed: int, process: subprocess.Popen, kills: list):
    """A progress callback that SIGKILLs ``process`` once ``committed`` frames are committed."""
    def kill():
        process.send_signal(signal.SIGKILL)
        process.wait()
    return once_done(committed, kill, kills)


def test_a_sequence_that_loses_a_worker_midway_is_complete_and_the_same_bytes_as_one_process(tmp_path, footage):
    frames, alone = footage
    with cluster(tmp_path / "cluster") as dask:
        kills = []
        report = paint_sequence_files([frames], tmp_path / "out", Params(**PARAMS),
                                      progress=killing_after(1, dask.workers[0], kills),
                                      farm=Farm(scheduler=dask.address))
        assert kills and dask.workers[0].returncode == -signal.SIGKILL and dask.workers[1].poll() is None
    assert report["complete"] and len(report["per_frame"]) == FRAMES
    assert folder_bytes(tmp_path / "out") == alone
    assert not [p.name for p in (tmp_path / "out").iterdir() if p.name.startswith(".staging-")]


def test_a_lost_scheduler_is_one_sentence_the_complete_frames_stay_and_a_rerun_goes_on_to_the_same_bytes(
        tmp_path, footage):
    frames, alone = footage
    out = tmp_path / "out"
    with cluster(tmp_path / "first") as dask:
        with pytest.raises(FarmError) as lost:
            paint_sequence_files([frames], out, Params(**PARAMS), progress=killing_after(2, dask.scheduler, []),
                                 farm=Farm(scheduler=dask.address))
    message = one_sentence(str(lost.value))
    assert dask.address in message and str(out) in message
    kept = folder_bytes(out)
    assert 2 <= sum(name.startswith("painting_") for name in kept) < FRAMES
    assert all(alone[name] == data for name, data in kept.items() if name.startswith(("painting_", "height_")))
    with cluster(tmp_path / "second") as dask:
        report = paint_sequence_files([frames], out, Params(**PARAMS), farm=Farm(scheduler=dask.address))
    assert report["complete"] and folder_bytes(out) == alone


def test_local_workers_and_a_run_resumed_on_them_give_the_bytes_of_one_process(tmp_path, footage):
    frames, alone = footage
    paint_sequence_files([frames], tmp_path / "workers", Params(**PARAMS), farm=Farm(workers=2))
    assert folder_bytes(tmp_path / "workers") == alone

    def cancel_after_three():
        return sum(1 for p in (tmp_path / "resumed").glob("painting_*.png")) >= 3

    with pytest.raises(Cancelled):
        paint_sequence_files([frames], tmp_path / "resumed", Params(**PARAMS), cancel=cancel_after_three)
    # asked once frame 3 is committed, as frame 4 is written beside frame 5's life: frame 4 is committed too
    assert len(list((tmp_path / "resumed").glob("painting_*.png"))) == 4
    paint_sequence_files([frames], tmp_path / "resumed", Params(**PARAMS), farm=Farm(workers=2))
    assert folder_bytes(tmp_path / "resumed") == alone


def test_an_unreachable_scheduler_is_one_sentence_naming_it_and_nothing_is_written(tmp_path, footage):
    """Refused at once: with every connect timeout an hour long (Dask retries a refused connection for the whole of
    its timeout), the command still ends within the test's hang guard."""
    frames, _ = footage
    with closed_port() as port:
        address = f"tcp://127.0.0.1:{port}"
        result = subprocess.run(painter_command("sequence", frames, "-o", tmp_path / "out", "--scheduler", address,
                                                "-q"), capture_output=True, text=True, env=painter_environment(),
                                cwd=ROOT)
    message = one_sentence_run(result)
    assert result.returncode == 2 and address in message and "refused the connection" in message
    assert not (tmp_path / "out").exists()


def painter_importable_without_this_tree(folder: Path) -> bool:
    """Whether this interpreter imports the painter from ``folder`` without this source tree on its path (an
    installed painter): then no worker here can lack it."""
    paths = [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p and Path(p).resolve() != ROOT]
    return subprocess.run([sys.executable, "-c", "import core.version"], cwd=folder, capture_output=True,
                          env=dict(os.environ, PYTHONPATH=os.pathsep.join(paths)), timeout=600).returncode == 0


def test_a_worker_that_cannot_import_the_painter_is_named_before_anything_is_painted(tmp_path, footage):
    if painter_importable_without_this_tree(tmp_path):
        pytest.skip("the painter is installed in this interpreter, so every worker imports it")
    frames, _ = footage
    with cluster(tmp_path / "cluster", workers=1, worker=Worker(painter=False)) as dask:
        # every connect timeout an hour long: the command ends within the test's hang guard without waiting for one
        result = subprocess.run(painter_command("sequence", frames, "-o", tmp_path / "out", "--scheduler",
                                                dask.address, "-q"), capture_output=True, text=True,
                                env=painter_environment(), cwd=ROOT)
    message = one_sentence_run(result)
    assert result.returncode == 2, result.stderr
    assert re.fullmatch(r"paint-relief: error: The Dask worker tcp://127\.0\.0\.1:\d+ on \S+ cannot import the "
                        r"painter \(No module named 'core'\): install it on every worker \(pip install "
                        r"\"\.\[farm\]\" from this checkout\)\.", message), message
    assert not (tmp_path / "out").exists()


def test_a_worker_that_joins_midway_without_the_painter_never_joins_and_the_shot_is_the_same_bytes(tmp_path,
                                                                                                footage):
    """Once the painter's worker plugin is sent, Dask turns away a worker that cannot import it: the worker stops
    at its start (its own log says why) and never takes a piece."""
    if painter_importable_without_this_tree(tmp_path):
        pytest.skip("the painter is installed in this interpreter, so every worker imports it")
    frames, alone = footage
    with cluster(tmp_path / "cluster", workers=1) as dask, \
            joining_worker(dask, tmp_path, worker=Worker(painter=False)) as join:
        turned_away = []
        report = paint_sequence_files([frames], tmp_path / "out", Params(**PARAMS),
                                      progress=once_done(2, lambda: turned_away.append(join(wait=False).wait(START_SECONDS)),
                                                         []),
                                      farm=Farm(scheduler=dask.address))
    assert turned_away and turned_away[0] != 0
    assert "No module named 'core'" in (tmp_path / "joining.log").read_text()
    assert report["complete"] and folder_bytes(tmp_path / "out") == alone


OLDEST_NUMPY = ROOT / ".venv-numpy1" / "bin" / "python"
"""An interpreter with the oldest NumPy and SciPy the painter supports (requirements-numpy1.txt) and Dask."""


def other_interpreter_versions() -> dict:
    """{"NumPy": ..., "SciPy": ...} of OLDEST_NUMPY when it runs Dask distributed too, else {}."""
    if not OLDEST_NUMPY.exists():
        return {}
    result = subprocess.run([str(OLDEST_NUMPY), "-c", "import distributed, numpy, scipy; "
                             "print(numpy.__version__, scipy.__version__)"], capture_output=True, text=True,
                            timeout=600)
    return dict(zip(["NumPy", "SciPy"], result.stdout.split(), strict=False)) if result.returncode == 0 else {}


def test_a_worker_with_other_numpy_and_scipy_versions_is_named_before_anything_is_painted(tmp_path, footage):
    import numpy
    import scipy

    theirs = other_interpreter_versions()
    if not theirs or (theirs["NumPy"], theirs["SciPy"]) == (numpy.__version__, scipy.__version__):
        pytest.skip(f"needs {OLDEST_NUMPY} with Dask distributed and another NumPy and SciPy than this one")
    frames, _ = footage
    with cluster(tmp_path / "cluster", workers=1, worker=Worker(python=str(OLDEST_NUMPY))) as dask:
        with pytest.raises(FarmError) as refused:
            paint_sequence_files([frames], tmp_path / "out", Params(**PARAMS), farm=Farm(scheduler=dask.address))
    message = one_sentence(str(refused.value))
    assert re.fullmatch(
        rf"The Dask worker tcp://127\.0\.0\.1:\d+ on \S+ runs NumPy {re.escape(theirs['NumPy'])} and SciPy "
        rf"{re.escape(theirs['SciPy'])} but this command runs NumPy {re.escape(numpy.__version__)} and SciPy "
        rf"{re.escape(scipy.__version__)}: install the same versions on every worker \(pip install \"\.\[farm\]\" "
        rf"numpy=={re.escape(numpy.__version__)} scipy=={re.escape(scipy.__version__)} from this checkout\)\.",
        message), message
    assert not (tmp_path / "out").exists()


def can_unshare() -> bool:
    """Whether this machine lets a process have a mount namespace of its own (root with CAP_SYS_ADMIN)."""
    try:
        return subprocess.run(["unshare", "--mount", "true"], capture_output=True, timeout=600).returncode == 0
    except (OSError, subprocess.TimeoutExpired):
        return False


def shared_frames(frames: Path, tmp_path: Path) -> tuple:
    """(a copy of ``frames`` in a folder of its own, a command prefix under which a worker sees that folder empty,
    as a machine that has not mounted the shared storage)."""
    shared = tmp_path / "shared" / "frames"
    shared.mkdir(parents=True)
    for frame in sorted(frames.iterdir()):
        (shared / frame.name).write_bytes(frame.read_bytes())
    return shared, ["unshare", "--mount", "--propagation", "private", "sh", "-c",
                    f"mount -t tmpfs none {shared} && exec \"$@\"", "worker"]


@pytest.mark.skipif(not can_unshare(), reason="needs `unshare --mount` to hide a folder from one worker")
def test_a_worker_that_cannot_see_the_input_is_named_before_anything_is_painted(tmp_path, footage):
    hidden, prefix = shared_frames(footage[0], tmp_path)
    with cluster(tmp_path / "cluster", workers=1, worker_prefix=prefix) as dask:
        with pytest.raises(OutputError) as refused:
            paint_sequence_files([hidden], tmp_path / "out", Params(**PARAMS), farm=Farm(scheduler=dask.address))
    message = str(refused.value)
    assert "tcp://127.0.0.1:" in message and str(hidden / "frame_0011.png") in message and "cannot read" in message
    assert not (tmp_path / "out").exists()


def paint_while_one_joins(painting: str, frames: Path, out: Path, join, joined: list, farm) -> None:
    """Paint the frames of the folder ``frames`` into ``out`` on ``farm`` as a shot (``painting`` "sequence") or a
    batch of stills, calling ``join`` (a worker joins) once two frames or one still are done."""
    if painting == "sequence":
        paint_sequence_files([frames], out, Params(**PARAMS), progress=once_done(2, join, joined), farm=farm)
    else:
        paint_batch(sorted(map(str, frames.iterdir())), out, Params(**PARAMS), progress=once_done(1, join, joined),
                    farm=farm)


@pytest.mark.skipif(not can_unshare(), reason="needs `unshare --mount` to hide a folder from one worker")
@pytest.mark.parametrize("painting", ["sequence", "batch"])
def test_a_worker_that_joins_midway_and_cannot_see_the_input_is_named_before_it_paints(tmp_path, footage, painting):
    shared, blind = shared_frames(footage[0], tmp_path)
    with cluster(tmp_path / "cluster", workers=1) as dask, joining_worker(dask, tmp_path, blind) as join:
        joined, farm = [], Farm(scheduler=dask.address)
        with pytest.raises(OutputError) as refused:
            paint_while_one_joins(painting, shared, tmp_path / "out", join, joined, farm)
    message = str(refused.value)
    assert joined and "tcp://127.0.0.1:" in message and "cannot read" in message and str(shared) in message
    if painting == "sequence":
        assert 2 <= len(list((tmp_path / "out").glob("painting_*.png"))) < FRAMES


def test_a_frame_written_twice_goes_to_two_staging_folders_of_the_same_bytes(tmp_path, footage):
    """A piece that runs twice (a worker thought lost finishes anyway) never writes into the other run's files:
    each writing makes a staging folder of its own, and the commit takes one whole."""
    from core.files.frames import find_frames
    from core.sequence.pieces import PieceKey, PieceKind
    from core.sequence.shot import Run, shot_settings

    frames, alone = footage
    found = find_frames([str(frames)])
    pieces = Run(found, shot_settings(found, Params(**PARAMS), SequenceSettings())).pieces(tmp_path, True)
    made = {}
    for kind in (PieceKind.PREPARE, PieceKind.CARRY, PieceKind.BIRTH, PieceKind.SHOWN):
        piece = pieces.piece(PieceKey(kind, 0))
        made[piece.key] = piece.make(*(made[key] for key in piece.needs))
    writing = pieces.piece(PieceKey(PieceKind.WRITE, 0))
    first, second = (writing.make(*(made[key] for key in writing.needs)) for _ in range(2))
    assert first.staging != second.staging and first.staging.parent == second.staging.parent == tmp_path
    assert first.files == second.files
    assert folder_bytes(first.staging, ()) == folder_bytes(second.staging, ())
    assert (first.staging / "height_0011.exr").read_bytes() == alone["height_0011.exr"]


def test_without_a_farm_the_painter_imports_no_dask(tmp_path, footage):
    frames, _ = footage
    code = ("import sys\nfrom core.cli import main\n"
            f"assert main(['sequence', {str(frames)!r}, '-o', {str(tmp_path / 'seq')!r}, '-q', '--frames', '11-12']) == 0\n"
            f"assert main(['batch', {str(sorted(frames.iterdir())[0])!r}, '-o', {str(tmp_path / 'batch')!r}, '-q']) == 0\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('dask', 'distributed')))")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600,
                            cwd=Path(__file__).resolve().parents[1])
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip().splitlines()[-1] == "[]"


def disk_full(*args, **kwargs):
    """A piece that fails for itself, as writing onto a full disk does."""
    raise OSError(errno.ENOSPC, "No space left on device", "/shared/out/.staging-1/height_0011.exr")


def test_a_piece_that_fails_with_an_os_error_is_named_and_not_taken_for_a_lost_scheduler(tmp_path, footage,
                                                                                          monkeypatch):
    import distributed

    import core.sequence.pieces
    from core.farm.sequence import ClusterFrames
    from core.files.frames import find_frames
    from core.sequence.shot import paint_sequence

    frames, _ = footage
    monkeypatch.setattr(core.sequence.pieces, "write", disk_full)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as \
            local, distributed.Client(local) as client:
        with pytest.raises(FarmError) as failed:
            paint_sequence(find_frames([str(frames)]), tmp_path / "out", Params(**PARAMS),
                           frames_painter=ClusterFrames(client))
    assert re.fullmatch(r"A Dask worker failed in the piece paint-relief-write-11-\w+ \(sent to \S+\): "
                        r"no space is left on the device \(/shared/out/\.staging-1/height_0011\.exr\)\.",
                        str(failed.value)), str(failed.value)
    assert not list((tmp_path / "out").glob("painting_*"))


WRITING = threading.Event()
"""Set once a piece writes the maps of frame 13 (``held_write``)."""
STOPPING = threading.Event()
"""Set once the run stops (``ClusterRun.stop`` begins)."""


def held_write(folder, number, *args, **kwargs):
    """Write frame ``number``'s maps (``pieces.write``); frame 13's only once the run stops, after telling
    ``WRITING`` it began: the run stops while a worker writes, at every timing."""
    if number == 13:
        WRITING.set()
        assert STOPPING.wait(HANG_SECONDS), "the run did not stop"
    return written_maps(folder, number, *args, **kwargs)


def test_a_run_stopped_while_a_worker_writes_maps_leaves_complete_frames_and_no_staging_folder(tmp_path, footage,
                                                                                                 monkeypatch):
    import distributed

    import core.farm.sequence
    import core.sequence.pieces
    from core.farm.sequence import ClusterFrames, ClusterRun
    from core.files.frames import find_frames
    from core.files.staging import STAGING_PREFIX
    from core.sequence.shot import paint_sequence

    frames, alone = footage
    WRITING.clear()
    STOPPING.clear()
    stop = ClusterRun.stop

    def stopping(run):
        STOPPING.set()
        stop(run)

    monkeypatch.setattr(core.sequence.pieces, "write", held_write)
    monkeypatch.setattr(ClusterRun, "stop", stopping)
    # the stopped run waits for frame 13's writing however slow the machine (not the shipped 30 s)
    monkeypatch.setattr(core.farm.sequence, "STOP_SECONDS", HANG_SECONDS)
    out = tmp_path / "out"

    def cancel():
        """Once frame 13 is being written and a frame is committed."""
        return WRITING.is_set() and any(out.glob("painting_*.png"))

    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as \
            local, distributed.Client(local) as client:
        with pytest.raises(Cancelled):
            paint_sequence(find_frames([str(frames)]), out, Params(**PARAMS), cancel=cancel,
                           frames_painter=ClusterFrames(client))
    assert not [p.name for p in out.iterdir() if p.name.startswith(STAGING_PREFIX)]
    maps = {name: data for name, data in folder_bytes(out).items() if re.search(r"_\d{4}\.", name)}
    assert maps and all(alone[name] == data for name, data in maps.items())
    paint_sequence_files([frames], out, Params(**PARAMS))
    assert folder_bytes(out) == alone


@pytest.mark.parametrize("painting", ["sequence", "batch"])
def test_a_worker_that_joins_midway_with_other_numpy_and_scipy_versions_is_named_before_it_paints(
        tmp_path, footage, painting):
    import numpy

    theirs = other_interpreter_versions()
    if not theirs or theirs["NumPy"] == numpy.__version__:
        pytest.skip(f"needs {OLDEST_NUMPY} with Dask distributed and another NumPy than this one")
    frames, _ = footage
    with cluster(tmp_path / "cluster", workers=1) as dask, \
            joining_worker(dask, tmp_path, worker=Worker(python=str(OLDEST_NUMPY))) as join:
        joined, farm = [], Farm(scheduler=dask.address)
        with pytest.raises(FarmError) as refused:
            paint_while_one_joins(painting, frames, tmp_path / "out", join, joined, farm)
    message = one_sentence(str(refused.value))
    assert joined and "tcp://127.0.0.1:" in message and f"runs NumPy {theirs['NumPy']}" in message
    if painting == "sequence":
        assert 2 <= len(list((tmp_path / "out").glob("painting_*.png"))) < FRAMES
