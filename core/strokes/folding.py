"""Eq. 4 folded over the rows of a brush: what one column of bristles lays where it passes (ALGORITHM §5).

A brush turned along a straight path stamps its row r at sample s where it
stamps row r + 1 at sample s + 1, so every point of a column's track is
passed over by the column's rows in order, front row first. Folding Eq. 4,
C <- a C_b + (1 - a) C, over those rows gives one contribution: the paint
laid, the log transmittance (the share of the old colour that shows
through) and the contact laid. Inside a stroke every row passes at full
contact; near its ends only some rows pass (the rows behind the front at
the start, the rows ahead of the back at the end) and the brush touches
down and lifts off (a contact below 1). ``track_folds`` serves all these
cases from tables of every run of rows at a few contact levels, so a
stroke's cost grows with its track, not with its track times its rows.
"""

from __future__ import annotations

import math

import numpy as np

MAX_INTENSITY = 1.0 - 1e-6  # keeps log(1 - I) finite for full-contact bristles

# Contact levels per unit of contact in the fold tables: the fold at a contact between two
# levels is interpolated linearly (an error well below 1/255, see the tests).
LEVELS_PER_CONTACT = 24


def tip_grid(along: np.ndarray, across: np.ndarray) -> tuple:
    """Row and column of each of B bristles in their tip's grid: (rows (B,) int, columns (B,) int, R, W).

    Bristles sit on a whole-pixel lattice (see core.brush): row r lies r px
    behind the front (largest ``along``), column c is c px right of the
    smallest ``across``. Lattice cells without a bristle are empty rows or columns.
    """
    along = np.asarray(along, np.float64)
    across = np.asarray(across, np.float64)
    rows = np.rint(along.max() - along).astype(np.int64)
    columns = np.rint(across - across.min()).astype(np.int64)
    return rows, columns, int(rows.max()) + 1, int(columns.max()) + 1


def fold_rows(scale: np.ndarray, grid: np.ndarray, grid_colour: np.ndarray, passes: float) -> tuple:
    """Eq. 4 folded over a brush's rows, front row first, for each of K contact patterns: the exact fold.

    scale: (K, R) contact multiplier of each row (0 = the row is absent);
    grid: (R, W) bristle contact; grid_colour: (R, W, 3). Returns
    (paint (3, K, W) one plane per channel, log transmittance (K, W), contact laid (K, W)), all float32.
    """
    strength = scale[:, :, None] * grid[None, :, :]                                    # (K, R, W)
    np.minimum(strength, np.float32(MAX_INTENSITY), out=strength)
    log_keep = np.log1p(-strength) * np.float32(passes)
    later = running_sum(log_keep, reverse=True) - log_keep                             # log prod over later rows
    weight = -np.expm1(log_keep) * np.exp(later)
    paint = np.stack([np.einsum("krw,rw->kw", weight, grid_colour[..., ch]) for ch in range(3)])
    return paint, log_keep.sum(axis=1), strength.sum(axis=1)


def running_sum(values: np.ndarray, reverse: bool = False) -> np.ndarray:
    """Cumulative sum of (L, R, ...) ``values`` along axis 1 (from the back when ``reverse``), as a new array.

    A loop over the R rows: for short axes it is several times faster than np.cumsum along axis 1.
    """
    total = values.copy()
    rows = range(total.shape[1] - 2, -1, -1) if reverse else range(1, total.shape[1])
    step = 1 if reverse else -1
    for r in rows:
        total[:, r] += total[:, r + step]
    return total


def fold_tables(levels: np.ndarray, grid: np.ndarray, grid_colour: np.ndarray, passes: float) -> tuple:
    """Eq. 4 folded over every run of rows that reaches the brush's back or starts at its front, at L contact levels.

    levels: (L,) contact multipliers; grid: (R, W) bristle contact;
    grid_colour: (R, W, 3). Entry j < R folds rows j .. R - 1 (the brush
    setting down: its back rows have reached the point, its front rows not
    yet), entry R + j folds rows 0 .. j (the brush lifting off past the
    point); entry 0 is the whole brush. Returns (paint (3, L, 2R, W) one
    plane per channel, log transmittance (L, 2R, W), contact laid (L, 2R, W)),
    float32, equal to ``fold_rows`` of those patterns up to rounding.
    """
    n_rows = grid.shape[0]
    strength = np.asarray(levels, np.float32)[:, None, None] * grid[None, :, :]       # (L, R, W)
    np.minimum(strength, np.float32(MAX_INTENSITY), out=strength)
    log_keep = np.log1p(-strength) * np.float32(passes)
    alpha = -np.expm1(log_keep)
    from_back = running_sum(log_keep, reverse=True)
    weight = alpha * np.exp(from_back - log_keep)                                     # a_r prod_{t>r} (1 - a_t)
    planes = np.ascontiguousarray(np.moveaxis(grid_colour, -1, 0))                     # (3, R, W)
    paint = np.empty((3, len(strength), 2 * n_rows, grid.shape[1]), np.float32)
    for ch in range(3):
        paint[ch, :, :n_rows] = running_sum(weight * planes[ch], reverse=True)
    folded = np.zeros((3, len(strength), grid.shape[1]), np.float32)
    for r in range(n_rows):                                                           # rows 0 .. r, front first
        folded *= 1.0 - alpha[None, :, r]
        folded += alpha[None, :, r] * planes[:, None, r]
        paint[:, :, n_rows + r] = folded
    log_total = np.concatenate([from_back, running_sum(log_keep)], axis=1)
    laid = np.concatenate([running_sum(strength, reverse=True), running_sum(strength)], axis=1)
    return paint, log_total, laid


