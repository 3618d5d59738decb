"""The bitmap font: labels are drawn without FreeType, the same everywhere."""

import sys

import numpy as np
import pytest

from core.figures import text
from core.figures.chart import line_chart
from core.figures.sheet import BACKGROUND, LABEL_COLOUR, label_strip


class _NoFreeType:
    """Stands in for an OpenImageIO built without FreeType: render_text draws nothing and returns False."""

    @staticmethod
    def render_text(*args, **kwargs):
        return False


@pytest.fixture
def no_freetype(monkeypatch):
    oiio = pytest.importorskip("OpenImageIO")
    monkeypatch.setattr(oiio, "ImageBufAlgo", _NoFreeType)
    return oiio


def test_labels_are_drawn_when_render_text_fails(no_freetype):
    assert no_freetype.ImageBufAlgo.render_text(None, 0, 0, "x") is False
    strip = label_strip("Cycles relief, light at 45 deg", 300, 24)
    lit = np.abs(strip - np.asarray(BACKGROUND)).max(axis=2) > 0.3
    assert lit.sum() > 150
    # The letters lie between the strip's top and bottom, starting at the 6 px margin.
    columns = np.flatnonzero(lit.any(axis=0))
    assert 5 <= columns[0] <= 8 and columns[-1] < 300


def test_labels_need_no_openimageio(monkeypatch):
    monkeypatch.setitem(sys.modules, "OpenImageIO", None)  # any import of it now fails
    strip = label_strip("r = +0.22", 120, 24)
    assert (np.abs(strip - np.asarray(BACKGROUND)).max(axis=2) > 0.3).sum() > 40


def test_chart_text_is_drawn(no_freetype):
    args = ([("paper", [0, 360], [0.0, 0.0])], (0, 360), (-1, 1), [0, 360], [-1, 1])
    titled = line_chart(*args, title="Pearson r per light azimuth", size=(400, 300))
    plain = line_chart(*args, size=(400, 300))
    title_rows = slice(5, 30)
    changed = np.abs(titled[title_rows] - plain[title_rows]).max(axis=2) > 0.3
    assert changed.sum() > 100
    assert np.array_equal(titled[60:], plain[60:])  # the title touches only its own rows


def test_text_scales_and_is_repeatable():
    assert text.text_width("Hertzmann", 28) == pytest.approx(2 * text.text_width("Hertzmann", 14))
    assert text.text_width("", 14) == 0.0
    a = np.zeros((40, 200, 3), np.float32)
    b = np.zeros((40, 200, 3), np.float32)
    text.draw_text(a, 3, 30, "Same text", 20, (1, 1, 1))
    text.draw_text(b, 3, 30, "Same text", 20, (1, 1, 1))
    assert np.array_equal(a, b) and a.max() == pytest.approx(1.0, abs=0.02)
    ink = np.flatnonzero(a[..., 0].max(axis=0) > 0.1)
    assert ink[-1] <= 3 + text.text_width("Same text", 20) + 1


def test_text_sits_on_its_baseline_and_is_clipped():
    image = np.zeros((60, 100, 1), np.float32)
    text.draw_text(image, 10, 40, "Hxg", 30, (1.0,))
    rows = np.flatnonzero(image[..., 0].max(axis=1) > 0.5)
    assert rows[0] >= 40 - 0.75 * 30 and 38 <= np.flatnonzero(image[:, 10:30, 0].max(axis=1) > 0.5)[-1] <= 41
    assert rows[-1] > 42  # the g descends below the baseline
    edge = np.zeros((10, 10, 3), np.float32)
    text.draw_text(edge, -50, 5, "far off the left edge", 12, (1, 1, 1))
    text.draw_text(edge, 0, 500, "below", 12, (1, 1, 1))
    assert edge.shape == (10, 10, 3)


def test_non_ascii_is_spelled_out():
    assert text.text_width("600×400", 14) == pytest.approx(text.text_width("600x400", 14))
    assert text.text_width("45°", 14) == pytest.approx(text.text_width("45 deg", 14))
    assert text.text_width("\u4e2d", 14) == pytest.approx(text.text_width("?", 14))


def test_label_colour_reaches_full_strength():
    strip = label_strip("HHHH", 100, 48)
    assert np.allclose(strip.reshape(-1, 3)[np.argmax(strip.sum(axis=2))], LABEL_COLOUR, atol=0.03)
