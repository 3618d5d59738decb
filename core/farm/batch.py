"""A batch painted on a Dask cluster: stills one task each, shots at once, each into its own folder.

Each still is painted by the same call as in one process (``core.api.paint_file``,
handed in by the caller), so its folder holds the same bytes. A still whose
worker is lost is painted again elsewhere; its folder's lock and all-or-nothing
commit (``files.staging``) keep a second painting of it from mixing files.
Shots are painted at once, each by the call that paints it alone
(``core.api.painted_shot``) in a thread of this process, their pieces
sharing the cluster's threads (``shared_threads``), so N shots keep up to N
times the workers busy.
"""

from __future__ import annotations

import concurrent.futures
import secrets
import threading
from pathlib import Path
from typing import Callable, List, Sequence, Tuple

from ..errors import Cancelled
from ..params import Params
from ..progress import CancelFn, ProgressFn
from .cluster import FarmError, address, check_new_workers, describe, import_distributed, raise_error
from .shared_threads import SharedThreads

WAIT_SECONDS = 0.25
"""Seconds between looks at the cancel callback while stills are painted."""


def paint_stills(client, paint_file: Callable, jobs: List[Tuple[Path, Path]], output_root: Path, params: Params,
                 normal_map: bool, progress: ProgressFn = None, cancel: CancelFn = None) -> List[dict]:
    """Paint each (input, folder) of ``jobs`` with ``paint_file(input, folder, params, normal_map=...)`` on
    ``client``'s cluster; return the reports in the jobs' order.

    Every worker must read every input and write under ``output_root`` (checked first, and a worker that joins when
    it is first seen: one sentence naming the worker and the path). progress(fraction, message) after each still;
    cancel() stops the batch (the stills painted stay). A still that fails raises its error and the rest are
    cancelled; a lost scheduler is a FarmError.
    """
    distributed = import_distributed()
    sources, checked = [source for source, _ in jobs], set()
    check_new_workers(client, client.nthreads(), checked, sources, [output_root])
    where = describe(client)
    token = secrets.token_hex(4)
    futures = [client.submit(paint_file, str(source), str(folder), params, normal_map=normal_map,
                             key=f"paint-relief-still-{k}-{token}", pure=False)
               for k, (source, folder) in enumerate(jobs)]
    try:
        with client.as_current():
            while True:
                done = sum(f.done() for f in futures)
                if progress is not None:
                    progress(done / len(jobs), f"{done}/{len(jobs)} stills painted ({where})")
                if done < len(jobs):
                    check_new_workers(client, client.nthreads(), checked, sources, [output_root])
                for future, (source, _) in zip(futures, jobs, strict=True):
                    if future.done() and future.status != "finished":
                        raise_error(future, f"painting {source}")
                if done == len(jobs):
                    return [future.result() for future in futures]
                if cancel is not None and cancel():
                    raise Cancelled(f"The batch was cancelled; the {done} stills painted stay in {output_root}.")
                pending = [f for f in futures if not f.done()]
                try:
                    distributed.wait(pending, timeout=WAIT_SECONDS, return_when="FIRST_COMPLETED")
                except TimeoutError:
                    continue
    except (concurrent.futures.CancelledError, distributed.comm.CommClosedError, OSError):
        raise FarmError(f"Lost the Dask scheduler at {address(client)}; the stills painted stay in "
                        f"{output_root}.") from None
    finally:
        client.cancel([f for f in futures if not f.done()])


def paint_shots(paint_shot: Callable, count: int, progress: ProgressFn = None, cancel: CancelFn = None) -> List[dict]:
    """Paint ``count`` shots at once, shot k by ``paint_shot(k, progress, cancel, shared)`` in a thread of its
    own, all with one ``SharedThreads``; return their reports in order.

    progress(fraction, message): the shots' mean fraction, with the message of the shot that spoke. A shot that
    fails stops the others (each keeps its complete frames) and its error is raised; cancel() or a signal to this
    process stops them all the same way.
    """
    shared, stop, lock = SharedThreads(), threading.Event(), threading.Lock()
    fractions = [0.0] * count

    def stopped() -> bool:
        return stop.is_set() or (cancel is not None and cancel())

    def reporter(k: int) -> ProgressFn:
        def report(fraction: float, message: str) -> None:
            with lock:
                fractions[k] = fraction
                if progress is not None:
                    progress(sum(fractions) / count, message)
        return report

    with concurrent.futures.ThreadPoolExecutor(count, thread_name_prefix="paint-relief-shot") as pool:
        futures = [pool.submit(paint_shot, k, reporter(k), stopped, shared) for k in range(count)]
        try:
            for future in concurrent.futures.as_completed(futures):
                if future.exception() is not None:
                    stop.set()
        finally:
            stop.set()
    return [future.result() for future in first_failure(futures)]


def first_failure(futures: Sequence[concurrent.futures.Future]) -> Sequence[concurrent.futures.Future]:
    """``futures``, all done, when none failed; else raise the error of the first that failed for a reason of its
    own (a shot stopped because another failed raises Cancelled, which comes last)."""
    errors = [future.exception() for future in futures if future.exception() is not None]
    if errors:
        raise next((error for error in errors if not isinstance(error, Cancelled)), errors[0])
    return futures
