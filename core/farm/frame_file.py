"""A frame file read again where a piece runs, in place of the frame sent from another worker.

The farm hands the pieces that only need a frame's picture (the motion and
the writing, ``core.sequence.pieces``) a ``FrameFile``, not the PREPARE
piece's result, so only what is made (an analysis, a motion, the strokes,
the frame shown) travels between workers and no piece waits on the worker
that read a frame. A frame is read four times (its PREPARE piece, the
motion to it and from it, and its writing; five when the shot measures, by
the next frame's writing too): at 1920x1080 a PNG frame reads in about
35 ms, a multilayer EXR with its Vector pass in 0.2 to 0.4 s, against 25 MB
(58 MB with the Vector pass) to send. None of these reads is on the
strokes' life chain.
"""

from __future__ import annotations

from pathlib import Path
from typing import Mapping, NamedTuple

from ..sequence.frame_work import FrameInput, read_frame
from ..sequence.pieces import Piece, PieceKey, PieceKind
from ..sequence.shot_settings import ShotSettings

READ_AGAIN = {PieceKind.MOTION: True, PieceKind.WRITE: False}
"""The pieces that read their frames again: {kind: whether it reads the Vector pass too}."""

LIFE_CHAIN = (PieceKind.CARRY, PieceKind.BIRTH)
"""The pieces that take the frame before's strokes from this process, not from the worker that made them."""


class FrameFile(NamedTuple):
    """A frame file, read (``frame_work.read_frame``) each time its ``frame`` is asked for."""

    path: Path
    shot: ShotSettings
    vectors: bool

    @property
    def frame(self) -> FrameInput:
        """The frame read from ``path``, with its Vector pass when ``vectors`` and the shot's motion comes from
        it."""
        return read_frame(self.path, self.shot, self.vectors)


READ, STROKES, RESULT = "read", "strokes", "result"
"""Where the farm takes a piece's input from (``input_source``)."""


def input_source(piece: PieceKey, need: PieceKey, sent: bool = True) -> str:
    """Where the farm takes the input ``need`` of the piece ``piece``: READ, the frame file read again where the
    piece runs (a PREPARE input of a piece in ``READ_AGAIN``); STROKES, the frame's strokes gathered in this process
    (the frame before's, for a piece of the ``LIFE_CHAIN``, or a BIRTH input never ``sent``: a resumed frame's);
    RESULT, the result of the piece ``need`` (a future on a cluster)."""
    if need.kind is PieceKind.PREPARE and piece.kind in READ_AGAIN:
        return READ
    if need.kind is PieceKind.BIRTH and (piece.kind in LIFE_CHAIN or not sent):
        return STROKES
    return RESULT


def cluster_arguments(piece: Piece, results: Mapping[PieceKey, object], strokes: Mapping[int, object],
                      shot: ShotSettings, paths) -> list:
    """The arguments the farm gives ``piece``, one per key it needs, from where ``input_source`` says: a
    ``FrameFile`` of ``paths``, the strokes in ``strokes`` ({frame index: strokes gathered in this process}) or the
    entry in ``results``."""
    arguments = []
    for need in piece.needs:
        source = input_source(piece.key, need, need in results)
        if source == READ:
            arguments.append(FrameFile(paths[need.index], shot, READ_AGAIN[piece.key.kind]))
        elif source == STROKES:
            arguments.append(strokes[need.index])
        else:
            arguments.append(results[need])
    return arguments
