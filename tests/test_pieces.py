"""The declaration of a shot frame's pieces (core.sequence.pieces): what each piece needs, by typed keys."""

import dataclasses
from pathlib import Path

from core.motion.source import OPTICAL_FLOW_MOTION
from core.params import Params
from core.sequence.pieces import LifeStep, PieceKey, PieceKind, ShotPieces, judging_bands
from core.sequence.shot_settings import ShotSettings

PREPARE, MOTION, CARRY, JUDGE, BIRTH, SHOWN, WRITE = PieceKind
SHOT = ShotSettings(Params(seed=1), 3, False, OPTICAL_FLOW_MOTION, (40, 60), measures=True)
PIECES = ShotPieces(SHOT, [Path(f"frame_{n}.png") for n in (7, 8, 9)], (7, 8, 9), Path("out"), analyse_ahead=True)
UNMEASURED = ShotPieces(dataclasses.replace(SHOT, measures=False), PIECES.paths, PIECES.numbers, Path("out"),
                        analyse_ahead=True)


def needs(kind: PieceKind, index: int, bands=(), band: int = 0, pieces: ShotPieces = PIECES) -> tuple:
    return pieces.piece(PieceKey(kind, index, band), bands).needs


def test_the_first_frame_lives_from_its_picture_alone():
    assert needs(PREPARE, 0) == ()
    assert needs(CARRY, 0) == (PieceKey(PREPARE, 0),)
    assert needs(BIRTH, 0) == (PieceKey(CARRY, 0),)
    assert needs(SHOWN, 0) == (PieceKey(BIRTH, 0),)
    assert needs(WRITE, 0) == (PieceKey(PREPARE, 0), PieceKey(BIRTH, 0), PieceKey(SHOWN, 0))


def test_a_later_frame_lives_from_the_frame_before_its_motion_and_its_judging_bands():
    bands = [(0, 20), (20, 40)]
    assert needs(MOTION, 2) == (PieceKey(PREPARE, 1), PieceKey(PREPARE, 2))
    assert needs(CARRY, 2) == (PieceKey(PREPARE, 2), PieceKey(BIRTH, 1), PieceKey(MOTION, 2))
    assert needs(JUDGE, 2, bands, 1) == (PieceKey(CARRY, 2),)
    assert needs(BIRTH, 2, bands) == (PieceKey(PREPARE, 2), PieceKey(BIRTH, 1), PieceKey(MOTION, 2),
                                      PieceKey(CARRY, 2), PieceKey(JUDGE, 2, 0), PieceKey(JUDGE, 2, 1))
    assert needs(WRITE, 2)[3:] == (PieceKey(PREPARE, 1), PieceKey(SHOWN, 1), PieceKey(MOTION, 2))


def test_a_frame_not_measured_is_written_from_its_own_pieces_alone():
    assert needs(WRITE, 2, pieces=UNMEASURED) == (PieceKey(PREPARE, 2), PieceKey(BIRTH, 2), PieceKey(SHOWN, 2))
    assert UNMEASURED.needed_by_next(1) == {PieceKey(PREPARE, 1), PieceKey(BIRTH, 1)}


def test_a_life_complete_at_its_carry_has_no_judging_bands_and_the_keys_run_in_order():
    assert judging_bands(LifeStep(object(), None), 40, 4) == []
    made = set()
    for key in PIECES.life_start_keys(1) + PIECES.life_end_keys(1, [(0, 40)]):
        assert set(PIECES.piece(key, [(0, 40)]).needs) - {PieceKey(PREPARE, 0), PieceKey(BIRTH, 0),
                                                           PieceKey(SHOWN, 0)} <= made
        made.add(key)
    assert str(PieceKey(JUDGE, 3, 1)) == "judge1-3" and str(PieceKey(CARRY, 3)) == "carry-3"


def test_a_committed_frame_keeps_only_its_picture_strokes_and_frame_shown_for_the_next():
    assert PIECES.needed_by_next(0) == {PieceKey(PREPARE, 0), PieceKey(BIRTH, 0), PieceKey(SHOWN, 0)}
    assert PIECES.needed_by_next(1) == {PieceKey(PREPARE, 1), PieceKey(BIRTH, 1), PieceKey(SHOWN, 1)}

