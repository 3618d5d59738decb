"""The figures bench/farm.py works out from piece times: the sequential share, the transfer and the projection."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "bench"))
from farm import (  # noqa: E402
    CHAIN_KINDS,
    CHAIN_SENT,
    SENT,
    output_digests,
    projection,
    sent_bytes,
    sequential_share,
    settling,
)

from core.farm.frame_file import cluster_arguments  # noqa: E402
from core.motion.source import OPTICAL_FLOW_MOTION  # noqa: E402
from core.params import Params  # noqa: E402
from core.sequence.pieces import PieceKey, PieceKind, ShotPieces  # noqa: E402
from core.sequence.shot_settings import ShotSettings  # noqa: E402

FIRST = {"prepare": 0.5, "carry": 10.0, "shown": 3.0, "write": 1.0, "commit": 0.2}
LATER = {"prepare": 2.0, "motion": 2.0, "carry": 0.5, "judge": 4.0, "birth": 1.5, "shown": 3.0, "write": 2.0,
         "commit": 1.0, "bands": {1: (3.0, 3.0), 2: (4.0, 2.0), 8: (6.0, 0.6)}}
SIZES = {"prepare": 200.0, "motion": 40.0, "carry": 20.0, "judge": 30.0, "birth": 50.0, "lived": 10.0,
         "shown": 60.0, "write": 1.0}


def test_sequential_share_is_carry_birth_and_commit_over_every_piece():
    assert sequential_share(LATER) == pytest.approx(3.0 / 16.0)


def test_settling_is_the_longest_of_the_bands_the_driver_cuts_for_the_threads():
    assert [settling(LATER, threads) for threads in (1, 2, 3, 7, 8, 64)] == [3.0, 2.0, 2.0, 2.0, 0.6, 0.6]


def test_sent_bytes_count_each_transfer_of_a_frame():
    # the analysis to the carry and the births; the motion to them and the writing; the carried strokes to the
    # client, the bands and the births; the bands to the births; the strokes without their canvas to the client and
    # from it to the next carry and births; the births with it to laying and to writing; the frame shown to this
    # frame's writing and the next's
    assert sent_bytes(SIZES) == pytest.approx(2 * 200 + 3 * 40 + 3 * 20 + 30 + 3 * 10 + 2 * 50 + 2 * 60 + 1)
    assert sent_bytes(SIZES, CHAIN_SENT) == pytest.approx(2 * 200 + 2 * 40 + 3 * 20 + 30 + 3 * 10)


def test_the_transfers_counted_are_the_inputs_the_farm_hands_each_piece():
    """SENT and CHAIN_SENT against the arguments the farm gives each piece of frame 1 (``cluster_arguments`` over
    the declared pieces), a frame read again being no transfer: a piece graph changed in one place and not the
    other fails here."""
    shot = ShotSettings(Params(seed=1), 3, False, OPTICAL_FLOW_MOTION, (40, 60), measures=True)
    pieces = ShotPieces(shot, [Path("a.png"), Path("b.png")], (1, 2), Path("out"), analyse_ahead=True)
    results = {PieceKey(kind, index, 0): ("result", kind.value) for kind in PieceKind for index in (0, 1)}

    def handed(kinds) -> list:
        pairs = []
        for kind in kinds:
            piece = pieces.piece(PieceKey(kind, 1), [(0, 40)])
            for argument in cluster_arguments(piece, results, {0: ("result", "lived")}, shot, pieces.paths):
                if isinstance(argument, tuple) and argument[:1] == ("result",):
                    pairs.append((kind.value, argument[1]))
        return sorted(pairs)

    assert handed(PieceKind) == sorted(pair for pair in SENT if pair[0] != "client")
    assert handed(CHAIN_KINDS) == sorted(pair for pair in CHAIN_SENT if pair[0] != "client")


def test_projection_on_few_threads_is_bound_by_the_work():
    p = projection(FIRST, LATER, frames=11, threads=2)
    assert p["chain"] == pytest.approx(10.0 + 10 * (2.0 + 2.0))         # carry, births and the longest of 2 bands
    assert p["commits"] == pytest.approx(0.2 + 10 * 1.0)
    assert p["work"] == pytest.approx((14.5 + 10 * 15.0) / 2)
    assert p["fill"] == 0.5 and p["drain"] == 5.0
    assert p["total"] == pytest.approx(82.25 + 5.5)


def test_projection_on_many_threads_is_bound_by_the_chain_and_transfers_lengthen_it():
    p = projection(FIRST, LATER, frames=11, threads=64)
    assert p["total"] == pytest.approx(10.0 + 10 * 2.6 + 5.5)
    slow = projection(FIRST, LATER, frames=11, threads=64, transfer=1.0, chain_transfer=0.5)
    assert slow["chain"] == pytest.approx(36.0 + 10 * 0.5)
    assert slow["work"] == pytest.approx((14.5 + 10 * 18.0) / 64)


def test_shots_at_once_cut_their_judging_canvas_for_their_share_of_the_threads():
    # 4 shots on 8 threads: 2 threads each, so 2 bands (4.0 s of work, 2.0 s on the chain) where one shot has 8
    alone, shared = projection(FIRST, LATER, frames=11, threads=8), projection(FIRST, LATER, frames=11, threads=8,
                                                                               shots=4)
    assert alone["chain"] == pytest.approx(10.0 + 10 * 2.6) and shared["chain"] == pytest.approx(10.0 + 10 * 4.0)
    assert alone["work"] == pytest.approx((14.5 + 10 * 17.0) / 8)
    assert shared["work"] == pytest.approx((14.5 + 10 * 15.0) / 8)


def test_commits_beside_the_life_chain_bound_the_projection_when_they_take_longer():
    p = projection(FIRST, dict(LATER, commit=5.0), frames=11, threads=64)
    assert p["chain"] == pytest.approx(36.0) and p["commits"] == pytest.approx(50.2)
    assert p["total"] == pytest.approx(50.2 + 5.5)


def test_output_digests_take_the_painted_files_only_and_see_a_changed_byte(tmp_path):
    for name in ("painting_0001.png", "height_0001.exr", "strokes.lives", "report.json"):
        (tmp_path / name).write_bytes(b"abc")
    digests = output_digests(tmp_path)
    assert sorted(digests) == ["height_0001.exr", "painting_0001.png", "strokes.lives"]
    (tmp_path / "report.json").write_bytes(b"abd")
    assert output_digests(tmp_path) == digests
    (tmp_path / "strokes.lives").write_bytes(b"abd")
    assert output_digests(tmp_path) != digests
