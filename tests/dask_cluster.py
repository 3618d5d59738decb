"""A real Dask cluster on loopback for the farm tests: one ``dask scheduler`` and ``dask worker`` processes, started
and stopped here, importing the painter from this source tree."""

import contextlib
import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path
from typing import Iterator, List, NamedTuple, Optional

ROOT = Path(__file__).resolve().parents[1]
START_SECONDS = 600
"""How long a scheduler or a worker may take to start: it only guards against a hang, far beyond the seconds
either takes on a loaded machine."""
HANG_SECONDS = 900
"""How long one farm test may run before it fails as hung: far beyond what the slowest takes on a loaded machine."""


class Hung(BaseException):
    """A test ran past its HANG_SECONDS; a BaseException, so no ``except Exception`` (nor one of TimeoutError) on
    the way turns it into an answer that passes."""


@contextlib.contextmanager
def hang_guard(seconds: float = HANG_SECONDS) -> Iterator[None]:
    """Raise Hung in the main thread when the body runs past ``seconds`` (SIGALRM)."""
    def expired(signum, frame):
        raise Hung(f"the test did not finish within {seconds} s")
    previous = signal.signal(signal.SIGALRM, expired)
    signal.alarm(int(seconds))
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


@contextlib.contextmanager
def closed_port() -> Iterator[int]:
    """A port of 127.0.0.1 where a connection is refused for the whole body: a socket of this process is bound to
    it and does not listen, so no other process can take the port meanwhile."""
    with socket.socket() as bound:
        bound.bind(("127.0.0.1", 0))
        yield bound.getsockname()[1]


HOUR = 3600
"""The connect timeouts of ``painter_command``: a wait that lasts one of them outlasts any hang guard here."""


def painter_command(*arguments) -> List[str]:
    """``python -m core ARGUMENTS`` in which every connect timeout of the farm's (CONNECT_SECONDS) and of Dask's
    lasts an hour (with ``painter_environment()``): a command that still ends within a test's hang guard waited
    for none of them, however slow the machine."""
    code = ("import runpy, sys\n"
            "import core.farm.cluster\n"
            f"core.farm.cluster.CONNECT_SECONDS = {HOUR}\n"
            "sys.argv = ['core', *sys.argv[1:]]\n"
            "runpy.run_module('core', run_name='__main__', alter_sys=True)\n")
    return [sys.executable, "-c", code, *map(str, arguments)]


def painter_environment() -> dict:
    """The environment of ``painter_command``: the painter importable from this source tree, Dask's connect
    timeout an hour."""
    return dict(environment(), DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT=f"{HOUR}s")


class Cluster(NamedTuple):
    address: str
    scheduler: subprocess.Popen
    workers: List[subprocess.Popen]


class Worker(NamedTuple):
    """How the workers are started: under ``prefix`` (a command, e.g. ``unshare``), by the interpreter ``python``,
    and with the painter importable (``painter``: this source tree on their path and their working folder) or
    not (neither, as on a machine where the painter was never installed)."""

    prefix: Optional[List[str]] = None
    python: str = sys.executable
    painter: bool = True


PAINTER = Worker()
"""A worker of this interpreter that imports the painter from this source tree."""


def environment(painter: bool = True) -> dict:
    """The processes' environment: the painter importable from this source tree (or not), Dask's logs quiet."""
    paths = [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p and Path(p).resolve() != ROOT]
    return dict(os.environ, PYTHONPATH=os.pathsep.join(([str(ROOT)] if painter else []) + paths),
                DASK_LOGGING__DISTRIBUTED="error")


