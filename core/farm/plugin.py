"""The worker plugin every Paint Relief cluster runs (imported only where Dask distributed is installed)."""

from __future__ import annotations

import contextlib

from distributed import WorkerPlugin


class PainterWorker(WorkerPlugin):
    """Sets a worker up to paint as ``python -m core`` does.

    The painter's own thread pool and file writers use one thread, since a
    worker's threads each run a task of their own (a thread count changes no
    painted byte: ``core.tuning``); and the C heap keeps a stroke's freed
    temporaries for the next (``core.heap.reused_heap``, for the worker's
    life), where Dask's nanny otherwise has glibc give them back at once.
    """

    idempotent = True

    def setup(self, worker) -> None:
        from .. import tuning
        from ..heap import reused_heap

        tuning.MAX_WORKERS = 1
        tuning.WRITERS = 1
        self.heap = contextlib.ExitStack()
        self.heap.enter_context(reused_heap())

    def teardown(self, worker) -> None:
        self.heap.close()
