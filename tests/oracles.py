"""Reference implementations and checks that only the tests use, to hold the production code to.

folder_bytes and same_bytes: "every output file the same bytes", the one
check behind every determinism, resume and farm test. one_sentence and
one_sentence_run: "bad input is one sentence", for a message and for a
command that ran. map_bytes, same_maps and same_painting: the same
check for paintings and canvases held in memory, map by map (and stroke by
stroke).

cut_costs and best_cut: Eq. 2 for one grid at a time (ALGORITHM §2), the
simple reference that core.analysis.partition.partition, which cuts a whole
generation of grids at once, must agree with bit for bit. Rectangles,
summed-area tables and cut geometry follow the conventions of
core/analysis/partition.py.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Dict, Iterable, Optional, Tuple

import numpy as np

from core.analysis.partition import DEFAULT_DELTA, _check_eq2_params, _eq2, rect_sums
from core.errors import ParameterError


def folder_bytes(folder: Path, leave_out: Iterable[str] = ("report.json",)) -> Dict[str, bytes]:
    """{file name: bytes} of every file in ``folder`` (not its subfolders) but those named in ``leave_out`` (by
    default report.json, which holds seconds and the output folder's path)."""
    skipped = set(leave_out)
    return {p.name: p.read_bytes() for p in sorted(Path(folder).iterdir()) if p.is_file() and p.name not in skipped}


def same_bytes(folder: Path, other: Path, leave_out: Iterable[str] = ("report.json",)) -> Dict[str, bytes]:
    """Assert that ``folder`` and ``other`` hold the same files with the same bytes (``folder_bytes``); return the
    first's. The message names the files that differ or that only one holds."""
    mine, theirs = folder_bytes(folder, leave_out), folder_bytes(other, leave_out)
    differ = sorted(name for name in set(mine) | set(theirs) if mine.get(name) != theirs.get(name))
    assert not differ, f"{folder} and {other} differ in {differ}"
    return mine


def one_sentence(message: str, naming=None) -> str:
    """Assert that ``message`` (an error's text; an operator's report, which Blender prefixes "Error: " headless)
    is one sentence: one line ending in a full stop, no second sentence, no traceback, naming ``naming`` (a path)
    when given. Return the sentence."""
    text = message.strip()
    text = text[len("Error: "):] if text.startswith("Error: ") else text
    assert text.endswith(".") and "\n" not in text and "Traceback" not in text, message
    assert naming is None or str(naming) in text, message
    assert not re.search(r"[.!?]\s+[A-Z]", text), message
    return text


def one_sentence_run(run) -> str:
    """Assert that the finished command ``run`` (a subprocess.CompletedProcess with text stderr) failed with one
    sentence on stderr and nothing else there; return the sentence."""
    lines = [line for line in run.stderr.splitlines() if line.strip()]
    assert run.returncode != 0, run.stderr
    assert len(lines) == 1, run.stderr
    return one_sentence(lines[0])


MAPS = ("colour", "height", "opacity", "coverage")
"""The maps of a Painting or a Canvas that its strokes make."""


def map_bytes(painting, names: Iterable[str] = MAPS) -> Dict[str, bytes]:
    """{map name: bytes} of the maps ``names`` of ``painting`` (a Painting, a Canvas or anything with those
    arrays as attributes)."""
    return {name: np.ascontiguousarray(getattr(painting, name)).tobytes() for name in names}


def same_maps(painting, other, names: Iterable[str] = MAPS) -> None:
    """Assert that ``painting`` and ``other`` hold the maps ``names`` with the same shapes, types and bytes; the
    message names the maps that differ."""
    names = tuple(names)
    differ = [name for name in names
              if (getattr(painting, name).shape, getattr(painting, name).dtype) != (getattr(other, name).shape,
                                                                                     getattr(other, name).dtype)]
    mine, theirs = map_bytes(painting, names), map_bytes(other, names)
    differ += [name for name in names if name not in differ and mine[name] != theirs[name]]
    assert not differ, f"the maps {differ} differ"


def same_painting(painting, other) -> None:
    """Assert that two Paintings are the same to the byte: every map (``same_maps``), every stroke's record in
    order and the strokes per layer."""
    same_maps(painting, other)
    assert [s.to_dict() for s in painting.strokes] == [s.to_dict() for s in other.strokes], "the strokes differ"
    assert painting.statistics["strokes_per_layer"] == other.statistics["strokes_per_layer"], "strokes per layer"


def _check_rect(sat: np.ndarray, rect) -> Tuple[int, int, int, int]:
    """(x0, y0, x1, y1) as ints when the half-open rectangle lies inside the SAT's (H, W) canvas; else ParameterError."""
    x0, y0, x1, y1 = (int(v) for v in rect)
    h, w = sat.shape[0] - 1, sat.shape[1] - 1
    if not (0 <= x0 <= x1 <= w and 0 <= y0 <= y1 <= h):
        raise ParameterError(f"The rectangle {(x0, y0, x1, y1)} does not lie inside the {w}x{h} canvas.")
    return x0, y0, x1, y1


def cut_costs(sat: np.ndarray, rect, min_side: int, delta: float = DEFAULT_DELTA,
              gamma: float = 1.0) -> Tuple[int, np.ndarray, np.ndarray]:
    """Eq. 2 for every admissible cut of one grid, in one vectorised expression.

    sat: float64 (H + 1, W + 1) summed-area table of the [0, 1] energy.
    rect: (x0, y0, x1, y1) ints, half-open, inside the canvas.
    min_side: smallest stroke size in px (>= 1); both halves keep at least
        this many pixels along the cut axis.
    delta: δ of Eq. 2 on the energy's scale (> 0); gamma: γ (>= 0).

    Returns ``(axis, positions, costs)``:
      * axis: 1 when the cut is a vertical line at a column (width >= height;
        positions are x coordinates, numpy axis 1 of the image), 0 when it is
        a horizontal line at a row (positions are y coordinates);
      * positions: int64 (K,) ABSOLUTE cut coordinates ``x0 + i`` (or
        ``y0 + i``), increasing, for ``i = min_side .. length - min_side``;
      * costs: float64 (K,) Eq. 2 cost of each position (dimensionless, > 0).
    K = 0 (empty arrays) when the longer side is shorter than ``2 * min_side``.
    """
    sat = np.asarray(sat, dtype=np.float64)
    _check_eq2_params(min_side, delta, gamma)
    min_side = int(min_side)
    x0, y0, x1, y1 = _check_rect(sat, rect)
    w, h = x1 - x0, y1 - y0
    if w >= h:
        axis, start, length = 1, x0, w
    else:
        axis, start, length = 0, y0, h
    if length < 2 * min_side:
        return axis, np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.float64)
    pos = np.arange(start + min_side, start + length - min_side + 1, dtype=np.int64)
    if axis == 1:
        s1 = rect_sums(sat, x0, y0, pos, y1)
        s2 = rect_sums(sat, pos, y0, x1, y1)
        a1 = (pos - x0) * h
        a2 = (x1 - pos) * h
    else:
        s1 = rect_sums(sat, x0, y0, x1, pos)
        s2 = rect_sums(sat, x0, pos, x1, y1)
        a1 = (pos - y0) * w
        a2 = (y1 - pos) * w
    return axis, pos, _eq2(s1, a1, s2, a2, float(delta), float(gamma))


def best_cut(sat: np.ndarray, rect, min_side: int, delta: float = DEFAULT_DELTA,
             gamma: float = 1.0) -> Optional[int]:
    """Absolute coordinate of the cheapest admissible cut of one grid, or None.

    Same arguments as :func:`cut_costs`. The result is a column (x) when the
    grid's width >= its height, else a row (y). Ties go to the smallest
    position. None when no admissible cut exists (longer side < 2·min_side).
    """
    _, pos, costs = cut_costs(sat, rect, min_side, delta, gamma)
    if pos.size == 0:
        return None
    return int(pos[int(np.argmin(costs))])
