"""A real Dask cluster on loopback for the farm tests: one ``dask scheduler`` and ``dask worker`` processes, started
and stopped here, importing the painter from this source tree."""

import contextlib
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Iterator, List, NamedTuple, Optional

ROOT = Path(__file__).resolve().parents[1]
START_SECONDS = 60


class Cluster(NamedTuple):
    address: str
    scheduler: subprocess.Popen
    workers: List[subprocess.Popen]


def environment() -> dict:
    """The processes' environment: the painter importable from this source tree, Dask's logs quiet."""
    return dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])),
                DASK_LOGGING__DISTRIBUTED="error")


@contextlib.contextmanager
def cluster(folder: Path, workers: int = 2, worker_prefix: Optional[List[str]] = None) -> Iterator[Cluster]:
    """A scheduler on 127.0.0.1 and ``workers`` single-threaded workers without nannies (a worker killed stays
    dead), its files in ``folder``; ``worker_prefix``: a command the workers run under (e.g. ``unshare``)."""
    folder.mkdir(parents=True, exist_ok=True)
    address_file = folder / "scheduler.json"
    address_file.unlink(missing_ok=True)
    log = open(folder / "cluster.log", "ab")
    started: List[subprocess.Popen] = []
    try:
        scheduler = spawn(started, [sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
                                    "--port", "0", "--no-dashboard", "--scheduler-file", str(address_file)], log)
        address = wait_for_address(address_file, scheduler)
        processes = [spawn(started, (worker_prefix or []) + worker_command(address), log) for _ in range(workers)]
        wait_for_workers(address, workers)
        yield Cluster(address, scheduler, processes)
    finally:
        stop(started)
        log.close()


def worker_command(address: str) -> List[str]:
    """A single-threaded ``dask worker`` of the scheduler at ``address``, without a nanny."""
    return [sys.executable, "-m", "distributed.cli.dask_worker", address, "--nthreads", "1", "--no-nanny",
            "--no-dashboard", "--host", "127.0.0.1", "--death-timeout", "60"]


@contextlib.contextmanager
def joining_worker(dask: Cluster, folder: Path, worker_prefix: Optional[List[str]] = None) -> Iterator[object]:
    """A function that starts one more worker of ``dask`` (under ``worker_prefix``) and waits until it has
    joined; the worker is stopped after the body."""
    started: List[subprocess.Popen] = []
    log = open(folder / "joining.log", "ab")

    def join() -> None:
        spawn(started, (worker_prefix or []) + worker_command(dask.address), log)
        wait_for_workers(dask.address, len(dask.workers) + 1)

    try:
        yield join
    finally:
        stop(started)
        log.close()


def stop(started: List[subprocess.Popen]) -> None:
    """SIGTERM every process of ``started`` that still runs, then wait for each (SIGKILL after 15 s)."""
    for process in started:
        if process.poll() is None:
            process.send_signal(signal.SIGTERM)
    for process in started:
        try:
            process.wait(timeout=15)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def spawn(started: List[subprocess.Popen], command: List[str], log) -> subprocess.Popen:
    process = subprocess.Popen(command, cwd=ROOT, env=environment(), stdout=log, stderr=subprocess.STDOUT)
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

    with Client(address, timeout="30s", set_as_default=False) as client:
        client.wait_for_workers(count, timeout=START_SECONDS)
