"""Eq. 4 folded over the rows of a brush: what one column of bristles lays where it passes (ALGORITHM §5).

A brush turned along a straight path stamps its row r at sample s where it
stamps row r + 1 at sample s + 1, so every point of a column's track is
passed over by the column's rows in order, front row first. Folding Eq. 4,
C <- a C_b + (1 - a) C, over those rows gives one contribution: the paint
laid, the log transmittance (the share of the old colour that shows
through) and the contact laid. Inside a stroke every row passes at full
contact; near its ends only a run of rows passes (the rows behind the front
at the start, the rows ahead of the back at the end) and the brush touches
down and lifts off (a contact below 1).

The paint's colour is the fold of the rows that pass at full contact (a
bristle keeps its colour along the whole path). How much of it a track sample lays (its transmittance and contact) depends only on the brush
and on the run of rows and the contact there, not on the colours, so it
comes from tables of row sums at LEVELS_PER_CONTACT + 1 contact levels that
every stroke of a brush width shares: any run of rows is a difference of
two prefix sums, and a contact between two levels is interpolated linearly.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

MAX_INTENSITY = 1.0 - 1e-6  # keeps log(1 - I) finite for full-contact bristles

# Contact levels per unit of contact in the row tables: the fold at a contact between two
# levels is interpolated linearly (an error well below 1/255, see the tests).
LEVELS_PER_CONTACT = 24


class TipGrid(NamedTuple):
    """Where B bristles sit on their tip's lattice of R rows and W columns."""

    rows: np.ndarray            # int64 (B,) in [0, R)
    columns: np.ndarray         # int64 (B,) in [0, W)
    n_rows: int                 # R
    n_columns: int              # W


def tip_grid(along: np.ndarray, across: np.ndarray) -> TipGrid:
    """Row and column of each of B bristles in their tip's grid, and the grid's rows R and columns W.

    Bristles sit on a whole-pixel lattice (see core.brush): row r lies r px
    behind the front (largest ``along``), column c is c px right of the
    smallest ``across``. Lattice cells without a bristle are empty rows or columns.
    """
    along = np.asarray(along, np.float64)
    across = np.asarray(across, np.float64)
    rows = np.rint(along.max() - along).astype(np.int64)
    columns = np.rint(across - across.min()).astype(np.int64)
    return TipGrid(rows, columns, int(rows.max()) + 1, int(columns.max()) + 1)


def run_colours(grid: np.ndarray, grid_colours: np.ndarray, passes: float, stroke: np.ndarray,
                first_row: np.ndarray, last_row: np.ndarray) -> np.ndarray:
    """(K, W, 3) float32: the colour K track samples lay, each folding rows first_row .. last_row of its stroke.

    grid: (R, W) bristle contact; grid_colours: (N, R, W, 3) each stroke's
    bristle colours on the tip's lattice; stroke, first_row, last_row: (K,)
    int. The colour is the run's fold at full contact per unit of its alpha
    (0 in a column without bristles):
    sum_r a_r C_r prod_{r<t<=last} (1 - a_t) = e^{L(last+1)} (Q(last+1) - Q(first)),
    with L the prefix sums of log(1 - a_r) and Q those of a_r C_r e^{-L(r+1)}
    (float64; each row's log(1 - a) is kept above -600 / R, so the
    exponentials stay finite; a row that lets less than that through hides
    everything before it anyway).
    """
    n_rows = grid.shape[0]
    strength = np.minimum(np.asarray(grid, np.float64), MAX_INTENSITY)
    log_keep = np.maximum(np.log1p(-strength) * passes, -600.0 / n_rows)
    prefix = np.zeros((n_rows + 1, grid.shape[1]))
    np.cumsum(log_keep, axis=0, out=prefix[1:])
    term = -np.expm1(log_keep) * np.exp(-prefix[1:])                                   # (R, W)
    sums = np.zeros((grid_colours.shape[0], n_rows + 1) + grid_colours.shape[2:])
    np.cumsum(term[None, :, :, None] * grid_colours, axis=1, out=sums[:, 1:])
    top = prefix[last_row + 1]
    alpha = -np.expm1(top - prefix[first_row])
    scale = np.divide(np.exp(top), alpha, out=np.zeros_like(alpha), where=alpha > 0)
    return ((sums[stroke, last_row + 1] - sums[stroke, first_row]) * scale[..., None]).astype(np.float32)


class RowRuns(NamedTuple):
    """What K track samples of a brush W columns wide lay, each folding a run of the brush's rows."""

    log_keep: np.ndarray        # float32 (K, W) <= 0, log transmittance
    laid: np.ndarray            # float32 (K, W) >= 0, the contact laid


@dataclass(frozen=True)
class RowTables:
    """Prefix sums over a brush's rows at contact levels l / LEVELS_PER_CONTACT, l = 0 .. LEVELS_PER_CONTACT.

    log_keep: float64 (L, R + 1, W), sum over rows < r of passes log(1 - min(level grid, MAX_INTENSITY)).
    laid: float64 (L, R + 1, W), sum over rows < r of min(level grid, MAX_INTENSITY).
    """

    log_keep: np.ndarray
    laid: np.ndarray

    @classmethod
    def of(cls, grid: np.ndarray, passes: float) -> "RowTables":
        """The tables of an (R, W) brush grid, each row passing ``passes`` times."""
        levels = np.arange(LEVELS_PER_CONTACT + 1, dtype=np.float64) / LEVELS_PER_CONTACT
        strength = np.minimum(levels[:, None, None] * np.asarray(grid, np.float64)[None], MAX_INTENSITY)
        shape = (len(levels), grid.shape[0] + 1, grid.shape[1])
        log_keep, laid = np.zeros(shape), np.zeros(shape)
        np.cumsum(np.log1p(-strength) * passes, axis=1, out=log_keep[:, 1:])
        np.cumsum(strength, axis=1, out=laid[:, 1:])
        return cls(log_keep, laid)

    def runs(self, first_row: np.ndarray, last_row: np.ndarray, touch: np.ndarray) -> RowRuns:
        """What K track samples lay, each passed by rows first_row .. last_row at contact ``touch``.

        first_row, last_row: (K,) int in [0, R - 1]; touch: (K,) in [0, 1].
        """
        position = np.clip(np.asarray(touch, np.float64), 0.0, 1.0) * LEVELS_PER_CONTACT
        below = np.minimum(np.floor(position).astype(np.int64), LEVELS_PER_CONTACT - 1)
        frac = (position - below)[:, None]
        out = []
        for table in (self.log_keep, self.laid):
            low = table[below, last_row + 1] - table[below, first_row]
            high = table[below + 1, last_row + 1] - table[below + 1, first_row]
            out.append((low * (1.0 - frac) + high * frac).astype(np.float32))
        return RowRuns(*out)