def track_folds(first_row: np.ndarray, last_row: np.ndarray, touch: np.ndarray, grid: np.ndarray,
                grid_colour: np.ndarray, passes: float) -> tuple:
    """Eq. 4 folded at K track samples, each passed over by rows first_row .. last_row at contact ``touch``.

    first_row, last_row: (K,) int in [0, R - 1]; touch: (K,) in (0, 1];
    grid (R, W), grid_colour (R, W, 3). Returns (colour (3, K, W) one plane
    per channel, log transmittance (K, W), contact laid (K, W)) float32, where colour is the
    mean colour of the paint laid (the folded paint over its alpha; 0 where
    nothing is laid). The samples inside the stroke (every row at full
    contact) share one exact fold. The others are folded exactly while they
    are few; else (long brushes, whose ends span many samples) they come
    from ``fold_tables`` at contact levels LEVELS_PER_CONTACT per unit apart
    between min(touch) and 1, interpolated linearly (colour and
    transmittance apart, so a colour between two levels is a mix of theirs
    and never brighter or more saturated), and the rare runs that neither
    reach the brush's back nor start at its front (a stroke shorter than its
    brush) are folded exactly.
    """
    n_rows = grid.shape[0]
    touch = np.asarray(touch, np.float64)
    rows = np.arange(n_rows)
    paint, log_whole, laid_whole = fold_rows(np.ones((1, n_rows), np.float32), grid, grid_colour, passes)
    colour = np.repeat(mean_colour(paint, log_whole), len(touch), axis=1)       # every row at full contact
    log_total, laid = np.repeat(log_whole, len(touch), axis=0), np.repeat(laid_whole, len(touch), axis=0)
    whole = (first_row == 0) & (last_row == n_rows - 1)
    ends = np.flatnonzero(~whole | (touch < 1.0))
    lowest = float(touch[ends].min()) if ends.size else 1.0
    n_levels = 1 + math.ceil((1.0 - lowest) * LEVELS_PER_CONTACT)
    inner = (first_row > 0) & (last_row < n_rows - 1)
    if ends.size <= 2 * n_levels:                                                 # few: fold each exactly
        exact, tabled = ends, ends[:0]
    else:                                                                         # (inner runs are ends too)
        exact, tabled = ends[inner[ends]], ends[~inner[ends]]
    if tabled.size:
        first, last, contact = first_row[tabled], last_row[tabled], touch[tabled]
        entry = np.where(first > 0, first, np.where(last < n_rows - 1, n_rows + last, 0))
        lowest = float(contact.min())
        n_levels = 1 + math.ceil((1.0 - lowest) * LEVELS_PER_CONTACT)
        levels = np.linspace(lowest, 1.0, n_levels) if n_levels > 1 else np.ones(1)
        paint_t, log_t, laid_t = fold_tables(levels, grid, grid_colour, passes)
        position = (contact - lowest) / max(1.0 - lowest, 1e-12) * (n_levels - 1)
        below = np.clip(np.floor(position).astype(np.int64), 0, max(n_levels - 2, 0))
        above = np.minimum(below + 1, n_levels - 1)
        frac = np.clip(position - below, 0.0, 1.0).astype(np.float32)[:, None]
        log_below, log_above = log_t[below, entry], log_t[above, entry]
        colour[:, tabled] = lerp(mean_colour(paint_t[:, below, entry], log_below),
                                 mean_colour(paint_t[:, above, entry], log_above), frac)
        log_total[tabled] = lerp(log_below, log_above, frac)
        laid[tabled] = lerp(laid_t[below, entry], laid_t[above, entry], frac)
    if exact.size:
        present = (rows[None, :] >= first_row[exact, None]) & (rows[None, :] <= last_row[exact, None])
        paint, log_total[exact], laid[exact] = fold_rows((touch[exact, None] * present).astype(np.float32),
                                                         grid, grid_colour, passes)
        colour[:, exact] = mean_colour(paint, log_total[exact])
    return colour, log_total, laid


def mean_colour(paint: np.ndarray, log_total: np.ndarray) -> np.ndarray:
    """(3, ...) float32 colour planes of folded ``paint`` (3, ...) per unit of its alpha 1 - exp(``log_total``) (...);
    0 where the alpha is 0."""
    alpha = -np.expm1(log_total)
    scale = np.divide(1.0, alpha, out=np.zeros_like(alpha), where=alpha > 0)
    return paint * scale[None]


def lerp(low: np.ndarray, high: np.ndarray, frac: np.ndarray) -> np.ndarray:
    """low + (high - low) frac, written as low (1 - frac) + high frac so that frac = 1 gives ``high`` exactly."""
    return low * (1.0 - frac) + high * frac
