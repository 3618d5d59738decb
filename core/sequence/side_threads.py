"""The side threads of a shot painted in one process (``shot.Run.paint_from``): the next frame read and its motion
found (``FrameAhead``), the frame before laid as shown and its maps written (``FrameBehind``), each beside the
life of the frame between them."""

from __future__ import annotations

import concurrent.futures
from typing import Dict

from .frame_step import PaintedFrame
from .pieces import Piece, PieceKey, PieceKind, ShotPieces


class SideThread:
    """A side thread for one piece of work at a time (``pending``, its future), waited for on leaving the
    ``with`` block."""

    def __init__(self, name: str):
        self.pool = concurrent.futures.ThreadPoolExecutor(1, thread_name_prefix=name)
        self.pending = None

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.pool.shutdown(wait=True)


class FrameBehind(SideThread):
    """One frame's SHOWN and WRITE pieces made on a side thread while the next frame's life is made: ``start``
    hands it the pieces with the results they need, ``finished`` waits for them."""

    def __init__(self):
        super().__init__("paint-relief-frame")

    def start(self, index: int, painted: PaintedFrame, shown: Piece, write: Piece,
              made: Dict[PieceKey, object]) -> None:
        """Make frame ``index``'s ``shown`` then ``write`` pieces on the side thread from the results in ``made``
        now (``write`` needs ``shown``'s result, the rest from ``made``); ``painted`` is the frame's strokes."""
        shown_inputs = [made[key] for key in shown.needs]
        write_inputs = [None if key == shown.key else made[key] for key in write.needs]
        at = write.needs.index(shown.key)

        def side():
            shown_now = shown.make(*shown_inputs)
            write_inputs[at] = shown_now
            return shown_now, write.make(*write_inputs)

        self.pending = index, painted, self.pool.submit(side)

    def finished(self):
        """(index, strokes, the frame as shown, the frame written) of the frame started last, once made (its failure
        raised), or None when none is pending."""
        if self.pending is None:
            return None
        index, painted, future = self.pending
        self.pending = None
        shown_now, written = future.result()
        return index, painted, shown_now, written


class FrameAhead(SideThread):
    """The next frame's PREPARE and MOTION pieces (reading it, the motion to it) made on a side thread while this
    frame's life is made: ``start`` hands it the pieces, ``finished`` waits for them. Its analysis is left to its
    CARRY: made ahead, it would overlap the life's own peak of memory (at 1920x1080 +650 MiB for a few per cent of
    time)."""

    def __init__(self):
        super().__init__("paint-relief-ahead")

    def start(self, pieces: ShotPieces, index: int, made: Dict[PieceKey, object]) -> None:
        """Make frame ``index``'s PREPARE and MOTION pieces (``index`` >= 1) on the side thread, the frame before's
        PREPARE result taken from ``made`` now."""
        prepare = pieces.piece(PieceKey(PieceKind.PREPARE, index))
        motion = pieces.piece(PieceKey(PieceKind.MOTION, index))
        before = made[PieceKey(PieceKind.PREPARE, index - 1)]

        def side() -> Dict[PieceKey, object]:
            prepared = prepare.make()
            moved = motion.make(before, prepared)
            return {prepare.key: prepared, motion.key: moved}

        self.pending = self.pool.submit(side)

    def finished(self) -> Dict[PieceKey, object]:
        """{key: result} of the pieces started last, once made (their failure raised); empty when none is
        pending."""
        if self.pending is None:
            return {}
        future, self.pending = self.pending, None
        return future.result()
