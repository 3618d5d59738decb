"""The canvas being painted: colour, coverage, height and opacity (ALGORITHM §3, §5, §6)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np

from .. import tuning
from ..workers import balanced_runs, run_all, worker_count
from .compositing import Footprints


@dataclass
class Canvas:
    """Painted state of an (H, W) canvas, or of H rows of a taller frame.

    colour:   float32 (H, W, 3) sRGB [0, 1]; starts as the canvas colour.
    coverage: float32 (H, W) [0, 1]; 1 - prod(1 - I) of every bristle that touched a pixel.
    height:   float32 (H, W) >= 0; paint height, 1 = one full bristle's contact.
    opacity:  float32 (H, W) [0, 1]; accumulated stroke opacity.
    first_row: the frame's row that row 0 holds; frame_height: the frame's rows (None: H, the canvas is the frame).
    Strokes are placed in the frame, and only what they lay on the canvas's rows is laid (``lay``).
    only: (H, W) bool, the pixels strokes are laid on, the others keeping what they hold (None: every pixel).
    snapshots: a ``snapshots.Snapshots`` that catches the canvas while its strokes are laid, for a time-lapse
    (None: not caught; a still's whole canvas only).
    """

    colour: np.ndarray
    coverage: np.ndarray
    height: np.ndarray
    opacity: np.ndarray
    first_row: int = 0
    frame_height: Optional[int] = None
    only: Optional[np.ndarray] = None
    snapshots: Optional[object] = None

    @classmethod
    def blank(cls, shape: tuple, canvas_colour, rows: Optional[Tuple[int, int]] = None) -> "Canvas":
        """A bare canvas of (H, W) = ``shape`` in ``canvas_colour`` (sRGB triple); with ``rows`` = (first, stop),
        of those rows of an (H, W) frame only."""
        frame_height, w = shape
        first, stop = rows or (0, frame_height)
        h = stop - first
        colour = np.empty((h, w, 3), dtype=np.float32)
        colour[...] = np.asarray(canvas_colour, dtype=np.float32)
        zeros = lambda: np.zeros((h, w), dtype=np.float32)  # noqa: E731
        return cls(colour, zeros(), zeros(), zeros(), first, None if rows is None else frame_height)

    @property
    def frame_shape(self) -> tuple:
        """(frame height, W): the shape of the frame strokes are placed in."""
        h, w = self.height.shape
        return (self.frame_height or h, w)

    def lay(self, footprints: Footprints | list, height_mode: str, build: float, kept: np.ndarray = None) -> None:
        """Lay a run of strokes' footprints on the canvas (``lay_run``), caught between strokes by the canvas's
        ``snapshots`` when it has them (``snapshots.lay_caught``: the same canvas)."""
        if self.snapshots is None:
            self.lay_run(footprints, height_mode, build, kept)
        else:
            from .snapshots import lay_caught

            lay_caught(self, [footprints] if isinstance(footprints, Footprints) else list(footprints), height_mode,
                       build, kept)

    def lay_run(self, footprints: Footprints | list, height_mode: str, build: float, kept: np.ndarray = None) -> None:
        """Lay a run of strokes' footprints on the canvas, each after the one before (ALGORITHM §5, §6).

        footprints: the run's Footprints, or a list of the Footprints of its
        consecutive pieces (laid as one run, without joining them first).
        kept: optional (N,) bool over the run's N strokes, lay only those
        where it is True (as if the others were not in the run).
        The k-th stroke to touch a pixel in the run is laid on it in the k-th
        pass, every pixel of a pass at once: each pixel sees its strokes in
        the run's order, so the canvas is exactly what laying the strokes one
        by one gives. The arithmetic is ``composite``'s. Bands of
        rows holding about equal shares of the entries are laid side by side
        on the worker threads (a pixel's strokes all lie in its band), each
        band picking its own entries out of the pieces.
        """
        pieces, first = [], 0
        for part in [footprints] if isinstance(footprints, Footprints) else footprints:
            counts = np.diff(part.starts)
            part_kept = None if kept is None else np.asarray(kept[first:first + len(counts)], bool)
            first += len(counts)
            if part.pixel.size == 0 or (part_kept is not None and not part_kept.any()):
                continue
            laid = None if part_kept is None or part_kept.all() else np.repeat(part_kept, counts)
            entries = (part.pixel, part.transmittance, part.paint, part.deposit, part.height,
                       np.repeat(inverse_full(part.full), counts))
            if self.frame_height is not None or self.only is not None:
                entries, laid = self.laid_here(entries, laid)
            pieces.append((entries, laid))
        if not pieces:
            return
        bands = row_bands([entries[0] for entries, _ in pieces], [laid for _, laid in pieces], self.height.shape,
                          worker_count(), tuning.LAY_LEAST_ENTRIES)
        run_all(lambda rows: self._lay_entries(*band_entries(pieces, rows, self.height.shape), height_mode, build),
                bands)

    def laid_here(self, entries: tuple, laid: Optional[np.ndarray]) -> tuple:
        """(entries, None): the entries of a piece of footprints placed in the frame (pixel (E,) the frame's flat
        index, then the value arrays; ``laid`` (E,) bool or None, those laid) that fall on the canvas's rows and on
        its ``only`` pixels, pixel made the canvas's flat index."""
        h, w = self.height.shape
        pixel = entries[0] - self.first_row * w
        inside = (pixel >= 0) & (pixel < h * w)
        if self.only is not None:
            inside &= np.take(self.only.reshape(-1), np.where(inside, pixel, 0))
        if laid is not None:
            inside &= laid
        picked = np.flatnonzero(inside)
        return (np.take(pixel, picked),) + tuple(np.take(values, picked, axis=0) for values in entries[1:]), None

    def _lay_entries(self, pixel: np.ndarray, transmittance: np.ndarray, paint: np.ndarray, deposit: np.ndarray,
                     raised: np.ndarray, inverse: np.ndarray, height_mode: str, build: float) -> None:
        """``lay`` of E entries in the run's order: pixel (E,) flat index, the stroke's transmittance, paint
        (E, 3), deposit and height there, and inverse (E,) 1 / the stroke's full deposit."""
        keys = pixel.astype(np.int32) if self.height.size < 2 ** 31 else pixel
        by_pixel = np.argsort(keys, kind="stable")
        ordered = keys[by_pixel]
        new = np.ones(len(ordered), bool)
        np.not_equal(ordered[1:], ordered[:-1], out=new[1:])
        position = np.arange(len(ordered))
        rank = position - np.maximum.accumulate(np.where(new, position, 0))
        order = by_pixel[np.argsort(rank, kind="stable")]      # pass after pass, each in the run's order
        passes = np.bincount(rank)
        at_all = np.take(pixel, order)
        transmittance, deposit = np.take(transmittance, order), np.take(deposit, order)
        raised = np.take(raised, order)
        paint = np.take(paint, order, axis=0)
        inverse = np.take(inverse, order)
        colour, coverage, height, opacity = self.flat()
        done = 0
        for size in passes.tolist():
            part = slice(done, done + size)
            done += size
            at = at_all[part]
            colour[at], coverage[at], height[at], opacity[at] = composite(
                np.take(colour, at, axis=0), np.take(coverage, at), np.take(height, at), np.take(opacity, at),
                transmittance[part], paint[part], deposit[part], raised[part], inverse[part], height_mode, build)

    def flat(self) -> tuple:
        """Views of the canvas over its H W pixels: colour (H W, 3), coverage, height, opacity (H W,); what is
        written through them is written on the canvas. ValueError if an array is not C-contiguous (it would be
        reshaped into a copy, and the writes lost)."""
        arrays = (self.colour, self.coverage, self.height, self.opacity)
        if not all(values.flags.c_contiguous for values in arrays):
            raise ValueError("the canvas's colour, coverage, height and opacity must be C-contiguous arrays "
                             "(laying writes through flat views of them)")
        return self.colour.reshape(-1, 3), self.coverage.reshape(-1), self.height.reshape(-1), self.opacity.reshape(-1)


def row_bands(pixels: list, laid: list, shape: tuple, parts: int, least: int) -> list:
    """[(first, stop), ...] runs of whole rows of an (H, W) canvas, at most ``parts`` of them, holding about equal
    shares of the entries of pieces of a run: ``pixels`` [(E_i,) flat pixel indices, ...] and ``laid``
    [(E_i,) bool or None (every entry), ...] the entries laid, counted on every tuning.BAND_SAMPLE-th entry. At least
    ``least`` entries each (``balanced_runs``: one run of every row when there are fewer than 2 ``least``)."""
    h, w = shape
    if parts <= 1:
        return [(0, h)]
    rows = np.zeros(h, np.int64)
    for pixel, selected in zip(pixels, laid, strict=True):
        every = tuning.BAND_SAMPLE
        sample = pixel[::every] if selected is None else pixel[::every][selected[::every]]
        rows += np.bincount(sample // w, minlength=h)
    return balanced_runs(rows * tuning.BAND_SAMPLE, parts, least)


def band_entries(pieces: list, rows: tuple, shape: tuple) -> tuple:
    """The entries of ``pieces`` [((pixel, value arrays ...), laid (E,) bool or None), ...] laid on rows
    [first, stop) of an (H, W) canvas, joined piece after piece: (pixel, value arrays ...)."""
    first, stop = rows
    whole = first == 0 and stop == shape[0]
    parts = []
    for entries, laid in pieces:
        pixel = entries[0]
        inside = laid if whole else (pixel >= first * shape[1]) & (pixel < stop * shape[1])
        if laid is not None and not whole:
            inside &= laid
        if inside is None:
            parts.append(entries)
            continue
        picked = np.flatnonzero(inside)
        parts.append(tuple(np.take(values, picked, axis=0) for values in entries))
    if len(parts) == 1:
        return parts[0]
    return tuple(np.concatenate(arrays) for arrays in zip(*parts, strict=True))


def inverse_full(full: np.ndarray) -> np.ndarray:
    """(N,) float32 1 / full where full > 0, else 0 (a stroke that deposits nothing changes no height)."""
    full = np.asarray(full, np.float32)
    return np.divide(np.float32(1.0), full, out=np.zeros_like(full), where=full > 0)


def composite(colour: np.ndarray, coverage: np.ndarray, height: np.ndarray, opacity: np.ndarray,
              transmittance: np.ndarray, paint: np.ndarray, deposit: np.ndarray, stroke_height: np.ndarray,
              inverse: np.ndarray, height_mode: str, build: float) -> tuple:
    """One stroke laid on canvas values (ALGORITHM §6): new (colour, coverage, height, opacity), all float32.

    Every argument is an array over the same pixels (colour and paint with
    a last axis of 3): transmittance T the share of the old colour the
    stroke lets show through, paint what it lays on top, deposit and
    stroke_height its contact and height there, inverse 1 / its full
    deposit (its 90th-percentile deposit; 0 if it has none).
    Colour by Eq. 4 (folded): C T + paint; coverage as the same stroke
    painted in white. The stroke's opacity o = a f, with a = 1 - T its
    colour alpha and f = min(1, deposit / full) how fully its paint covers,
    so the opacity follows the bristles' real footprint and fades with them
    at the edges and ends. Height, with h the stroke's height:
    'over'        H <- H + a (h - f H)          (= o h + (1 - o) H where f = 1),
    'accumulate'  H <- H + a (h - f (1 - b) H)  (= o (h + b H) + (1 - o) H where f = 1),
    b = ``build`` in [0, 1), never below 0. Where the stroke covers fully
    this is the paper's weighted sum (or bounded build-up: H tends to
    h / (1 - b) under repeated strokes, and to h / (f (1 - b)), no more
    than the full stroke's height / (1 - b), at its edges). At its feathered
    edges and ends, where f < 1, the thin paint lies on the old instead of
    replacing it, so a stroke never digs a groove into the paint beneath, and
    it lies there as thick as it is (a h, not o h = a f h): two strokes
    whose edges meet at half contact leave about as much paint as one
    stroke's body, so crowded small strokes leave no groove between them.
    Opacity A = o + (1 - o) A.
    """
    colour = colour * transmittance[..., None] + paint
    alpha = np.float32(1.0) - transmittance
    coverage = coverage + (np.float32(1.0) - coverage) * alpha
    fullness = np.minimum(deposit * inverse, np.float32(1.0))
    o = alpha * fullness
    loss = np.float32(1.0 if height_mode != "accumulate" else 1.0 - build)
    height = np.maximum(height + alpha * (stroke_height - fullness * loss * height), np.float32(0.0))
    opacity = opacity + (np.float32(1.0) - opacity) * o
    return colour, coverage, height, opacity
