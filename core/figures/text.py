"""Text drawn from a bitmap font shipped with the painter: labels without FreeType.

The font is ``font.npz`` beside this file: printable ASCII (32-126) of Droid
Sans (Apache License 2.0) rendered once at 32 px per em as 8-bit coverage,
one cell per glyph as wide as its advance (``tools/render_font.py`` makes
it). Text is laid out at 32 px, then box-filtered to the size asked for, so
every size is anti-aliased and the same text, size and position always give
the same pixels. Characters outside printable ASCII are drawn as their
nearest ASCII spelling ("×" as "x", "°" as " deg", others as "?").
"""

from __future__ import annotations

import functools
import os
from typing import Dict, Sequence, Tuple

import numpy as np

FONT_FILE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "font.npz")
# Spellings of the non-ASCII characters the painter's own labels use.
_ASCII = {"×": "x", "°": " deg", "−": "-", "–": "-", "—": "-", "≈": "~", "·": ".", "θ": "theta", "π": "pi"}


@functools.lru_cache(maxsize=1)
def _font() -> Dict[str, np.ndarray]:
    """The font's arrays: coverage uint8 (cell height, atlas width), offsets and widths (int32, one per glyph)."""
    with np.load(FONT_FILE, allow_pickle=False) as data:
        return {name: data[name] for name in data.files}


def _ascii(text: str) -> str:
    return "".join(ch if 32 <= ord(ch) <= 126 else _ASCII.get(ch, "?") for ch in text)


def _glyph_indices(text: str) -> np.ndarray:
    font = _font()
    return np.asarray([ord(ch) - int(font["first"]) for ch in _ascii(text)], dtype=np.int64)


def text_width(text: str, size: float) -> float:
    """Width in pixels of ``text`` drawn ``size`` px per em (the sum of its glyphs' advances)."""
    font = _font()
    glyphs = _glyph_indices(text)
    return float(font["widths"][glyphs].sum()) * size / float(font["em"])


def _coverage_at_em(text: str) -> np.ndarray:
    """float32 (cell height, width) coverage in [0, 1] of ``text`` laid out at the font's own size."""
    font = _font()
    glyphs = _glyph_indices(text)
    if glyphs.size == 0:
        return np.zeros((font["coverage"].shape[0], 0), np.float32)
    columns = np.concatenate([np.arange(font["offsets"][g], font["offsets"][g] + font["widths"][g]) for g in glyphs])
    return font["coverage"][:, columns].astype(np.float32) / np.float32(255)


def _box_resample(a: np.ndarray, rows: int, cols: int) -> np.ndarray:
    """Area-average (h, w) ``a`` onto (rows, cols): each output pixel is the mean of the input area it covers."""
    def weights(n_in: int, n_out: int) -> np.ndarray:
        # w[i, j] = length of input pixel j inside output pixel i, in input units, rows summing to n_in / n_out.
        edges = np.linspace(0.0, n_in, n_out + 1)
        lo = np.maximum(edges[:-1, None], np.arange(n_in)[None, :])
        hi = np.minimum(edges[1:, None], np.arange(1, n_in + 1)[None, :])
        w = np.clip(hi - lo, 0.0, None)
        return w / w.sum(axis=1, keepdims=True)

    return (weights(a.shape[0], rows) @ a.astype(np.float64) @ weights(a.shape[1], cols).T).astype(np.float32)


def text_coverage(text: str, size: float) -> Tuple[np.ndarray, int]:
    """Coverage of ``text`` at ``size`` px per em: (float32 (h, w) in [0, 1], baseline row within it)."""
    font = _font()
    scale = float(size) / float(font["em"])
    at_em = _coverage_at_em(text)
    rows = max(1, int(round(at_em.shape[0] * scale)))
    cols = int(round(at_em.shape[1] * scale))
    baseline = int(round(int(font["ascent"]) * scale))
    if cols == 0:
        return np.zeros((rows, 0), np.float32), baseline
    return np.clip(_box_resample(at_em, rows, cols), 0.0, 1.0), baseline


def draw_text(image: np.ndarray, x: float, y: float, text: str, size: float,
              colour: Sequence[float] = (0.0, 0.0, 0.0)) -> np.ndarray:
    """Blend ``text`` into float (H, W, C) ``image`` in place, its baseline's left end at (x, y) px; return image.

    ``size`` is pixels per em (a capital letter is about 0.7 of it tall);
    ``colour`` has C values in the image's own encoding. Parts outside the
    image are clipped.
    """
    coverage, baseline = text_coverage(text, size)
    top, left = int(round(y)) - baseline, int(round(x))
    h, w = image.shape[:2]
    y0, x0 = max(top, 0), max(left, 0)
    y1, x1 = min(top + coverage.shape[0], h), min(left + coverage.shape[1], w)
    if y0 >= y1 or x0 >= x1:
        return image
    alpha = coverage[y0 - top:y1 - top, x0 - left:x1 - left, None]
    paint = np.asarray(colour, dtype=image.dtype).reshape(1, 1, -1)
    image[y0:y1, x0:x1] = image[y0:y1, x0:x1] * (1 - alpha) + paint * alpha
    return image
