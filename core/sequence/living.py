"""The strokes alive on a frame of a sequence and what each one's life has kept (ALGORITHM §9).

A ``LivingStrokes`` is a frame's ``StrokeList`` in laying order (by layer,
within a layer by size, largest first, within a size by birth, older
first) with, for every stroke, its identity, its birth frame, its fade level
and whether it is dying, its bristle offsets (each bristle's colour as laid
minus the anchor colour at birth: Eq. 5's mixing and the stroke's
perturbation, which it keeps for life) and the length of its control
polygon at birth (what stretching is measured against).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import List, Tuple

import numpy as np

from ..strokes.path import polygon_lengths
from ..strokes.stroke_list import StrokeList, bristle_entries


@dataclass(frozen=True)
class LivingStrokes:
    """N strokes of one frame.

    strokes: the frame's ``StrokeList`` in laying order; its contact is level / fade_frames.
    ident: int64 (N,) the stroke's identity, unique in the sequence, growing with birth.
    birth: int64 (N,) the 0-based index of the frame it was born on.
    level: int32 (N,) 1 .. fade_frames: its contact in steps of 1 / fade_frames.
    dying: bool (N,) it is fading out (it died, not occluded).
    offsets: float32 (M, 3) each bristle's colour minus the anchor colour, row for row with strokes.bristles.
    birth_length: float64 (N,) px, the length of its control polygon at birth.
    fade_frames: K >= 1, frames to fade in and out.
    """

    strokes: StrokeList
    ident: np.ndarray
    birth: np.ndarray
    level: np.ndarray
    dying: np.ndarray
    offsets: np.ndarray
    birth_length: np.ndarray
    fade_frames: int

    def __len__(self) -> int:
        """The number of strokes N."""
        return len(self.ident)

    @classmethod
    def born(cls, strokes: StrokeList, first_ident: int, frame: int, level: int, fade_frames: int) -> "LivingStrokes":
        """Strokes just laid on ``frame`` by the still painter's rules, identities from ``first_ident`` on, at
        fade ``level`` (fade_frames for a sequence's first frame, painted as a still; 1 for a later birth)."""
        n = len(strokes)
        offsets = strokes.bristles - np.repeat(strokes.anchor_colour, np.diff(strokes.bristle_starts), axis=0)
        living = cls(strokes, first_ident + np.arange(n, dtype=np.int64), np.full(n, frame, np.int64),
                     np.full(n, level, np.int32), np.zeros(n, bool), offsets.astype(np.float32),
                     polygon_lengths(strokes.control, strokes.control_count), int(fade_frames))
        return living.with_contact()

    def subset(self, index) -> "LivingStrokes":
        """Some of the strokes: ``index`` a (K,) int array (in its order) or an (N,) bool mask (in order)."""
        picked = np.arange(len(self))[index]
        entries, _ = bristle_entries(self.strokes.bristle_starts, picked)
        return LivingStrokes(self.strokes.subset(picked), self.ident[picked], self.birth[picked],
                             self.level[picked], self.dying[picked], self.offsets[entries],
                             self.birth_length[picked], self.fade_frames)

    @staticmethod
    def joined(parts: List["LivingStrokes"]) -> "LivingStrokes":
        """The strokes of several, put in laying order (``in_order``)."""
        join = lambda name: np.concatenate([getattr(part, name) for part in parts])  # noqa: E731
        together = LivingStrokes(StrokeList.joined([part.strokes for part in parts]), join("ident"), join("birth"),
                                 join("level"), join("dying"), join("offsets"), join("birth_length"),
                                 parts[0].fade_frames)
        return together.in_order()

    def in_order(self) -> "LivingStrokes":
        """The strokes in laying order: by layer, then size (largest first), then identity (older first)."""
        order = np.lexsort((self.ident, -self.strokes.size.astype(np.int64), self.strokes.layer))
        if np.array_equal(order, np.arange(len(self))):
            return self
        return self.subset(order)

    def fading_out(self, stale: np.ndarray) -> Tuple["LivingStrokes", int]:
        """The strokes with those ``stale`` (N,) bool and not dying yet starting to fade out (one level down, as on
        their first frame of dying), and how many of them were gone at once (a newborn at its first level)."""
        starting = stale & ~self.dying
        level = np.where(starting, self.level - 1, self.level).astype(np.int32)
        stepped = replace(self, level=level, dying=self.dying | starting)
        return stepped.subset(level > 0).with_contact(), int(np.count_nonzero(level == 0))

    def with_contact(self) -> "LivingStrokes":
        """The same strokes with the list's contact set from their fade level: level / fade_frames."""
        contact = (self.level / np.float32(self.fade_frames)).astype(np.float32)
        return replace(self, strokes=replace(self.strokes, contact=contact))

    def settled(self) -> "LivingStrokes":
        """The strokes that are not dying, at full contact: what the canvas that births are judged on holds."""
        kept = self.subset(~self.dying)
        return replace(kept, strokes=replace(kept.strokes, contact=np.ones(len(kept), np.float32)))

    def at_full_contact(self) -> bool:
        """Whether every stroke is settled: none fading in or out, so the frame is laid as its judging canvas."""
        return bool(np.all(self.level == self.fade_frames) and not np.any(self.dying))
