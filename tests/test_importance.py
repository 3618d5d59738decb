"""Reference image and importance map (ALGORITHM §1)."""

import numpy as np

from core.analysis.importance import (
    bilateral_filter,
    importance_map,
    normalise_energy,
    reference_image,
    resize_mask,
    sobel_energy,
)


def test_constant_image_has_zero_energy():
    image = np.full((40, 60, 3), 0.37, dtype=np.float32)
    reference = reference_image(image, 0.005, 0.1)
    assert np.all(sobel_energy(reference[..., 0]) == 0.0)
    assert np.all(importance_map(reference, 99.0) == 0.0)


def test_sobel_energy_of_a_linear_ramp_is_its_slope():
    x = np.arange(50, dtype=np.float32)
    ramp = np.tile(0.01 * x, (30, 1))
    energy = sobel_energy(ramp)
    np.testing.assert_allclose(energy[1:-1, 1:-1], 0.01, rtol=1e-4)


def test_bilateral_filter_keeps_a_step_edge_and_reduces_noise():
    rng = np.random.default_rng(3)
    clean = np.zeros((96, 96), dtype=np.float32)
    clean[:, 48:] = 0.8
    noisy = clean + rng.normal(0.0, 0.03, clean.shape).astype(np.float32)
    filtered = bilateral_filter(noisy, sigma_spatial=4.0, sigma_range=0.1)
    interior = np.s_[8:-8, 8:40], np.s_[8:-8, 56:-8]
    for region in interior:
        assert filtered[region].std() < 0.5 * noisy[region].std()
    # The step stays a step: the two pixels either side of it keep their levels.
    assert abs(filtered[8:-8, 46].mean() - 0.0) < 0.05
    assert abs(filtered[8:-8, 49].mean() - 0.8) < 0.05
    # A plain Gaussian of the same sigma would have blurred it to about the middle value.
    assert filtered[8:-8, 47].mean() < 0.1 and filtered[8:-8, 48].mean() > 0.7


def test_bilateral_filter_preserves_constant_and_shape():
    image = np.full((20, 30, 3), 0.25, dtype=np.float32)
    out = bilateral_filter(image, 3.0, 0.1)
    assert out.shape == image.shape and out.dtype == np.float32
    np.testing.assert_allclose(out, 0.25, atol=1e-5)


def test_normalise_energy_clips_hot_pixels():
    energy = np.full((100, 100), 0.1, dtype=np.float32)
    energy[0, 0] = 100.0
    norm = normalise_energy(energy, 99.0)
    assert norm.max() == 1.0 and norm.min() >= 0.0
    # One hot pixel does not flatten the map: everything else normalises to 1 too.
    assert np.count_nonzero(norm == 1.0) == norm.size


def test_mask_raises_importance_where_it_is_white():
    rng = np.random.default_rng(0)
    reference = rng.random((32, 32, 3), dtype=np.float32)
    mask = np.zeros((16, 16), dtype=np.float32)
    mask[:, 8:] = 1.0
    plain = importance_map(reference, 100.0)
    boosted = importance_map(reference, 100.0, mask=mask, mask_strength=3.0)
    ratio_left = boosted[:, :16].mean() / plain[:, :16].mean()
    ratio_right = boosted[:, 16:].mean() / plain[:, 16:].mean()
    assert ratio_right > 2.0 * ratio_left


def test_resize_mask_to_image_shape():
    mask = np.array([[0.0, 1.0]], dtype=np.float32)
    out = resize_mask(mask, (4, 8))
    assert out.shape == (4, 8)
    assert out[:, 0].max() == 0.0 and out[:, -1].min() == 1.0
