"""Work spread over worker threads: pieces that tile the work, results in order, paintings that do not change."""

import threading

import numpy as np
import pytest
from test_rounds import photo, same_painting

from core import workers
from core.methods import huang11
from core.params import Params
from core.strokes import layout, rounds


@pytest.mark.parametrize("parts", [1, 2, 3, 7])
def test_balanced_runs_tile_the_items_in_runs_of_about_equal_cost(parts):
    cost = np.random.default_rng(parts).integers(1, 100, 500)
    runs = workers.balanced_runs(cost, parts, least=1)
    assert runs[0][0] == 0 and runs[-1][1] == 500
    assert all(a < b for a, b in runs) and all(runs[i][1] == runs[i + 1][0] for i in range(len(runs) - 1))
    assert len(runs) == parts
    sums = [int(cost[a:b].sum()) for a, b in runs]
    assert max(sums) - min(sums) <= 2 * cost.max()


def test_balanced_runs_leave_small_work_whole():
    cost = np.full(100, 10)
    assert workers.balanced_runs(cost, 4, least=500) == [(0, 50), (50, 100)]   # 1000 of work: two runs of 500
    assert workers.balanced_runs(cost, 4, least=600) == [(0, 100)]
    assert workers.balanced_runs(np.zeros(0), 4, least=1) == [(0, 0)]


def test_run_all_keeps_the_order_of_its_items_and_uses_threads():
    seen = set()

    def work(i):
        seen.add(threading.current_thread().name)
        return i * i

    assert workers.run_all(work, list(range(50))) == [i * i for i in range(50)]
    assert workers.run_all(work, [3]) == [9]
    if workers.worker_count() > 1:
        assert any(name.startswith("paint-relief") for name in seen)


def painted_by(monkeypatch, count: int):
    """A small painting made with ``count`` workers, every round, grid run and stroke run split between them;
    returns (painting, the most runs any piece of work was cut into)."""
    image = photo(3, 64, 72, "blobs")
    params = Params(seed=2, stroke_sizes=(16, 8, 4), layers=3, size_reference_megapixels=0.0046, detail_pass=True)
    pieces = []
    split = workers.balanced_runs
    monkeypatch.setattr(rounds, "balanced_runs", lambda *args: pieces.append(split(*args)) or pieces[-1])
    monkeypatch.setattr(rounds, "worker_count", lambda: count)
    monkeypatch.setattr(layout, "worker_count", lambda: count)
    monkeypatch.setattr(rounds, "WORKER_LEAST_SAMPLES", 1)
    monkeypatch.setattr(rounds, "WORKER_LEAST_STROKES", 1)
    monkeypatch.setattr(layout, "ANCHOR_LEAST_PIXELS", 1)
    return huang11.paint(image, params), max(len(p) for p in pieces)


@pytest.mark.parametrize("count", [2, 5])
def test_the_painting_does_not_depend_on_how_many_workers_share_it(monkeypatch, count):
    alone, cut = painted_by(monkeypatch, 1)
    assert cut == 1
    shared, cut = painted_by(monkeypatch, count)
    assert cut == count
    same_painting(alone, shared)
