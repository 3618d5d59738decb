"""The figures bench/farm.py works out from piece times: the sequential share, the transfer and the projection."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "bench"))
from farm import CHAIN_SENT, output_digests, projection, sent_bytes, sequential_share  # noqa: E402

FIRST = {"prepared": 0.5, "life": 10.0, "shown": 3.0, "written": 1.0, "commit": 0.2}
LATER = {"prepared": 2.0, "motion": 2.0, "life": 4.0, "shown": 3.0, "written": 2.0, "commit": 1.0}
SIZES = {"prepared": 200.0, "motion": 40.0, "life": 50.0, "shown": 60.0, "written": 1.0}


def test_sequential_share_is_life_and_commit_over_every_piece():
    assert sequential_share(LATER) == pytest.approx(5.0 / 14.0)


def test_sent_bytes_count_each_transfer_of_a_frame():
    # strokes: to the client, from it to the next life, to laying, to writing; the frame shown to this frame's
    # writing and the next's; the motion to the life and the writing
    assert sent_bytes(SIZES) == pytest.approx(200 + 2 * 40 + 4 * 50 + 2 * 60 + 1)
    assert sent_bytes(SIZES, CHAIN_SENT) == pytest.approx(200 + 40 + 2 * 50)


def test_projection_on_few_threads_is_bound_by_the_work():
    p = projection(FIRST, LATER, frames=11, threads=2)
    assert p["chain"] == pytest.approx(10.0 + 10 * 5.0)
    assert p["work"] == pytest.approx((14.5 + 10 * 13.0) / 2)
    assert p["fill"] == 0.5 and p["drain"] == 5.0
    assert p["total"] == pytest.approx(72.25 + 5.5)


def test_projection_on_many_threads_is_bound_by_the_chain_and_transfers_lengthen_it():
    p = projection(FIRST, LATER, frames=11, threads=64)
    assert p["total"] == pytest.approx(60.0 + 5.5)
    slow = projection(FIRST, LATER, frames=11, threads=64, transfer=1.0, chain_transfer=0.5)
    assert slow["chain"] == pytest.approx(60.0 + 10 * 0.5)
    assert slow["work"] == pytest.approx((14.5 + 10 * 14.0) / 64)


def test_output_digests_take_the_painted_files_only_and_see_a_changed_byte(tmp_path):
    for name in ("painting_0001.png", "height_0001.exr", "strokes.lives", "report.json"):
        (tmp_path / name).write_bytes(b"abc")
    digests = output_digests(tmp_path)
    assert sorted(digests) == ["height_0001.exr", "painting_0001.png", "strokes.lives"]
    (tmp_path / "report.json").write_bytes(b"abd")
    assert output_digests(tmp_path) == digests
    (tmp_path / "strokes.lives").write_bytes(b"abd")
    assert output_digests(tmp_path) != digests
