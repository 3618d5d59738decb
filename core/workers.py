"""The painter's worker threads: independent pieces of work spread over the machine's cores.

A round's strokes are planned, made and judged each on its own (ALGORITHM
§5, "Speed"), a grid's anchor is its own choice, and an image's channels
and smoothing levels are filtered apart, so such work is cut into pieces
worked on side by side and joined back in order: the result is the same
bytes whatever the number of workers. NumPy and SciPy give up the
interpreter lock inside their array loops, which is where this work spends
its time.
"""

from __future__ import annotations

import os
import threading
from concurrent.futures import ThreadPoolExecutor
from typing import Callable, List, Sequence

import numpy as np

from . import tuning

_pool = None
_pool_lock = threading.Lock()
POOL_PREFIX = "paint-relief-worker"
"""The names of the worker threads begin with this."""


def worker_count() -> int:
    """How many runs a round is cut into: the usable cores, at most ``tuning.MAX_WORKERS``."""
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:                      # not on Linux
        cores = os.cpu_count() or 1
    return max(1, min(tuning.MAX_WORKERS, cores))


def bounded_runs(cost: np.ndarray, limit: float) -> List[tuple]:
    """[(first, stop), ...]: the N items of ``cost`` (N,) >= 0 cut, in order, into runs of consecutive items whose
    total cost is at most ``limit``, each run as long as the limit allows (cut greedily, first to last); an item
    costing more than ``limit`` is a run of its own. No runs for no items."""
    total = np.cumsum(np.asarray(cost))
    runs, first = [], 0
    while first < len(total):
        before = total[first - 1] if first else 0
        stop = max(int(np.searchsorted(total, before + limit, side="right")), first + 1)
        runs.append((first, stop))
        first = stop
    return runs


def balanced_runs(cost: np.ndarray, parts: int, least: float) -> List[tuple]:
    """[(first, stop), ...]: at most ``parts`` runs of consecutive items of about equal total ``cost`` (N,) >= 0,
    each of at least ``least`` (so small work is not split); one run when the whole is below 2 ``least``."""
    n = len(cost)
    total = np.cumsum(np.asarray(cost, np.float64))
    whole = float(total[-1]) if n else 0.0
    parts = int(min(parts, whole // least)) if least > 0 else parts
    if n == 0 or parts <= 1:
        return [(0, n)]
    cuts = np.searchsorted(total, whole * np.arange(1, parts) / parts, side="right")
    bounds = np.unique(np.concatenate(([0], np.clip(cuts, 1, n - 1), [n])))
    return list(zip(bounds[:-1].tolist(), bounds[1:].tolist(), strict=True))


def run_all(work: Callable, items: Sequence) -> list:
    """[work(item) for item in items], on the worker threads when there is more than one item (in order, in the
    calling thread, when that is one of the worker threads: a worker waiting for the others could wait for
    itself)."""
    global _pool
    if len(items) <= 1 or threading.current_thread().name.startswith(POOL_PREFIX):
        return [work(item) for item in items]
    with _pool_lock:
        if _pool is None:
            _pool = ThreadPoolExecutor(worker_count(), thread_name_prefix=POOL_PREFIX)
    return list(_pool.map(work, items))


def in_row_blocks(work: Callable, height: int, width: int) -> None:
    """work(rows) for slices ``rows`` of whole rows covering an image of ``height`` x ``width`` pixels,
    about ``tuning.BLOCK_PIXELS`` each, on the worker threads (for per-pixel work writing its rows of an output)."""
    step = max(1, tuning.BLOCK_PIXELS // max(width, 1))
    run_all(work, [slice(top, min(height, top + step)) for top in range(0, height, step)])
