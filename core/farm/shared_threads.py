"""The cluster's threads shared by several shots painted at once from this process.

Each shot's run (``farm.sequence.ClusterRun``) starts its pieces itself, in
a thread of its own. ``SharedThreads`` keeps, for all of them together, the
pieces running and the worker each was sent to, so that together they keep
no more pieces running than the workers have threads. A run may start a
piece while it runs fewer than its share (the threads over the runs, at
least one), or while the free threads outnumber what the other runs that
wait for threads lack of their shares: a shot whose life waits lends its
threads to the others. Every run waits on every run's pieces, so a thread
freed by one is taken up at once by another.
"""

from __future__ import annotations

import threading
from typing import Dict, List, Mapping, Optional

from .scheduling import free_workers


class SharedThreads:
    """The pieces running for the runs painting at once (one for a run alone), guarded by a lock."""

    def __init__(self):
        self.lock = threading.Lock()
        self.running: Dict[object, tuple] = {}    # future: (run, the worker it was sent to)
        self.runs: Dict[object, bool] = {}        # run: whether it waits for threads

    def join(self, run) -> None:
        """Count ``run`` among the runs sharing the threads."""
        with self.lock:
            self.runs[run] = False

    def leave(self, run) -> None:
        """Stop counting ``run`` and its pieces."""
        with self.lock:
            self.runs.pop(run, None)
            for future in [f for f, (owner, _) in self.running.items() if owner is run]:
                del self.running[future]

    def count(self) -> int:
        """The runs sharing the threads now."""
        with self.lock:
            return len(self.runs)

    def started(self, run, future, worker: Optional[str]) -> None:
        """``run`` sent the piece of ``future`` to ``worker``."""
        with self.lock:
            self.running[future] = (run, worker)

    def finished(self, future) -> None:
        """The piece of ``future`` is no longer running."""
        with self.lock:
            self.running.pop(future, None)

    def futures(self) -> List[object]:
        """The futures of every run's pieces running (a piece done is no longer running, whether or not its run
        has seen it yet)."""
        with self.lock:
            return [future for future in self.running if not future.done()]

    def free(self, threads: Mapping[str, int]) -> Dict[str, int]:
        """``scheduling.free_workers`` of the workers ``threads`` with every run's pieces running."""
        with self.lock:
            return free_workers(threads, [worker for future, (_, worker) in self.running.items()
                                          if not future.done()])

    def may_start(self, run, threads: Mapping[str, int]) -> bool:
        """Whether ``run`` may start a piece now on workers of ``threads`` ({worker: threads}) (module docstring);
        when it may not, it is counted as waiting for threads until it starts every piece it can."""
        with self.lock:
            running = [(owner, worker) for future, (owner, worker) in self.running.items() if not future.done()]
            free = sum(free_workers(threads, [worker for _, worker in running]).values())
            share = max(1, sum(threads.values()) // max(1, len(self.runs)))
            counts = {owner: 0 for owner in self.runs}
            for owner, _ in running:
                counts[owner] = counts.get(owner, 0) + 1
            lacking = sum(max(0, share - counts[other]) for other, waits in self.runs.items()
                          if other is not run and waits)
            allowed = free > 0 and (counts.get(run, 0) < share or free > lacking)
            if run in self.runs:
                self.runs[run] = not allowed
            return allowed

    def satisfied(self, run) -> None:
        """``run`` started every piece it could: it no longer waits for threads."""
        with self.lock:
            if run in self.runs:
                self.runs[run] = False
