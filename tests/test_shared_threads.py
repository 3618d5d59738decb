"""Several shots painted at once share the cluster's threads (``core.farm.shared_threads``, ``farm.batch.paint_shots``).

The sharing is checked on plain futures: a run alone takes every thread; two
runs wanting threads get half each; a run whose life waits lends its threads.
``paint_shots`` runs its shots side by side, hands back their reports in
order, and a shot that fails stops the others and is the error raised.
"""

import concurrent.futures
import threading
import time

import pytest

from core.errors import Cancelled
from core.farm.batch import paint_shots
from core.farm.shared_threads import SharedThreads

THREADS = {"tcp://a": 2, "tcp://b": 2}


def start_until_refused(shared: SharedThreads, run, futures: list) -> int:
    """Start pieces of ``run`` while it may; how many it started."""
    started = 0
    while shared.may_start(run, THREADS):
        future = concurrent.futures.Future()
        shared.started(run, future, sorted(shared.free(THREADS))[0])
        futures.append(future)
        started += 1
    return started


def test_a_run_alone_takes_every_thread_and_a_finished_piece_frees_its_thread():
    shared, futures = SharedThreads(), []
    shared.join("one")
    assert start_until_refused(shared, "one", futures) == 4
    assert shared.free(THREADS) == {}
    futures[0].set_result(None)                  # done, not yet seen by its run: free all the same
    assert sum(shared.free(THREADS).values()) == 1 and len(shared.futures()) == 3
    assert start_until_refused(shared, "one", futures) == 1


def test_a_run_that_waits_for_threads_gets_each_thread_freed_until_it_has_its_share():
    shared, futures = SharedThreads(), []
    shared.join("one")
    shared.join("two")
    assert shared.count() == 2
    assert start_until_refused(shared, "one", futures) == 4      # "two" does not want threads yet: all are lent
    assert start_until_refused(shared, "two", futures) == 0      # refused: it now waits for threads
    futures[0].set_result(None)
    assert start_until_refused(shared, "one", futures) == 0      # over its share, and "two" lacks two threads
    assert start_until_refused(shared, "two", futures) == 1
    futures[1].set_result(None)
    assert start_until_refused(shared, "one", futures) == 0
    assert start_until_refused(shared, "two", futures) == 1
    owners = [shared.running[f][0] for f in shared.futures()]
    assert owners.count("one") == 2 and owners.count("two") == 2
    shared.satisfied("two")                                      # it started all it could: it lends again
    futures[2].set_result(None)
    assert start_until_refused(shared, "one", futures) == 1
    shared.leave("two")                                          # its pieces no longer count
    assert shared.count() == 1
    assert [shared.running[f][0] for f in shared.futures()] == ["one"] * 2
    assert start_until_refused(shared, "one", futures) == 2


def test_shots_painted_at_once_run_side_by_side_and_give_their_reports_in_order():
    both = threading.Barrier(3, timeout=600)     # only against shots run one after another: they would hang

    def paint_shot(k, progress, cancel, shared):
        assert isinstance(shared, SharedThreads)
        progress(0.5, f"shot {k}")
        both.wait()                              # every shot is running at the same time
        progress(1.0, f"shot {k}")
        return {"shot": k}

    said = []
    assert paint_shots(paint_shot, 3, lambda fraction, message: said.append(fraction)) == [{"shot": k}
                                                                                           for k in range(3)]
    assert said[-1] == pytest.approx(1.0) and max(said) == said[-1]


def test_a_shot_that_fails_stops_the_others_and_its_error_is_raised():
    stopped = []

    def paint_shot(k, progress, cancel, shared):
        if k == 1:
            time.sleep(0.2)
            raise OSError("frame 3 of shot 1 cannot be read")
        while not cancel():
            time.sleep(0.01)
        stopped.append(k)
        raise Cancelled("The run was cancelled.")

    with pytest.raises(OSError, match="shot 1"):
        paint_shots(paint_shot, 3)
    assert sorted(stopped) == [0, 2]


def test_cancelling_stops_every_shot():
    flag = threading.Event()

    def paint_shot(k, progress, cancel, shared):
        flag.set()
        while not cancel():
            time.sleep(0.01)
        raise Cancelled("The run was cancelled.")

    with pytest.raises(Cancelled):
        paint_shots(paint_shot, 2, cancel=flag.is_set)
