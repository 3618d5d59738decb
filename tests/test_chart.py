"""Line charts: lines land where their values say."""

import numpy as np

from core.figures.chart import SERIES_COLOURS, draw_segment, line_chart


def test_segment_is_drawn_between_its_ends_only():
    image = np.ones((20, 40, 3))
    draw_segment(image, (5, 10), (30, 10), 3.0, (1.0, 0.0, 0.0))
    assert np.allclose(image[10, 15], (1, 0, 0))
    assert np.allclose(image[10, 38], (1, 1, 1)) and np.allclose(image[2, 15], (1, 1, 1))


def test_a_flat_series_is_a_horizontal_line_at_its_value():
    chart = line_chart([("zero", [0, 360], [0.5, 0.5])], (0, 360), (-1, 1), [0, 180, 360], [-1, 0, 1],
                       size=(400, 300))
    # Plot area: x 70..380, y 40..240; y = 0.5 sits a quarter of the way down.
    row = 40 + round(0.25 * 200)
    np.testing.assert_allclose(chart[row, 200], SERIES_COLOURS[0], atol=0.02)
    assert not np.allclose(chart[row + 20, 200], SERIES_COLOURS[0], atol=0.1)
