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

from ..sequence.pieces import PieceKey, PieceKind

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
    bands = board.bands.get(living)
    if bands is not None:
        judging = [PieceKey(PieceKind.JUDGE, living, band) for band in range(bands)]
        yield from (key for key in judging if key not in board.started)
        birth = PieceKey(PieceKind.BIRTH, living)
        if birth not in board.started and all(key in board.made for key in judging):
            yield birth
    for index in range(living, min(living + 2, ahead)):
        yield from preparing(board, index)
    for index in range(committed, living):
        if PieceKey(PieceKind.SHOWN, index) not in board.started:
            yield PieceKey(PieceKind.SHOWN, index)
        if ready_to_write(board, index):
            yield PieceKey(PieceKind.WRITE, index)
    for index in range(living + 2, ahead):
        yield from preparing(board, index)


def preparing(board: Board, index: int) -> Iterator[PieceKey]:
    """The pieces frame ``index`` needs before it can live, not started yet: its PREPARE and (after the first
    frame) its MOTION."""
    kinds = (PieceKind.PREPARE, PieceKind.MOTION) if index > 0 else (PieceKind.PREPARE,)
    yield from (PieceKey(kind, index) for kind in kinds if PieceKey(kind, index) not in board.started)


def ready_to_live(board: Board, index: int) -> bool:
    """Whether frame ``index``'s life can start: its carry is not started, the frame before has lived, and its own
    PREPARE and MOTION are made."""
    needs = [PieceKey(PieceKind.PREPARE, index)] + ([PieceKey(PieceKind.MOTION, index)] if index else [])
    return (index < board.count and PieceKey(PieceKind.CARRY, index) not in board.started
            and (index == 0 or index - 1 in board.lived) and all(key in board.made for key in needs))


def ready_to_write(board: Board, index: int) -> bool:
    """Whether frame ``index``'s maps can be written: its WRITE is not started, it is shown and, when the shot
    measures and after the first frame, the frame before is shown and the motion between them made."""
    before = [PieceKey(PieceKind.SHOWN, index - 1), PieceKey(PieceKind.MOTION, index)] if index and board.measures \
        else []
    return (PieceKey(PieceKind.WRITE, index) not in board.started
            and all(key in board.made for key in [PieceKey(PieceKind.SHOWN, index)] + before))


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
