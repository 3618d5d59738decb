"""The canvas caught while its strokes are laid, for a time-lapse of the painting being painted.

A ``Snapshots`` rides on a ``Canvas`` (``Canvas.snapshots``): every stroke
laid on it (``Canvas.lay``'s runs, a solid line's ``solid_stroke``) is
counted in the order it is laid, and after every ``step`` strokes the pixels
those strokes touched are kept with their values then, a *delta*. Only the
pixels touched are kept, so the snapshots hold about as many values as the
strokes cover, not a whole canvas each. The number of strokes is not known
before the last is laid: the step starts at 1 stroke and doubles whenever
2 x ``frames`` deltas are held, two neighbouring deltas merged into one, so
between ``frames`` and 2 x ``frames`` deltas are held at the end (fewer only
when the painting has fewer strokes than that), at about a millisecond of
processor time a delta at 1 megapixel, merging included (about 740 deltas
for the 6,692 strokes of 100 frames).

``frame_deltas()`` then gives the time-lapse: frame k of N (k = 1 .. N) shows the
canvas after the first round(k S / N) of the painting's S strokes rounded down
to a multiple of the final step, which is a power of two at most S / N, so
every frame shows more strokes than the one before when S >= N; the last
frame is the painting itself. Values are kept as float16 (the maps are
written as half floats): colour sRGB clipped to [0, 1], height, opacity.
"""

from __future__ import annotations

from typing import Iterator, List, NamedTuple, Optional, Tuple

import numpy as np


class Delta(NamedTuple):
    """The pixels a step's strokes touched and their values after it: index (K,) int64 flat (row * W + column),
    ascending; colour (K, 3) float16 sRGB [0, 1]; height (K,) float16 >= 0; opacity (K,) float16 [0, 1]."""

    index: np.ndarray
    colour: np.ndarray
    height: np.ndarray
    opacity: np.ndarray


def merged(first: Delta, second: Delta) -> Delta:
    """One delta of two consecutive ones: their pixels, each with its value after ``second``."""
    index = np.concatenate([second.index, first.index])
    kept, where = np.unique(index, return_index=True)
    return Delta(kept, *(np.concatenate([b, a])[where] for a, b in zip(first[1:], second[1:], strict=True)))


def frame_strokes(total: int, frames: int, step: int) -> List[int]:
    """The strokes each of ``frames`` time-lapse frames shows of a painting of ``total`` strokes caught every
    ``step``: round(k total / frames) rounded down to a multiple of ``step`` for k < frames, and ``total`` last."""
    shown = [(int(np.floor(k * total / frames + 0.5)) // step) * step for k in range(1, frames)]
    return shown + [total]


class Snapshots:
    """Catches an (H, W) canvas every ``step`` strokes while it is painted, for a time-lapse of ``frame_count``
    frames (module docstring). ``count`` strokes were laid in all; ``deltas`` hold the canvas after each step."""

    def __init__(self, shape: Tuple[int, int], frame_count: int):
        if frame_count < 1:
            raise ValueError(f"A time-lapse needs at least one frame, got {frame_count}.")
        self.shape = tuple(shape)
        self.frame_count = int(frame_count)
        self.step = 1
        self.since = 0
        self.count = 0
        self.deltas: List[Delta] = []
        self.touched = np.zeros(self.shape[0] * self.shape[1], bool)

    def until_next(self) -> int:
        """How many strokes may still be laid before the canvas is caught."""
        return self.step - self.since

    def laid(self, canvas, strokes: int, pixels: Optional[List[np.ndarray]] = None,
             box: Optional[Tuple[slice, slice]] = None) -> None:
        """``strokes`` (at most ``until_next()``) were laid on ``canvas``, touching the flat indices ``pixels``
        (a list of arrays) or the (rows, columns) ``box``; the canvas is caught when a step is full."""
        if box is not None:
            self.touched.reshape(self.shape)[box] = True
        for part in pixels or ():
            self.touched[part] = True
        self.since += strokes
        self.count += strokes
        if self.since >= self.step:
            self.catch(canvas)

    def catch(self, canvas) -> None:
        """Keep the touched pixels' values of ``canvas`` as a delta; merge pairs when 2 x frames are held."""
        index = np.flatnonzero(self.touched)
        self.touched[index] = False
        colour = np.take(canvas.colour.reshape(-1, 3), index, axis=0)
        np.clip(colour, 0.0, 1.0, out=colour)
        self.deltas.append(Delta(index, colour.astype(np.float16), np.take(canvas.height, index).astype(np.float16),
                                 np.take(canvas.opacity, index).astype(np.float16)))
        self.since = 0
        if len(self.deltas) >= 2 * self.frame_count:
            self.deltas = [merged(self.deltas[i], self.deltas[i + 1]) for i in range(0, len(self.deltas), 2)]
            self.step *= 2

    def held_bytes(self) -> int:
        """The bytes the deltas hold."""
        return sum(sum(array.nbytes for array in delta) for delta in self.deltas)

    def frame_deltas(self) -> Iterator[Tuple[int, List[Delta]]]:
        """(strokes shown, deltas) of each time-lapse frame but the last, in order (``frame_strokes``): the frame is
        the canvas before it (a bare canvas before the first) with ``deltas`` stored in order. The last frame is
        the painting itself."""
        applied = 0
        for strokes in frame_strokes(self.count, self.frame_count, self.step)[:-1]:
            upto = max(applied, strokes // self.step)
            yield strokes, self.deltas[applied:upto]
            applied = upto


def footprints_slice(footprints, first: int, stop: int):
    """The ``Footprints`` of strokes ``first`` .. ``stop`` - 1 of ``footprints`` (views of its arrays)."""
    from .compositing import Footprints

    starts = footprints.starts
    a, b = int(starts[first]), int(starts[stop])
    return Footprints(starts=starts[first:stop + 1] - a, pixel=footprints.pixel[a:b],
                      transmittance=footprints.transmittance[a:b], paint=footprints.paint[a:b],
                      deposit=footprints.deposit[a:b], height=footprints.height[a:b],
                      full=footprints.full[first:stop])


def lay_caught(canvas, parts: list, height_mode: str, build: float, kept: Optional[np.ndarray]) -> None:
    """``Canvas.lay`` of a run's footprint ``parts`` (consecutive pieces of its N strokes; ``kept`` optional (N,)
    bool, the strokes laid) on ``canvas`` with its ``snapshots`` caught between strokes: the run is laid in pieces
    that end where a step of the snapshots is full. Laying a run in pieces gives the same canvas as laying it at
    once (each pixel sees its strokes in the run's order)."""
    snapshots = canvas.snapshots
    first = 0
    for part in parts:
        count = len(part.starts) - 1
        laid = np.ones(count, bool) if kept is None else np.asarray(kept[first:first + count], bool)
        first += count
        cursor = 0
        while cursor < count:
            running = np.cumsum(laid[cursor:])
            need = snapshots.until_next()
            stop = count if running[-1] < need else cursor + int(np.searchsorted(running, need)) + 1
            piece, chosen = footprints_slice(part, cursor, stop), laid[cursor:stop]
            canvas.lay_run(piece, height_mode, build, None if chosen.all() else chosen)
            pixels = piece.pixel if chosen.all() else piece.pixel[np.repeat(chosen, np.diff(piece.starts))]
            snapshots.laid(canvas, int(np.count_nonzero(chosen)), [pixels])
            cursor = stop
