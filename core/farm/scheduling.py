"""Which of a shot's pieces the farm starts next and on which worker: plain functions over plain data.

``Board`` says where a run stands: the pieces started and those made
(``core.sequence.pieces.PieceKey``), the frames whose strokes this process
holds, and each frame's number of judging bands once its carry is made.
``urgent`` lists the pieces that can start, most urgent first: the next
life first (its carry, its judging bands, its births), then what the next
two lives need, then laying and writing the frames that have lived, then
preparing frames further ahead, earlier frames first. ``free_workers`` and
``place`` keep no more pieces running than the workers have threads, and
send a piece to the free worker that holds most of its inputs. Handing Dask
everything at once lets a worker queue the next life behind other work
where its inputs are while another worker idles, and the life chain waits.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, Iterable, Iterator, Mapping, Optional, Set

from ..sequence.pieces import PieceKey, PieceKind, piece_needs
from .frame_file import READ, STROKES, input_source

MAX_BANDS = 8
"""Bands of rows a frame's judging canvas is laid in at most, side by side (one per worker thread up to this): a
stroke across a band's edge is laid in both, so more bands than this cost more than they save."""


@dataclass(frozen=True)
class Board:
    """Where a run of ``count`` frames stands: the pieces ``started`` (running or made) and ``made``, the frames
    ``lived`` whose strokes this process holds, and ``bands``: {frame index: its judging bands} once its carry is
    made; ``measures``: whether a frame's WRITE needs the frame before's SHOWN and the motion between them
    (``ShotSettings.measures``)."""

    count: int
    started: Set[PieceKey]
    made: Set[PieceKey]
    lived: Set[int]
    bands: Mapping[int, int]
    measures: bool = False


def band_count(threads: Mapping[str, int], shots: int = 1) -> int:
    """The bands a frame's judging canvas is cut into on workers of ``threads`` ({worker: threads}) shared by
    ``shots`` shots painted at once: one per thread of the shot's share (the threads over the shots), at least 1,
    at most MAX_BANDS. A band lays again every stroke across its edges, so bands beyond a shot's share cost work
    the other shots' pieces would have used."""
    return max(1, min(sum(threads.values()) // max(1, shots), MAX_BANDS))


def frames_ahead(committed: int, count: int, threads: Mapping[str, int]) -> int:
    """The first frame whose pieces wait, with frames ``committed`` on not committed: two frames a worker thread
    and two more beyond the last committed, at most ``count``."""
    return min(count, committed + 2 * max(sum(threads.values()), 1) + 2)


def urgent(board: Board, committed: int, living: int, ahead: int) -> Iterator[PieceKey]:
    """The pieces that can start now, most urgent first: frames ``committed`` on are not committed, frames
    ``living`` on have not lived, frames ``ahead`` on wait."""
    if ready_to_live(board, living):
        yield PieceKey(PieceKind.CARRY, living)
    judging = [PieceKey(PieceKind.JUDGE, living, band) for band in range(board.bands.get(living, 0))]
    yield from (key for key in judging + [PieceKey(PieceKind.BIRTH, living)] if ready(board, key))
    for index in range(living, min(living + 2, ahead)):
        yield from preparing(board, index)
    for index in range(committed, living):
        if ready(board, PieceKey(PieceKind.SHOWN, index)):
            yield PieceKey(PieceKind.SHOWN, index)
        if ready_to_write(board, index):
            yield PieceKey(PieceKind.WRITE, index)
    for index in range(living + 2, ahead):
        yield from preparing(board, index)


def preparing(board: Board, index: int) -> Iterator[PieceKey]:
    """The pieces frame ``index`` needs before it can live, not started yet: its PREPARE and (after the first
    frame) its MOTION."""
    kinds = (PieceKind.PREPARE, PieceKind.MOTION) if index > 0 else (PieceKind.PREPARE,)
    yield from (PieceKey(kind, index) for kind in kinds if ready(board, PieceKey(kind, index)))


def ready(board: Board, key: PieceKey) -> bool:
    """Whether the piece ``key`` can start: it is not started, its frame is in the run (and, for a JUDGE or BIRTH
    piece, its judging bands are known) and every input it needs (``pieces.piece_needs``) is at hand."""
    if key in board.started or key.index >= board.count:
        return False
    if key.kind in (PieceKind.JUDGE, PieceKind.BIRTH) and key.index not in board.bands:
        return False
    needs = piece_needs(key, board.bands.get(key.index, 0), board.measures)
    return all(at_hand(board, key, need) for need in needs)


def at_hand(board: Board, key: PieceKey, need: PieceKey) -> bool:
    """Whether the input ``need`` of the piece ``key`` is at hand where the farm takes it from
    (``frame_file.input_source``): a frame read again always, strokes once gathered here, a result once made."""
    source = input_source(key, need, need in board.started)
    if source == READ:
        return True
    if source == STROKES:
        return need.index in board.lived
    return need in board.made


def ready_to_live(board: Board, index: int) -> bool:
    """Whether frame ``index``'s life can start: its carry is ready (the frame before has lived, its own PREPARE
    and MOTION are made)."""
    return ready(board, PieceKey(PieceKind.CARRY, index))


def ready_to_write(board: Board, index: int) -> bool:
    """Whether frame ``index``'s maps can be written: its WRITE is ready (the frame is shown and, when the shot
    measures and after the first frame, the frame before is shown and the motion between them made)."""
    return ready(board, PieceKey(PieceKind.WRITE, index))


def free_workers(threads: Mapping[str, int], running: Iterable[str]) -> Dict[str, int]:
    """{worker: free threads} of the workers (``threads``: {worker: threads}) running fewer pieces than they have
    threads; ``running``: the worker of each piece running (one entry a piece)."""
    busy: Dict[str, int] = {}
    for worker in running:
        busy[worker] = busy.get(worker, 0) + 1
    return {w: n - busy.get(w, 0) for w, n in threads.items() if n > busy.get(w, 0)}


def place(free: Iterable[str], workers: Iterable[str], holders: Iterable[Iterable[str]]) -> Optional[str]:
    """The worker a piece goes to: of the ``free`` workers (else of all ``workers`` when none is free) the one
    that holds the most of its inputs (``holders``: the workers holding each input), the first by address on a
    tie; None when there is no worker."""
    candidates = sorted(free) or sorted(workers)
    if not candidates:
        return None
    held = {w: 0 for w in candidates}
    for holding in holders:
        for worker in holding:
            if worker in held:
                held[worker] += 1
    return max(candidates, key=lambda w: held[w])
