"""Where farm work runs: a local Dask cluster of worker processes, or an existing cluster reached by its scheduler.

Dask distributed is imported only here and only when a farm is asked for
(``--workers`` or ``--scheduler``), so the painter runs without it. Every
worker paints one task at a time on one thread per worker thread: the
worker's threads, not the painter's own thread pool, spread the work
(``plugin.PainterWorker``), and the bytes painted do not depend on either.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import contextlib
import importlib.util
import logging
import os
import secrets
import socket
import warnings
from pathlib import Path
from typing import Iterator, List, NamedTuple, Optional

from ..errors import OutputError, PaintReliefError, ParameterError, plain_cause
from . import address as addresses
from . import software

CONNECT_SECONDS = 10
"""Seconds to reach a scheduler, to hear it answer as a Dask scheduler, and to wait for its first worker, before
giving up."""


class FarmError(PaintReliefError):
    """The cluster could not be reached or was lost: one sentence naming the scheduler's address."""


class Farm(NamedTuple):
    """Where to paint: ``workers`` local worker processes, or the cluster whose scheduler is at ``scheduler``."""

    workers: Optional[int] = None
    scheduler: Optional[str] = None

    def validate(self) -> None:
        """ParameterError (one sentence) for no place, both places, fewer than one worker, or a scheduler's
        address that is not tcp://HOST:PORT (``address.parse``)."""
        if (self.workers is None) == (self.scheduler is None):
            raise ParameterError("Give either a number of local workers or a scheduler's address, not both.")
        if self.workers is not None and self.workers < 1:
            raise ParameterError(f"The number of workers must be at least 1, not {self.workers}.")
        if self.scheduler is not None:
            addresses.parse(self.scheduler)


def import_distributed():
    """The ``distributed`` module; ParameterError saying how to install it when it is missing."""
    try:
        import distributed
    except ImportError as exc:
        raise ParameterError("Painting on a Dask cluster needs Dask distributed, which is not installed here: "
                             "pip install 'paint-relief[farm]' (or dask[distributed]).") from exc
    return distributed


@contextlib.contextmanager
def connected(farm: Farm) -> Iterator[object]:
    """A ``distributed.Client`` of ``farm`` for the body, closed after it (a local cluster is shut down).

    FarmError (one sentence naming the address) when the scheduler cannot be reached or has no worker within
    CONNECT_SECONDS, and (naming the worker) when a worker runs other software than this process
    (``check_software``), before the painter's worker plugin is sent. Dask's own log lines are silenced: progress
    and errors are the caller's to tell, in its words.
    """
    farm.validate()
    distributed = import_distributed()
    quiet_logs()
    with contextlib.ExitStack() as stack:
        if farm.scheduler is None:
            stack.enter_context(environment_kept())
            cluster = stack.enter_context(distributed.LocalCluster(
                n_workers=farm.workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                silence_logs=logging.CRITICAL))
            client = stack.enter_context(distributed.Client(cluster, set_as_default=False))
        else:
            client = stack.enter_context(reach(distributed, farm.scheduler))
        check_software(client, list(client.nthreads()))
        from .plugin import PainterWorker

        try:
            client.register_plugin(PainterWorker(), name="paint-relief-painter")
        except Exception:
            check_software(client, list(client.nthreads()))     # a worker without the painter that just joined
            raise
        yield client


@contextlib.contextmanager
def environment_kept() -> Iterator[None]:
    """This process's environment as it was before the block, once it ends: a local cluster's nannies leave Dask's
    settings for the processes they start in it (one BLAS and OpenMP thread, a malloc trim threshold), and every
    process this one starts later (the side-by-side painters of ``core.objects``) would run with them, slower
    and, with one BLAS thread, painting other bytes."""
    saved = dict(os.environ)
    try:
        yield
    finally:
        for name in set(os.environ) - set(saved):
            del os.environ[name]
        for name, value in saved.items():
            if os.environ.get(name) != value:
                os.environ[name] = value


def quiet_logs() -> None:
    """Silence Dask's and Tornado's loggers (Dask sets some of its child loggers' levels itself)."""
    names = [name for name in logging.root.manager.loggerDict if name.startswith(("distributed", "tornado"))]
    for name in ["distributed", "tornado", *names]:
        logging.getLogger(name).setLevel(logging.CRITICAL)


@contextlib.contextmanager
def reach(distributed, text: str) -> Iterator[object]:
    """A client of the scheduler at ``text`` that has at least one worker; FarmError naming it otherwise.

    The address is read (``address.parse``) and knocked at (``address.knock``) first, then greeted as Dask greets
    (``greet``), each within CONNECT_SECONDS: Dask's client would retry a refused connection for its whole timeout,
    and wait without end on a port where a server that is not a Dask scheduler listens."""
    problem = addresses.knock(text, addresses.parse(text), CONNECT_SECONDS)
    if problem:
        raise FarmError(problem)
    greet(distributed, text)
    try:
        with warnings.catch_warnings():
            # Dask's own table of differing versions: what matters to the bytes is check_software's to tell
            warnings.simplefilter("ignore", distributed.versions.VersionMismatchWarning)
            client = distributed.Client(text, timeout=f"{CONNECT_SECONDS}s", set_as_default=False)
    except (OSError, TimeoutError, ValueError, ImportError) as exc:
        raise FarmError(f"Cannot reach the Dask scheduler at {text} ({plain(exc)}); check the address and that "
                        f"`dask scheduler` runs there.") from None
    with client:
        try:
            client.wait_for_workers(1, timeout=CONNECT_SECONDS)
        except (OSError, TimeoutError) as exc:
            raise FarmError(f"The Dask scheduler at {text} has no worker ({plain(exc)}); start `dask worker "
                            f"{text}` on the machines that paint.") from None
        yield client


