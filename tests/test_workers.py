"""Work spread over worker threads: pieces that tile the work, results in order, paintings that do not change."""

import threading

import numpy as np
import pytest
from oracles import same_painting
from test_rounds import photo

from core import tuning, workers
from core.methods import huang11
from core.params import Params
from core.strokes import canvas, layout, rounds


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


def test_bounded_runs_cut_the_items_in_order_into_the_longest_runs_within_the_limit():
    # worked out by hand: a run takes items while its total stays within the limit; an item over it stands alone
    assert workers.bounded_runs(np.array([3, 1, 2, 5, 1, 1, 9, 1]), 5) == [(0, 2), (2, 3), (3, 4), (4, 6), (6, 7),
                                                                          (7, 8)]
    assert workers.bounded_runs(np.array([2, 3, 5, 5]), 5) == [(0, 2), (2, 3), (3, 4)]          # totals of exactly 5
    assert workers.bounded_runs(np.array([7, 8]), 5) == [(0, 1), (1, 2)]
    assert workers.bounded_runs(np.array([0, 0, 4, 0, 0]), 4) == [(0, 5)]
    assert workers.bounded_runs(np.array([0.5, 0.25, 0.5]), 0.75) == [(0, 2), (2, 3)]
    assert workers.bounded_runs(np.zeros(0), 5) == []
    rng = np.random.default_rng(3)
    for limit in (1, 10, 50, 1000):
        cost = rng.integers(0, 40, 300)
        runs = workers.bounded_runs(cost, limit)
        assert [i for first, stop in runs for i in range(first, stop)] == list(range(300))      # each once, in order
        for first, stop in runs:
            assert cost[first:stop].sum() <= limit or stop - first == 1
            assert stop == 300 or cost[first:stop + 1].sum() > limit                          # no longer run fits


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
    """A small painting made with ``count`` workers, every round, grid run, stroke run and lay split between
    them; returns (painting, the most runs any piece of work was cut into, the most bands a lay was cut into)."""
    image = photo(3, 64, 72, "blobs")
    params = Params(seed=2, stroke_sizes=(16, 8, 4), layers=3, size_reference_megapixels=0.0046, detail_pass=True)
    pieces, bands = [], []
    split = workers.balanced_runs
    monkeypatch.setattr(rounds, "balanced_runs", lambda *args: pieces.append(split(*args)) or pieces[-1])
    cut = canvas.row_bands
    monkeypatch.setattr(canvas, "row_bands", lambda *args: bands.append(cut(*args)) or bands[-1])
    for module in (rounds, layout, canvas):
        monkeypatch.setattr(module, "worker_count", lambda: count)
    monkeypatch.setattr(tuning, "LAY_LEAST_ENTRIES", 1)
    monkeypatch.setattr(tuning, "WORKER_LEAST_SAMPLES", 1)
    monkeypatch.setattr(tuning, "WORKER_LEAST_STROKES", 1)
    monkeypatch.setattr(tuning, "ANCHOR_LEAST_PIXELS", 1)
    return huang11.paint(image, params), max(len(p) for p in pieces), max(len(b) for b in bands)


@pytest.mark.parametrize("count", [2, 5])
def test_the_painting_does_not_depend_on_how_many_workers_share_it(monkeypatch, count):
    alone, cut, banded = painted_by(monkeypatch, 1)
    assert cut == banded == 1
    shared, cut, banded = painted_by(monkeypatch, count)
    assert cut == banded == count
    same_painting(alone, shared)


def test_row_bands_cut_the_rows_into_runs_of_about_equal_entries_and_pick_each_bands_entries_in_order():
    rng = np.random.default_rng(4)
    first, second = rng.integers(0, 600, 300), rng.integers(0, 600, 300)                # two pieces' worth, 20 x 30
    values = [(pixel, pixel * 0.5) for pixel in (first, second)]
    bands = canvas.row_bands([first, second], [None, None], (20, 30), 3, least=50)
    assert len(bands) == 3 and bands[0][0] == 0 and bands[-1][1] == 20                 # runs of whole rows
    assert all(bands[k][1] == bands[k + 1][0] for k in range(2))
    picked = [canvas.band_entries(list(zip(values, [None, None], strict=True)), rows, (20, 30)) for rows in bands]
    joined = np.concatenate([first, second])
    assert sorted(np.concatenate([pixel for pixel, _ in picked]).tolist()) == sorted(joined.tolist())  # every entry once
    for (top, stop), (pixel, half) in zip(bands, picked, strict=True):
        inside = joined[(joined >= top * 30) & (joined < stop * 30)]
        np.testing.assert_array_equal(pixel, inside)                                     # in the run's order
        np.testing.assert_array_equal(half, pixel * 0.5)                                 # values follow their entry
        assert abs(len(pixel) - 200) <= 2 * 30 * 2 + 40                                   # about equal shares
    assert canvas.row_bands([first, second], [None, None], (20, 30), 3, least=400) == [(0, 20)]
    laid = [rng.uniform(size=300) < 0.5, None]
    for rows in canvas.row_bands([first, second], laid, (20, 30), 3, least=50) + [(0, 20)]:
        pixel, _ = canvas.band_entries(list(zip(values, laid, strict=True)), rows, (20, 30))
        wanted = np.concatenate([first[laid[0]], second])
        np.testing.assert_array_equal(pixel, wanted[(wanted >= rows[0] * 30) & (wanted < rows[1] * 30)])

def test_row_blocks_cover_every_row_once_in_blocks_of_about_the_block_pixels(monkeypatch):
    monkeypatch.setattr(tuning, "BLOCK_PIXELS", 70)
    seen = []
    workers.in_row_blocks(seen.append, 23, 10)
    rows = sorted((s.start, s.stop) for s in seen)
    assert rows[0][0] == 0 and rows[-1][1] == 23 and all(rows[i][1] == rows[i + 1][0] for i in range(len(rows) - 1))
    assert all(stop - start == 7 for start, stop in rows[:-1])                          # 70 px of 10-px rows
    seen.clear()
    workers.in_row_blocks(seen.append, 5, 1000)                                          # a row wider than a block
    assert sorted(s.start for s in seen) == [0, 1, 2, 3, 4]


def test_analysis_in_blocks_of_rows_gives_the_same_bytes_as_in_one_block(monkeypatch):
    from core.analysis import importance, orientation

    image = photo(5, 61, 53, "blobs")
    lum = image.mean(axis=2)
    energy = np.random.default_rng(5).random(lum.shape, dtype=np.float32)
    params = Params(rbf_grid_step=4)

    def analysed():
        return (importance.bilateral_filter(image, 3.0, 0.1),
                orientation.orientation_field(lum, energy, params, scale=0.06))

    whole = analysed()
    monkeypatch.setattr(tuning, "BLOCK_PIXELS", 200)                                   # 3 rows a block
    monkeypatch.setattr(tuning, "BILATERAL_SPLAT_PIXELS", 150)                                # 2 rows a splat
    monkeypatch.setattr(importance, "worker_count", lambda: 3)
    cut = analysed()
    for one, many in zip(whole, cut, strict=True):
        assert one.dtype == np.float32 and one.tobytes() == many.tobytes()


def test_run_all_called_from_a_worker_thread_works_in_that_thread_and_in_order():
    def inner(i):
        return threading.current_thread().name

    def outer(i):
        return i, workers.run_all(inner, list(range(4)))

    for _, names in workers.run_all(outer, list(range(8))):       # every worker waits for work of its own
        if workers.worker_count() > 1:
            assert len(set(names)) == 1 and names[0].startswith(workers.POOL_PREFIX)
