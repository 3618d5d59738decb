"""Several objects' textures painted on a Dask cluster: each job one task, painted by ``core.paint_object`` alone.

Each job is painted on a worker by the call that paints it in one process
(``core.api.paint_object``, handed in by the caller) with the job's own
arguments, its mesh (a ``SurfaceMesh``, a tuple of arrays) and parameters
sent with the task, so its folder holds the same bytes (the number of
threads changes none, BLAS's included). A job's own failure
(a ``PaintReliefError``) is that job's, and the others are painted. A job
stops, as ``paint_object`` stops when cancelled (nothing written), once the
batch's Dask event (``stop_name``) is set; its worker looks at it at most
every ``WAIT_SECONDS``.
"""

from __future__ import annotations

import concurrent.futures
import contextlib
import glob
import os
import secrets
import time
from pathlib import Path
from typing import Callable, Dict, List, Optional

from ..errors import Cancelled, PaintReliefError
from ..progress import CancelFn
from .cluster import FarmError, address, check_new_workers, import_distributed, plain, raise_error

WAIT_SECONDS = 0.25
"""Seconds between looks at the cancel callback while objects are painted, and at most between a task's looks at
the batch's stop event."""

STOP_SECONDS = 20.0
"""Seconds the tasks running when the batch is stopped are given to see the stop (each sees it within
``WAIT_SECONDS`` while painting) before they are left to the cluster."""

UDIM = "<UDIM>"
"""The mark of a tiled source's path (``core.surface.atlas``): its tiles are the files with a number there."""

Finished = Callable[[int, Optional[dict], Optional[PaintReliefError]], None]
"""finished(k, report, error): job k was painted (its report) or failed (its one-sentence error)."""


def paint_objects_on(client, paint_object: Callable, jobs: Dict[int, dict], finished: Finished,
                     cancel: CancelFn = None) -> None:
    """Paint each job of ``jobs`` (index: ``paint_object``'s keyword arguments) with ``paint_object(**job,
    cancel=...)`` as one task on ``client``'s cluster, calling ``finished`` as each is done, in the order they
    finish.

    Every worker must read every source and mesh file of the jobs (those that exist here: a missing one is its
    job's error) and write where each job's folder is made (``job_paths``): checked first, and a worker that joins
    when it is first seen, one sentence naming the worker and the path. A job's PaintReliefError, or another
    error of the painter's (said in one sentence), is its own; a worker that cannot import the painter or
    fails to read or write a file is a FarmError, as a lost scheduler. cancel(): looked at every WAIT_SECONDS;
    when it returns True the jobs not started are dropped, those running are stopped and waited for (their folders
    as they were; a job past its last look finishes, and is ``finished``) and Cancelled is raised.
    """
    distributed = import_distributed()
    readable, writable = job_paths(jobs.values())
    checked: set = set()
    check_new_workers(client, client.nthreads(), checked, readable, writable)
    token = secrets.token_hex(4)
    stop_name = f"paint-relief-objects-stop-{token}"
    stop = distributed.Event(stop_name, client=client)
    futures = {client.submit(painted_object, paint_object, job, stop_name,
                             key=f"paint-relief-object-{k}-{token}", pure=False): k for k, job in jobs.items()}
    pending = set(futures)

    def collect(stopping: bool = False) -> None:
        for future in [f for f in pending if f.done() and not (stopping and f.status == "cancelled")]:
            pending.discard(future)
            k = futures[future]
            report, error = task_outcome(future, k, jobs[k])
            if not (stopping and isinstance(error, Cancelled)):
                finished(k, report, error)

    try:
        with client.as_current():
            while pending:
                collect()
                if not pending:
                    break
                check_new_workers(client, client.nthreads(), checked, readable, writable)
                if cancel is not None and cancel():
                    stop.set()
                    running = {key for keys in client.processing().values() for key in keys}
                    client.cancel([f for f in pending if f.key not in running])
                    with contextlib.suppress(TimeoutError):
                        distributed.wait([f for f in pending if f.key in running], timeout=STOP_SECONDS)
                    collect(stopping=True)
                    raise Cancelled("Painting the objects was cancelled.")
                try:
                    distributed.wait(list(pending), timeout=WAIT_SECONDS, return_when="FIRST_COMPLETED")
                except TimeoutError:
                    continue
    except (concurrent.futures.CancelledError, distributed.comm.CommClosedError, OSError):
        raise FarmError(f"Lost the Dask scheduler at {address(client)}; the objects painted stay in their "
                        f"folders.") from None
    finally:
        client.cancel([f for f in pending if not f.done()])


def painted_object(paint_object: Callable, job: dict, stop_name: str):
    """Run on a worker: ``paint_object(**job)``'s report, or the PaintReliefError it raised (returned, so that it is
    the job's outcome); it stops (Cancelled) once the Dask event ``stop_name`` is set."""
    import distributed

    stop = distributed.Event(stop_name)
    seen = {"at": 0.0, "set": False}

    def cancel() -> bool:
        now = time.monotonic()
        if not seen["set"] and now - seen["at"] >= WAIT_SECONDS:
            seen["at"], seen["set"] = now, stop.is_set()
        return seen["set"]

    try:
        return paint_object(**job, cancel=cancel)
    except PaintReliefError as exc:
        return exc


def task_outcome(future, k: int, job: dict):
    """(report, None) or (None, error) of job ``k``'s task, done: its own failure is its error in one sentence; a
    worker's OSError or ImportError is raised as a FarmError (``raise_error``)."""
    if future.status == "finished":
        result = future.result()
        if isinstance(result, PaintReliefError):
            return None, result
        return result, None
    if future.status == "cancelled":
        raise concurrent.futures.CancelledError()
    error = future.exception()
    if isinstance(error, (ImportError, OSError)):
        raise_error(future, f"painting object {k + 1} into {job['output_dir']}")
    return None, PaintReliefError(f"Painting object {k + 1} into {job['output_dir']} failed on a Dask worker: "
                                  f"{type(error).__name__}, {plain(error)}.")


def job_paths(jobs) -> tuple:
    """(readable, writable) of ``jobs``: every source file and OBJ mesh of theirs that is a file here (a tiled
    source's tiles), and for each folder the nearest folder above it that exists, where it will be made."""
    readable: List[Path] = []
    writable: List[Path] = []
    for job in jobs:
        texture = job["texture_path"]
        sources = list(texture) if isinstance(texture, (list, tuple)) else [texture]
        if isinstance(job["mesh"], (str, os.PathLike)):
            sources.append(job["mesh"])
        for source in map(os.fspath, sources):
            found = sorted(glob.glob(glob.escape(source).replace(glob.escape(UDIM), "[0-9]" * 4))) \
                if UDIM in source else [source]
            readable += [Path(path) for path in found if os.path.isfile(path) and Path(path) not in readable]
        parent = Path(job["output_dir"]).resolve().parent
        while not parent.is_dir() and parent != parent.parent:
            parent = parent.parent
        if parent not in writable:
            writable.append(parent)
    return readable, writable