@contextlib.contextmanager
def cluster(folder: Path, workers: int = 2, worker_prefix: Optional[List[str]] = None,
            worker: Worker = PAINTER) -> Iterator[Cluster]:
    """A scheduler on 127.0.0.1 and ``workers`` single-threaded workers without nannies (a worker killed stays
    dead), its files in ``folder``; ``worker_prefix``: a command the workers run under (e.g. ``unshare``),
    ``worker``: how else they are started."""
    folder.mkdir(parents=True, exist_ok=True)
    address_file = folder / "scheduler.json"
    address_file.unlink(missing_ok=True)
    log = open(folder / "cluster.log", "ab")
    started: List[subprocess.Popen] = []
    try:
        scheduler = spawn(started, [sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
                                    "--port", "0", "--no-dashboard", "--scheduler-file", str(address_file)], log)
        address = wait_for_address(address_file, scheduler)
        worker = worker._replace(prefix=worker_prefix or worker.prefix)
        processes = [spawn_worker(started, worker, address, folder, log) for _ in range(workers)]
        wait_for_workers(address, workers)
        yield Cluster(address, scheduler, processes)
    finally:
        stop(started)
        log.close()


def worker_command(address: str, python: str = sys.executable) -> List[str]:
    """A single-threaded ``dask worker`` of the scheduler at ``address``, without a nanny."""
    return [python, "-m", "distributed.cli.dask_worker", address, "--nthreads", "1", "--no-nanny",
            "--no-dashboard", "--host", "127.0.0.1", "--death-timeout", str(START_SECONDS)]


def spawn_worker(started: List[subprocess.Popen], worker: Worker, address: str, folder: Path,
                 log) -> subprocess.Popen:
    """Start one worker of the scheduler at ``address`` as ``worker`` says; one without the painter works in
    ``folder``, where no painter is."""
    return spawn(started, (worker.prefix or []) + worker_command(address, worker.python), log,
                 cwd=ROOT if worker.painter else folder, painter=worker.painter)


@contextlib.contextmanager
def joining_worker(dask: Cluster, folder: Path, worker_prefix: Optional[List[str]] = None,
                   worker: Worker = PAINTER) -> Iterator[object]:
    """A function that starts one more worker of ``dask`` (under ``worker_prefix``, as ``worker`` says), waits
    until it has joined unless told not to (``join(wait=False)``), and returns its process; the worker is stopped
    after the body."""
    started: List[subprocess.Popen] = []
    log = open(folder / "joining.log", "ab")

    def join(wait: bool = True) -> subprocess.Popen:
        process = spawn_worker(started, worker._replace(prefix=worker_prefix or worker.prefix), dask.address,
                               folder, log)
        if wait:
            wait_for_workers(dask.address, len(dask.workers) + 1)
        return process

    try:
        yield join
    finally:
        stop(started)
        log.close()


def stop(started: List[subprocess.Popen]) -> None:
    """SIGTERM every process of ``started`` that still runs, then wait for each (SIGKILL after 15 s: a process
    stopped either way is all the tests need, so the wait may run out at any speed)."""
    for process in started:
        if process.poll() is None:
            process.send_signal(signal.SIGTERM)
    for process in started:
        try:
            process.wait(timeout=15)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def spawn(started: List[subprocess.Popen], command: List[str], log, cwd: Path = ROOT,
          painter: bool = True) -> subprocess.Popen:
    process = subprocess.Popen(command, cwd=cwd, env=environment(painter), stdout=log, stderr=subprocess.STDOUT)
    started.append(process)
    return process


def wait_for_address(address_file: Path, scheduler: subprocess.Popen) -> str:
    deadline = time.monotonic() + START_SECONDS
    while time.monotonic() < deadline:
        assert scheduler.poll() is None, "the scheduler stopped while starting"
        with contextlib.suppress(OSError, ValueError, KeyError):
            return json.loads(address_file.read_text())["address"]
        time.sleep(0.1)
    raise TimeoutError("the scheduler did not start")


def wait_for_workers(address: str, count: int) -> None:
    from distributed import Client

    with Client(address, timeout=f"{START_SECONDS}s", set_as_default=False) as client:
        client.wait_for_workers(count, timeout=START_SECONDS)
