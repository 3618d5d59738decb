"""The farm's choices (core.farm.scheduling) on plain data: which piece of a shot starts next and on which worker,
with no Dask."""

import random
from pathlib import Path

import pytest

from core.farm.frame_file import cluster_arguments
from core.farm.scheduling import (
    MAX_BANDS,
    Board,
    band_count,
    frames_ahead,
    free_workers,
    place,
    ready_to_live,
    ready_to_write,
    urgent,
)
from core.motion.source import OPTICAL_FLOW_MOTION
from core.params import Params
from core.sequence.pieces import PieceKey, PieceKind, ShotPieces, row_bands
from core.sequence.shot_settings import ShotSettings

PREPARE, MOTION, CARRY, JUDGE, BIRTH, SHOWN, WRITE = PieceKind


def key(kind: PieceKind, index: int, band: int = 0) -> PieceKey:
    return PieceKey(kind, index, band)


def board(made=(), running=(), lived=(), bands=None, count=6, measures=False) -> Board:
    """A run of ``count`` frames: the keys ``made`` and those still ``running`` started."""
    return Board(count, set(made) | set(running), set(made), set(lived), bands or {}, measures)


def test_the_first_frame_prepares_then_lives_before_the_frames_after_it_prepare():
    start = board()
    assert list(urgent(start, 0, 0, 3)) == [key(PREPARE, 0), key(PREPARE, 1), key(MOTION, 1), key(PREPARE, 2),
                                            key(MOTION, 2)]
    prepared = board(made=[key(PREPARE, 0)])
    assert list(urgent(prepared, 0, 0, 1))[0] == key(CARRY, 0)


def test_a_carried_frame_judges_its_bands_then_births_and_a_completed_life_births_at_once():
    carried = board(made=[key(PREPARE, 1), key(MOTION, 1), key(CARRY, 1)], lived=[0], bands={1: 3})
    assert list(urgent(carried, 1, 1, 2))[:3] == [key(JUDGE, 1, 0), key(JUDGE, 1, 1), key(JUDGE, 1, 2)]
    life = [key(PREPARE, 1), key(MOTION, 1), key(CARRY, 1)]
    judged = board(made=life + [key(JUDGE, 1, 0), key(JUDGE, 1, 1)], running=[key(JUDGE, 1, 2)], lived=[0],
                   bands={1: 3})
    assert key(BIRTH, 1) not in list(urgent(judged, 1, 1, 2))
    done = board(made=life + [key(JUDGE, 1, b) for b in range(3)], lived=[0], bands={1: 3})
    assert list(urgent(done, 1, 1, 2))[0] == key(BIRTH, 1)
    complete = board(made=[key(CARRY, 1)], lived=[0], bands={1: 0})
    assert list(urgent(complete, 1, 1, 2))[0] == key(BIRTH, 1)


def test_a_frame_lives_only_after_the_frame_before_has_lived():
    ready = [key(PREPARE, 2), key(MOTION, 2)]
    assert not ready_to_live(board(made=ready, lived=[0]), 2)
    assert ready_to_live(board(made=ready, lived=[1]), 2)
    assert not ready_to_live(board(made=ready + [key(CARRY, 2)], lived=[1]), 2)
    assert not ready_to_live(board(made=ready, lived=[5], count=5), 5)


def test_a_measured_frame_is_written_once_it_and_the_frame_before_are_shown():
    lived = [key(PREPARE, 0), key(BIRTH, 0), key(PREPARE, 1), key(BIRTH, 1)]
    assert ready_to_write(board(made=lived + [key(SHOWN, 0)], measures=True), 0)
    assert not ready_to_write(board(made=lived + [key(SHOWN, 1), key(MOTION, 1)], measures=True), 1)
    assert not ready_to_write(board(made=lived + [key(SHOWN, 0), key(SHOWN, 1)], measures=True), 1)
    assert ready_to_write(board(made=lived + [key(SHOWN, 0), key(SHOWN, 1), key(MOTION, 1)], measures=True), 1)
    assert not ready_to_write(board(made=lived + [key(SHOWN, 0), key(SHOWN, 1), key(MOTION, 1), key(WRITE, 1)],
                                    measures=True), 1)


def test_a_frame_not_measured_is_written_once_it_is_shown():
    lived = [key(PREPARE, 1), key(BIRTH, 1)]
    assert ready_to_write(board(made=lived + [key(SHOWN, 1)]), 1)
    assert not ready_to_write(board(made=lived + [key(SHOWN, 0), key(MOTION, 1)]), 1)
    assert not ready_to_write(board(made=lived + [key(SHOWN, 1), key(WRITE, 1)]), 1)


