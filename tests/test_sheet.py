"""Contact sheets: layout, scaling and labels."""

import numpy as np

from core.figures.sheet import BACKGROUND, contact_sheet, fit_height, label_strip


def test_fit_height_keeps_aspect_and_values():
    image = np.full((50, 100, 3), 0.25, np.float32)
    out = fit_height(image, 20)
    assert out.shape == (20, 40, 3)
    np.testing.assert_allclose(out, 0.25, atol=1e-6)
    assert fit_height(np.zeros((10, 10)), 5).shape == (5, 5, 3)


def test_label_strip_draws_text():
    strip = label_strip("Hertzmann 1998", 200, 24)
    assert strip.shape == (24, 200, 3)
    assert (strip.max(axis=2) > 0.5).sum() > 50  # letters are drawn in light grey
    assert np.allclose(label_strip("", 200, 24), BACKGROUND)


def test_sheet_places_every_panel():
    red = np.zeros((30, 60, 3), np.float32)
    red[..., 0] = 1.0
    blue = np.zeros((30, 30, 3), np.float32)
    blue[..., 2] = 1.0
    sheet = contact_sheet([("a", red), ("b", blue), ("c", red)], panel_height=30, columns=2, gap=4,
                          label_height=10)
    assert sheet.shape == (2 * 40 + 3 * 4, 2 * 60 + 3 * 4, 3)
    assert np.allclose(sheet[4 + 10, 4], (1, 0, 0))           # first panel, below its label
    assert np.allclose(sheet[4 + 10, 4 + 60 + 4], (0, 0, 1))  # second panel
    assert np.allclose(sheet[4 + 40 + 4 + 10, 4], (1, 0, 0))  # third panel, second row
    assert np.allclose(sheet[4 + 10, 4 + 60 + 4 + 40], BACKGROUND)  # right of the narrow panel
