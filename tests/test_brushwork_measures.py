"""Brushwork figures of bench/brushwork_measures.py against values worked out by hand."""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

from core.strokes import Stroke

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "bench"))
from brushwork_measures import (  # noqa: E402
    detail_share,
    gradient_correlation,
    layer_strokes,
    median_length_to_width_layers,
    speckle_share,
    width_contrast,
)


def stroke(layer, anchor, size, path=((0.0, 0.0),)):
    return Stroke(layer, anchor, size, np.asarray(path, np.float32).reshape(-1, 2), np.zeros(3, np.float32))


def grey(h, w, value):
    return np.full((h, w, 3), value, np.float32)


# Paths of lengths 5 (3-4-5 triangle), 10 and 5 + 6 = 11 px, and a single point (length 0).
SHAPES = [stroke(0, (0, 0), 5, [(0, 0), (3, 4)]),            # L/w = 1
          stroke(0, (0, 0), 5, [(0, 0), (6, 8)]),            # L/w = 2
          stroke(1, (0, 0), 2, [(0, 0), (3, 4), (3, 10)]),   # L/w = 5.5
          stroke(2, (0, 0), 1)]                               # L/w = 0, the last layer


def test_layer_strokes_leave_out_the_last_layer_only_with_a_detail_pass():
    assert layer_strokes([0, 0, 1, 2, 2], 2).tolist() == [True, True, True, False, False]
    assert layer_strokes([0, 0, 1, 2, 2], 0).tolist() == [True] * 5
    assert layer_strokes([], 3).tolist() == []


def test_median_length_to_width_of_layer_strokes():
    assert median_length_to_width_layers(SHAPES, 1) == pytest.approx(2.0)          # median of 1, 2, 5.5
    assert median_length_to_width_layers(SHAPES, 0) == pytest.approx(1.5)          # median of 0, 1, 2, 5.5
    assert math.isnan(median_length_to_width_layers([], 0))


def test_detail_share_counts_the_last_layer_when_there_is_a_detail_pass():
    assert detail_share(SHAPES, 1) == pytest.approx(0.25)
    assert detail_share(SHAPES, 0) == 0.0
    assert detail_share([], 0) == 0.0


def test_speckle_of_a_flat_painting_is_zero():
    assert speckle_share(grey(12, 12, 0.5), grey(12, 12, 0.3)) == 0.0


def test_one_bright_dot_absent_from_the_photo_is_one_pixel_of_speckle():
    painting = grey(10, 12, 0.5)
    painting[4, 5] = 0.7                                 # 0.2 above its 5 x 5 median of 0.5
    assert speckle_share(painting, grey(10, 12, 0.5)) == pytest.approx(1 / 120)
    faint = grey(10, 12, 0.5)
    faint[4, 5] = 0.58                                   # 0.08: not above 0.10
    assert speckle_share(faint, grey(10, 12, 0.5)) == 0.0


def test_a_dot_the_photo_has_too_is_not_speckle():
    painting = grey(10, 12, 0.5)
    painting[4, 5] = 0.7
    # The photo's dot after a Gaussian of 0.7 px keeps the 2-D centre weight (1 / 1.7548)^2 = 0.325 of its
    # 0.2 contrast: 0.065 above the 5 x 5 median, not below 0.04.
    assert speckle_share(painting, painting.copy()) == 0.0


def test_a_coloured_dot_counts_by_its_luminance():
    painting = grey(10, 10, 0.5)
    painting[5, 5] = (0.5, 0.5, 1.0)                     # Y rises by 0.0722 * 0.5 = 0.036 only
    assert speckle_share(painting, grey(10, 10, 0.5)) == 0.0
    painting[5, 5] = (0.5, 0.7, 0.5)                     # Y rises by 0.7152 * 0.2 = 0.143
    assert speckle_share(painting, grey(10, 10, 0.5)) == pytest.approx(1 / 100)


def test_gradient_correlation_ignores_contrast_and_polarity():
    rng = np.random.default_rng(3)
    photo = rng.random((30, 40, 3)).astype(np.float32)
    assert gradient_correlation(photo, photo) == pytest.approx(1.0)
    assert gradient_correlation(0.5 * photo + 0.2, photo) == pytest.approx(1.0)   # magnitudes scale by 0.5
    assert gradient_correlation(1.0 - photo, photo) == pytest.approx(1.0)         # same magnitudes
    assert gradient_correlation(grey(30, 40, 0.4), photo) == 0.0


def test_gradient_correlation_of_edges_in_different_places():
    # Two vertical steps 30 px apart: every row of each gradient magnitude is one profile p, shifted, and the
    # two do not overlap, so the correlation is -S1^2 / (W S2 - S1^2) with S1 = sum p, S2 = sum p^2 over a
    # row of W px. p is proportional to |g(x + 1) - g(x - 1)|, g the step after the Gaussian of 1 px: the
    # sum of the 9 weights exp(-k^2 / 2) (k = -4..4, normalised) over the k that reach the step.
    w = np.exp(-0.5 * np.arange(-4, 5) ** 2)
    w /= w.sum()
    g = np.array([w[np.arange(-4, 5) + x >= 15].sum() for x in range(60)])
    profile = np.abs(g[2:] - g[:-2])
    s1, s2 = profile.sum(), (profile ** 2).sum()
    photo, painting = grey(20, 60, 0.0), grey(20, 60, 0.0)
    photo[:, 15:] = 1.0
    painting[:, 45:] = 1.0
    assert gradient_correlation(painting, photo) == pytest.approx(-s1 ** 2 / (60 * s2 - s1 ** 2), rel=1e-6)


def test_width_contrast_of_strokes_in_known_smooth_and_detailed_pixels():
    # A vertical step between columns 19 and 20 of a 40 px wide photo: after the Gaussian of 2 px (8 px
    # reach) and the Sobel, columns 0-10 and 29-39 have no gradient at all (more than 30 % of the pixels,
    # so that is the smooth class) and columns 18-21 have the largest (the top 10 % of the 40 columns).
    photo = grey(20, 40, 0.0)
    photo[:, 20:] = 1.0
    strokes = [stroke(0, (2, 3), 8), stroke(0, (35, 10), 12), stroke(1, (45, 5), 16),   # smooth (45 -> 39)
               stroke(0, (19, 7), 2), stroke(1, (20, 12), 4),                          # detailed
               stroke(0, (15, 9), 100),                                                # neither
               stroke(2, (5, 5), 40), stroke(2, (19, 2), 1)]                           # the last layer
    assert width_contrast(strokes, photo, 2) == pytest.approx(12 / 3)      # medians of (8, 12, 16), (2, 4)
    assert width_contrast(strokes, photo, 0) == pytest.approx(14 / 2)      # of (8, 12, 16, 40), (2, 4, 1)
    assert math.isnan(width_contrast(strokes[:3], photo, 0))               # no stroke in detail
    assert math.isnan(width_contrast([], photo, 0))