def test_lived_frames_are_shown_and_written_before_frames_further_ahead_prepare():
    lived = board(made=[key(PREPARE, i) for i in range(4)] + [key(MOTION, i) for i in range(1, 4)]
                  + [key(BIRTH, 0), key(SHOWN, 0)], lived=[0, 1])
    order = list(urgent(lived, 0, 2, 6))
    assert order.index(key(SHOWN, 1)) < order.index(key(PREPARE, 4))
    assert key(WRITE, 0) in order and key(WRITE, 1) not in order


def test_frames_ahead_and_bands_follow_the_threads():
    assert frames_ahead(3, 100, {"a": 1, "b": 1}) == 3 + 2 * 2 + 2
    assert frames_ahead(3, 6, {"a": 4}) == 6
    assert frames_ahead(0, 100, {}) == 4
    assert [band_count({"a": n}) for n in (0, 1, 3, 20)] == [1, 1, 3, MAX_BANDS]
    # shots painted at once share the threads: each cuts its judging canvas for its share alone
    assert [band_count({"a": 2, "b": 2}, shots) for shots in (0, 1, 2, 3, 4, 5)] == [4, 4, 2, 1, 1, 1]
    assert band_count({"a": 64}, 4) == MAX_BANDS
    assert row_bands(10, 3) == [(0, 3), (3, 6), (6, 10)]
    assert row_bands(2, 5) == [(0, 1), (1, 2)]


def test_free_workers_count_the_pieces_each_runs():
    threads = {"tcp://a": 2, "tcp://b": 1, "tcp://c": 1}
    assert free_workers(threads, ["tcp://a", "tcp://b"]) == {"tcp://a": 1, "tcp://c": 1}
    assert free_workers(threads, ["tcp://a", "tcp://a", "tcp://b", "tcp://c"]) == {}


def test_a_piece_goes_to_the_free_worker_holding_most_of_its_inputs():
    workers = ["tcp://a", "tcp://b", "tcp://c"]
    assert place(["tcp://b", "tcp://c"], workers, [["tcp://c"], ["tcp://a", "tcp://c"], ["tcp://b"]]) == "tcp://c"
    assert place(["tcp://c", "tcp://b"], workers, []) == "tcp://b"
    assert place([], workers, [["tcp://c"]]) == "tcp://c"
    assert place([], [], [["tcp://c"]]) is None


@pytest.mark.parametrize("measures", [False, True])
@pytest.mark.parametrize("bands", [0, 2])
@pytest.mark.parametrize("start", [0, 2])
def test_the_farm_starts_each_piece_once_its_declared_inputs_are_made_and_starts_them_all(measures, bands, start):
    """A run driven as ``core.farm.sequence.ClusterRun`` drives it, the pieces running finishing one at a time in a
    random order: each piece ``urgent`` names gets its arguments from the pieces' declaration
    (``ShotPieces.piece``, through ``cluster_arguments`` over the pieces made: a KeyError is a piece started
    before an input it needs), and every frame is committed (no piece is held back by a need the declaration does
    not make)."""
    count = 5
    shot = ShotSettings(Params(seed=1), 3, False, OPTICAL_FLOW_MOTION, (40, 60), measures=measures)
    pieces = ShotPieces(shot, [Path(f"frame_{n}.png") for n in range(count)], range(count), Path("out"),
                        analyse_ahead=True)
    for seed in range(8):
        order = random.Random(seed)
        made, running, strokes, cut = {}, [], {}, {}
        if start:       # a resumed run: the frame before's strokes gathered, its frame shown made again
            strokes[start - 1] = "strokes"
            if measures:
                made[key(SHOWN, start - 1)] = "shown"
        committed = living = start
        while committed < count:
            started = set(made) | set(running)
            for now in urgent(Board(count, started, set(made), set(strokes), cut, measures), committed, living,
                              count):
                cluster_arguments(pieces.piece(now, [(0, 40)] * cut.get(now.index, 0)), made, strokes, shot,
                                  pieces.paths)
                running.append(now)
            assert running, f"the run stalls at frame {living} (committed {committed})"
            done = running.pop(order.randrange(len(running)))
            made[done] = done.kind.value
            if key(CARRY, living) in made and living not in cut:
                cut[living] = bands if living else 0
            if key(BIRTH, living) in made:
                strokes[living] = "strokes"
                living += 1
            while committed < living and key(WRITE, committed) in made:
                for gone in [k for k in made if k.index == committed and k.kind is not SHOWN]:
                    del made[gone]
                made.pop(key(SHOWN, committed - 1), None)
                strokes.pop(committed - 1, None)
                committed += 1