def greet(distributed, text: str) -> None:
    """Open a Dask connection to ``text`` and close it once the scheduler has answered Dask's greeting; FarmError
    when what listens there does not answer as a Dask scheduler within CONNECT_SECONDS. On a thread of its own,
    so that a caller's own event loop is no matter."""
    async def hello() -> None:
        comm = await distributed.comm.connect(text, timeout=CONNECT_SECONDS)
        await comm.close()

    with concurrent.futures.ThreadPoolExecutor(1) as thread:
        try:
            thread.submit(asyncio.run, asyncio.wait_for(hello(), CONNECT_SECONDS)).result()
        except Exception as exc:  # whatever the first words were, they were not a Dask scheduler's
            how = f" within {CONNECT_SECONDS} s" if isinstance(exc, TimeoutError) else ""
            raise FarmError(f"What listens at {text} does not answer as a Dask scheduler{how}: check the address "
                            f"(a scheduler listens on port 8786 unless told another, its dashboard on 8787).") \
                from None


def plain(exc: BaseException) -> str:
    """An exception's message on one line, without a full stop."""
    text = " ".join(str(exc).split()) or type(exc).__name__
    return text.rstrip(".")


def describe(client) -> str:
    """"2 workers, dashboard http://..." : the cluster's size and its dashboard's address when it serves one."""
    info = client.scheduler_info()
    count = len(info.get("workers", {}))
    noun = "worker" if count == 1 else "workers"
    has_dashboard = "dashboard" in info.get("services", {}) and client.run_on_scheduler(bokeh_installed)
    return f"{count} {noun}" + (f", dashboard {client.dashboard_link}" if has_dashboard else "")


def bokeh_installed() -> bool:
    """Run on the scheduler: whether it can serve its dashboard (Dask draws it with Bokeh; without Bokeh the
    dashboard's address answers with a page asking for it)."""
    return importlib.util.find_spec("bokeh") is not None


def raise_error(future, what: str) -> None:
    """Raise the error of ``future``, a task that is done and did not finish: an OSError the task raised itself as
    a FarmError, "A Dask worker failed WHAT: the reason." (not to be taken for a lost scheduler, whose
    connection errors are OSErrors too), an ImportError (a worker that joined without the painter and was sent
    a task before it was checked) as a FarmError saying what to install, any other error of the task as it is,
    CancelledError when the cluster is lost."""
    error = future.exception() if future.status == "error" else None
    if isinstance(error, ImportError):
        raise FarmError(f"A Dask worker failed {what}: it cannot import the painter ({plain(error)}); install it on "
                        f"every worker ({software.INSTALL} from this checkout).")
    if isinstance(error, OSError):
        where = f" ({error.filename})" if error.filename else ""
        raise FarmError(f"A Dask worker failed {what}: {plain_cause(error)}{where}.")
    future.result()


def address(client) -> str:
    """The scheduler's address."""
    return client.scheduler.address


def check_paths(client, readable: List[Path], writable: List[Path], workers: List[str]) -> None:
    """OutputError (one sentence naming the worker and the path) when one of ``workers`` (addresses) of
    ``client``'s cluster cannot read one of ``readable`` files or write into one of ``writable`` folders (a probe
    file made and removed there)."""
    problems = client.run(path_problem, [str(p) for p in readable], [str(p) for p in writable], workers=workers)
    for worker, problem in sorted(problems.items()):
        if problem:
            raise OutputError(f"The Dask worker {worker} ({problem}); every worker must see the input and the "
                              f"output folders at the same paths.")


def check_software(client, workers: List[str]) -> None:
    """FarmError (one sentence naming the worker, what differs and what to install) when one of ``workers``
    (addresses) cannot import the painter or runs another version of it, NumPy, SciPy or OpenImageIO than this
    process (``software.difference``). ``software.installed`` travels as source text for the built-in ``eval``
    (``software.on_worker``), so it runs on a worker that cannot import the painter."""
    ours = software.installed(software.PACKAGES)
    theirs = client.run(eval, software.on_worker(software.installed, software.PACKAGES), {}, workers=workers)
    for worker, found in sorted(theirs.items()):
        problem = software.difference(worker, found, ours)
        if problem:
            raise FarmError(problem)


def check_new_workers(client, workers, checked: set, readable: List[Path], writable: List[Path]) -> None:
    """``check_software`` then ``check_paths`` on those of ``workers`` (addresses) not in ``checked`` yet, then add
    them to it: each worker is checked once, whether it was there at the start or joined later."""
    new = sorted(set(workers) - checked)
    if new:
        check_software(client, new)
        check_paths(client, readable, writable, new)
        checked.update(new)


def path_problem(readable: List[str], writable: List[str]) -> Optional[str]:
    """Run on a worker: what it cannot do of reading ``readable`` and writing into ``writable``, or None."""
    # imported here: it loads OpenImageIO, which a Farm alone does not need
    from ..files.staging import PROBE_PREFIX

    host = socket.gethostname()
    for path in readable:
        try:
            with open(path, "rb") as stream:
                stream.read(1)
        except OSError as exc:
            return f"on {host} cannot read {path}: {exc.strerror or plain(exc)}"
    for folder in writable:
        probe = Path(folder) / f"{PROBE_PREFIX}{os.getpid()}-{secrets.token_hex(8)}"
        try:
            probe.write_bytes(b"")
            probe.unlink()
        except OSError as exc:
            return f"on {host} cannot write into {folder}: {exc.strerror or plain(exc)}"
    return None


@contextlib.contextmanager
def large_arguments() -> Iterator[None]:
    """A context in which Dask does not warn of a task's large arguments: a frame's strokes travel with the task
    that continues them, so a lost worker never forces the life to be painted again from the first frame."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="Sending large graph")
        yield
