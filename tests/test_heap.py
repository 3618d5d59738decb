"""The C heap while painting: a stroke's freed temporaries are reused, not faulted in again (glibc only)."""

from __future__ import annotations

import resource
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest

from core import heap

pytestmark = pytest.mark.skipif(heap._glibc() is None, reason="the C library is not glibc")


def faults_of_repeated_work(rounds: int = 4) -> int:
    """Minor page faults of the later rounds of allocating, touching and freeing ten 8 MB arrays."""
    def work():
        arrays = [np.ones(2 * 2**20, np.float32) for _ in range(10)]
        del arrays
    work()
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    for _ in range(rounds):
        work()
    return resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before


def test_freed_blocks_are_reused_inside_and_returned_after():
    with heap.reused_heap():
        inside = faults_of_repeated_work()
    outside = faults_of_repeated_work()
    pages = 4 * 10 * 8 * 2**20 // 4096                      # every 4 KB page of every round
    assert inside < 0.02 * pages                             # reused: hardly any page faulted in again
    assert outside > 4 * inside + 0.05 * pages               # glibc's defaults hand it back each round (fewer
                                                             # faults than pages where huge pages back the arrays)


def test_threads_and_nesting_share_one_setting():
    errors = []

    def paint():
        try:
            with heap.reused_heap(), heap.reused_heap():
                assert heap._users >= 2
        except AssertionError as error:
            errors.append(error)
    threads = [threading.Thread(target=paint) for _ in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors and heap._users == 0


WORKER_THEN_MAIN = """
import resource, sys, threading
import numpy as np
from core import heap

with heap.reused_heap():
    worker = threading.Thread(target=lambda: [np.ones(2 * 2**20, np.float32) for _ in range(10)])
    worker.start()
    worker.join()
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    arrays = [np.ones(2 * 2**20, np.float32) for _ in range(10)]
    print(resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before)
"""


def test_blocks_freed_by_a_worker_thread_are_reused_by_the_main_thread():
    # a fresh process: the heap's arenas are set once per process
    done = subprocess.run([sys.executable, "-c", WORKER_THEN_MAIN], capture_output=True, text=True,
                          cwd=Path(__file__).resolve().parents[1], check=True)
    assert int(done.stdout) < 0.02 * 10 * 8 * 2**20 // 4096   # the worker's freed pages are faulted in no more
