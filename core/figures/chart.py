"""Small line charts drawn with NumPy (anti-aliased lines, text from the painter's bitmap font)."""

from __future__ import annotations

from typing import Sequence, Tuple

import numpy as np

from . import text as _text

Colour = Tuple[float, float, float]
SERIES_COLOURS: Tuple[Colour, ...] = ((0.84, 0.15, 0.16), (0.12, 0.47, 0.71), (0.17, 0.63, 0.17), (0.58, 0.40, 0.74))


def draw_segment(image: np.ndarray, p0, p1, width: float, colour: Colour) -> None:
    """Blend an anti-aliased, round-capped segment from p0 to p1 ((x, y) px) into (H, W, 3) ``image``."""
    h, w = image.shape[:2]
    r = width / 2.0 + 1.0
    x0, x1 = int(max(0, np.floor(min(p0[0], p1[0]) - r))), int(min(w, np.ceil(max(p0[0], p1[0]) + r) + 1))
    y0, y1 = int(max(0, np.floor(min(p0[1], p1[1]) - r))), int(min(h, np.ceil(max(p0[1], p1[1]) + r) + 1))
    if x0 >= x1 or y0 >= y1:
        return
    yy, xx = np.mgrid[y0:y1, x0:x1].astype(np.float64)
    d = np.subtract(p1, p0, dtype=np.float64)
    length2 = float(d @ d)
    t = np.zeros_like(xx) if length2 == 0 else np.clip(((xx - p0[0]) * d[0] + (yy - p0[1]) * d[1]) / length2, 0, 1)
    dist = np.hypot(xx - (p0[0] + t * d[0]), yy - (p0[1] + t * d[1]))
    a = np.clip(width / 2.0 - dist + 0.5, 0.0, 1.0)[..., None]
    image[y0:y1, x0:x1] = image[y0:y1, x0:x1] * (1 - a) + np.asarray(colour) * a


def draw_text(image: np.ndarray, x: int, y: int, text: str, size: int, colour: Colour = (0, 0, 0)) -> None:
    """Write ``text`` ``size`` px per em with its baseline at (x, y) px into (H, W, 3) float ``image``."""
    _text.draw_text(image, int(x), int(y), text, int(size), tuple(colour))


def line_chart(series: Sequence[Tuple[str, Sequence[float], Sequence[float]]], x_range, y_range, x_ticks,
               y_ticks, title: str = "", x_label: str = "", y_label: str = "", size=(720, 420)) -> np.ndarray:
    """(H, W, 3) sRGB picture of (label, xs, ys) series as lines with point markers and a legend."""
    width, height = size
    image = np.ones((height, width, 3), dtype=np.float64)
    left, right, top, bottom = 70, 20, 40, 60
    pw, ph = width - left - right, height - top - bottom

    def to_px(x, y):
        return (left + (x - x_range[0]) / (x_range[1] - x_range[0]) * pw,
                top + (y_range[1] - y) / (y_range[1] - y_range[0]) * ph)

    for x in x_ticks:
        draw_segment(image, to_px(x, y_range[0]), to_px(x, y_range[1]), 1.0, (0.88, 0.88, 0.88))
        px, py = to_px(x, y_range[0])
        draw_text(image, px - 10, py + 18, f"{x:g}", 13)
    for y in y_ticks:
        draw_segment(image, to_px(x_range[0], y), to_px(x_range[1], y), 1.0, (0.88, 0.88, 0.88))
        px, py = to_px(x_range[0], y)
        draw_text(image, px - 40, py + 5, f"{y:g}", 13)
    if y_range[0] < 0 < y_range[1]:
        draw_segment(image, to_px(x_range[0], 0), to_px(x_range[1], 0), 1.2, (0.5, 0.5, 0.5))
    draw_segment(image, (left, top), (left, top + ph), 1.2, (0, 0, 0))
    draw_segment(image, (left, top + ph), (left + pw, top + ph), 1.2, (0, 0, 0))
    for i, (label, xs, ys) in enumerate(series):
        colour = SERIES_COLOURS[i % len(SERIES_COLOURS)]
        points = [to_px(x, y) for x, y in zip(xs, ys, strict=True)]
        for p0, p1 in zip(points, points[1:], strict=False):
            draw_segment(image, p0, p1, 2.5, colour)
        for p in points:
            draw_segment(image, p, p, 7.0, colour)
        lx, ly = left + pw - 210, top + 18 + 20 * i
        draw_segment(image, (lx, ly - 5), (lx + 24, ly - 5), 3.0, colour)
        draw_text(image, lx + 32, ly, label, 14)
    draw_text(image, left + 12, 24, title, 17)
    draw_text(image, left + pw // 2 - 4 * len(x_label), height - 16, x_label, 14)
    draw_text(image, 6, top - 8, y_label, 14)
    return np.clip(image, 0.0, 1.0).astype(np.float32)
