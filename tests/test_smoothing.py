"""The reference smoothed at a brush's scale (core.strokes.smoothing): blur, block levels and sampling."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from core.strokes.smoothing import block_mean, smooth


def test_small_sigmas_blur_at_full_resolution():
    image = np.random.default_rng(0).random((40, 50, 3)).astype(np.float32)
    level = smooth(image, 1.5)
    assert level.factor == 1
    expected = ndimage.gaussian_filter(image.astype(np.float64), sigma=(1.5, 1.5, 0), mode="reflect")
    np.testing.assert_allclose(level.pixels, expected, atol=1e-5)
    np.testing.assert_allclose(level.sample(np.array([7.0, 31.0]), np.array([4.0, 22.0])),
                               expected[[4, 22], [7, 31]], atol=1e-5)


@pytest.mark.parametrize("sigma", [6.0, 20.0])
def test_block_levels_sample_a_linear_ramp_back(sigma):
    # blurring and block means keep a linear ramp (away from the reflected borders); bilinear sampling then
    # gives back the ramp's value at any position between block centres
    h, w = 300, 400
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    ramp = np.stack([0.002 * xx, 0.003 * yy, 0.001 * (xx + yy)], axis=-1).astype(np.float32)
    level = smooth(ramp, sigma)
    assert level.factor == int(sigma // 2)
    x = np.array([170.0, 181.3, 200.75, 229.5])
    y = np.array([125.0, 142.25, 150.5, 170.0])
    expected = np.stack([0.002 * x, 0.003 * y, 0.001 * (x + y)], axis=-1)
    np.testing.assert_allclose(level.sample(x, y), expected, atol=2e-4)


def test_a_one_pixel_image_is_that_pixel_everywhere():
    level = smooth(np.array([[[0.2, 0.4, 0.6]]], np.float32), 0.0)
    values = level.sample(np.array([0.0, 3.5], np.float32), np.array([0.0, -2.0], np.float32))
    np.testing.assert_array_equal(values, np.array([[0.2, 0.4, 0.6]] * 2, np.float32))


@pytest.mark.parametrize("shape, factor", [((9, 12, 3), 3), ((10, 7, 3), 4), ((5, 5, 1), 2), ((1, 1, 3), 2)])
def test_block_means_sum_each_block_in_row_major_order(shape, factor):
    # every block, edge blocks padded with their edge pixels, summed pixel after pixel in float32 and divided
    # by the block's f^2 pixels, worked out one block at a time
    image = (np.random.default_rng(7).random(shape) * 100).astype(np.float32)
    h, w, channels = shape
    means = block_mean(image, factor)
    assert means.shape == (-(-h // factor), -(-w // factor), channels) and means.dtype == np.float32
    for i in range(means.shape[0]):
        for j in range(means.shape[1]):
            total = np.zeros(channels, np.float32)
            for a in range(factor):
                for b in range(factor):
                    total += image[min(i * factor + a, h - 1), min(j * factor + b, w - 1)]
            np.testing.assert_array_equal(means[i, j], total / np.float32(factor * factor))
