"""Image comparison figures against values worked out by hand."""

import math

import numpy as np
import pytest

from core.measures.metrics import edge_fidelity, pearson, psnr, ssim


def test_psnr_of_a_known_error():
    a = np.zeros((10, 10, 3))
    assert psnr(a, a + 0.1) == pytest.approx(20.0)
    assert psnr(a, a + 0.01) == pytest.approx(40.0)
    assert math.isinf(psnr(a, a))


def test_ssim_bounds_and_known_cases():
    rng = np.random.default_rng(0)
    a = rng.random((40, 50))
    assert ssim(a, a) == pytest.approx(1.0)
    # A constant offset leaves contrast and structure alone: only the luminance term drops.
    # For means m and m + 0.2 the luminance term is (2 m (m+0.2) + c1) / (m^2 + (m+0.2)^2 + c1).
    flat = np.full((40, 50), 0.3)
    c1 = 0.01 ** 2
    expected = (2 * 0.3 * 0.5 + c1) / (0.3 ** 2 + 0.5 ** 2 + c1)
    assert ssim(flat, flat + 0.2) == pytest.approx(expected, rel=1e-9)
    assert ssim(a, 1.0 - a) < 0.0


def test_pearson_signs_and_constants():
    x = np.arange(20.0)
    assert pearson(x, 3 * x + 1) == pytest.approx(1.0)
    assert pearson(x, -x) == pytest.approx(-1.0)
    assert pearson(x, np.ones(20)) == 0.0


def test_edge_fidelity_ignores_contrast_scale_but_not_blur():
    rng = np.random.default_rng(1)
    a = rng.random((60, 60, 3))
    assert edge_fidelity(0.5 * a, a) == pytest.approx(1.0)
    assert edge_fidelity(np.full_like(a, 0.5) + 0.01 * a[::-1], a) < 0.3
