"""HSV conversions of core/colour.py against Python's colorsys."""

import colorsys

import numpy as np

from core.colour import hsv_to_rgb, rgb_to_hsv


def colours() -> np.ndarray:
    """(N, 3) float64 RGB [0, 1]: random colours, a few hundred in each of the six hue sectors (saturated and
    faint, dark and light), greys with black and white, the primaries and secondaries, and colours whose two
    largest channels tie."""
    rng = np.random.default_rng(7)
    hsv = np.column_stack([(np.repeat(np.arange(6), 300) + rng.random(1800)) / 6.0, rng.random(1800),
                           rng.random(1800)])
    by_sector = np.array([colorsys.hsv_to_rgb(*c) for c in hsv])
    greys = np.repeat(np.concatenate([[0.0, 1.0], rng.random(50)])[:, None], 3, axis=1)
    corners = np.array([[1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 1, 1], [0, 0, 1], [1, 0, 1]], np.float64)
    ties = rng.random((60, 3))
    for i, (a, b) in enumerate([(0, 1), (1, 2), (2, 0)] * 20):
        ties[i, b] = ties[i, a] = max(ties[i, a], ties[i, b])
    return np.concatenate([rng.random((2000, 3)), by_sector, greys, corners, 0.4 * corners + 0.3, ties])


def hue_distance(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance between hues (fractions of a turn) around the circle: 0.999 and 0 are 0.001 apart."""
    d = np.abs(a - b) % 1.0
    return np.minimum(d, 1.0 - d)


def test_the_colours_cover_every_hue_sector_and_the_greys():
    rgb = colours()
    hsv = np.array([colorsys.rgb_to_hsv(*c) for c in rgb])
    sector = np.floor(hsv[:, 0] * 6).astype(int)
    assert np.bincount(sector[hsv[:, 1] > 0], minlength=6).min() >= 300
    assert {(0.0, 0.0, 0.0), (1.0, 1.0, 1.0)} <= set(map(tuple, rgb.tolist()))
    assert (hsv[:, 1] == 0).sum() >= 52


def test_rgb_to_hsv_is_colorsys():
    rgb = colours()
    ours = rgb_to_hsv(rgb)
    theirs = np.array([colorsys.rgb_to_hsv(*c) for c in rgb])
    assert ours.shape == rgb.shape and ours.dtype == np.float64
    assert hue_distance(ours[:, 0], theirs[:, 0]).max() < 1e-12
    np.testing.assert_allclose(ours[:, 1:], theirs[:, 1:], rtol=0, atol=1e-12)
    grey = rgb.max(axis=1) == rgb.min(axis=1)
    assert np.all(ours[grey, :2] == 0.0)             # a grey has neither hue nor saturation


def test_hsv_to_rgb_is_colorsys_and_undoes_rgb_to_hsv():
    rgb = colours()
    hsv = np.array([colorsys.rgb_to_hsv(*c) for c in rgb])
    ours = hsv_to_rgb(hsv)
    theirs = np.array([colorsys.hsv_to_rgb(*c) for c in hsv])
    np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-12)
    np.testing.assert_allclose(hsv_to_rgb(rgb_to_hsv(rgb)), rgb, rtol=0, atol=1e-12)
