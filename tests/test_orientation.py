"""Tests of the orientation field (core/analysis/orientation.py, ALGORITHM §4, Eq. 3)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import RBFInterpolator

from core.analysis.orientation import (
    blend_orientations,
    gradient_normal,
    key_points,
    local_rbf_grid,
    orientation_field,
    rbf_orientation,
)
from core.params import Params

ANGLES_DEG = [0, 1, 30, 45, 89, 90, 135, 179]
BORDER = 8


def axial_diff(a, b):
    """Smallest difference between axial angles (radians), in [0, π/2]."""
    d = np.mod(np.abs(np.asarray(a, dtype=np.float64) - np.asarray(b, dtype=np.float64)), math.pi)
    return np.minimum(d, math.pi - d)


def stripes(phi_deg, shape=(128, 128), wavelength=12.0):
    """Sinusoidal stripes whose gradient points along phi; they run along phi + 90°."""
    h, w = shape
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    phi = math.radians(phi_deg)
    return (0.5 + 0.5 * np.sin(2 * math.pi * (x * math.cos(phi) + y * math.sin(phi)) / wavelength)).astype(np.float32)


def expected_tangent(phi_deg):
    return math.fmod(math.radians(phi_deg) + math.pi / 2, math.pi)


def fraction_within(theta, target, tol_deg=5.0, border=BORDER):
    inner = theta[border:-border, border:-border]
    return float(np.mean(axial_diff(inner, target) <= math.radians(tol_deg)))


def check_range(theta, shape):
    assert theta.shape == shape
    assert theta.dtype == np.float32
    assert np.all(np.isfinite(theta))
    assert theta.min() >= 0.0
    assert theta.max() < math.pi


# --- gradient_normal -----------------------------------------------------------------------

@pytest.mark.parametrize("phi", ANGLES_DEG)
def test_gradient_normal_recovers_stripe_tangent(phi):
    theta, strength = gradient_normal(stripes(phi), sigma=1.5)
    check_range(theta, (128, 128))
    assert strength.dtype == np.float32 and strength.shape == (128, 128)
    assert fraction_within(theta, expected_tangent(phi)) >= 0.95


def test_gradient_normal_defined_at_crests():
    # Vertical stripes (gradient along x): crests are columns where the raw gradient is ~0.
    img = stripes(0)
    theta, strength = gradient_normal(img, sigma=1.5)
    crest_cols = [c for c in range(BORDER, 128 - BORDER) if abs(math.sin(2 * math.pi * c / 12.0)) > 0.99]
    assert crest_cols
    inner = theta[BORDER:-BORDER, crest_cols]
    assert np.all(axial_diff(inner, math.pi / 2) <= math.radians(5))
    assert np.all(strength[BORDER:-BORDER, crest_cols] > 0)


def test_gradient_normal_single_edge_and_strength():
    img = np.zeros((40, 60), dtype=np.float32)
    img[:, 30:] = 1.0  # vertical edge: tangent is vertical (π/2)
    theta, strength = gradient_normal(img, sigma=1.0)
    assert np.all(axial_diff(theta[5:-5, 29:31], math.pi / 2) < 1e-3)
    assert strength[20, 29:31].max() > 0.1
    assert strength[20, 5] == 0.0


def test_gradient_normal_constant_image():
    theta, strength = gradient_normal(np.full((30, 20), 0.4, dtype=np.float32), sigma=1.5)
    check_range(theta, (30, 20))
    assert np.all(theta == 0.0)
    assert np.all(strength == 0.0)


# --- key_points ----------------------------------------------------------------------------

def test_key_points_one_per_cell_strongest():
    rng = np.random.default_rng(1)
    energy = rng.random((100, 100)).astype(np.float32)
    strength = np.ones_like(energy)
    ys, xs = key_points(strength, energy, cells=10, threshold=0.0, max_points=10_000)
    assert ys.dtype.kind == "i" and xs.dtype.kind == "i"
    assert len(ys) == 100
    cells = set(zip((ys // 10).tolist(), (xs // 10).tolist(), strict=True))
    assert len(cells) == 100
    for y, x in zip(ys, xs, strict=True):
        cy, cx = y // 10 * 10, x // 10 * 10
        assert energy[y, x] == energy[cy:cy + 10, cx:cx + 10].max()


def test_key_points_threshold_and_max_points():
    rng = np.random.default_rng(2)
    energy = rng.random((90, 90)).astype(np.float32)
    strength = np.ones_like(energy)
    ys, xs = key_points(strength, energy, cells=9, threshold=0.999, max_points=10_000)
    assert np.all(energy[ys, xs] >= 0.999)
    all_ys, all_xs = key_points(strength, energy, cells=9, threshold=0.0, max_points=10_000)
    ys, xs = key_points(strength, energy, cells=9, threshold=0.0, max_points=5)
    assert len(ys) == 5
    kept = np.sort(energy[ys, xs])
    assert np.array_equal(kept, np.sort(energy[all_ys, all_xs])[-5:])


def test_key_points_aspect_ratio_and_edge_cases():
    energy = np.ones((50, 200), dtype=np.float32)
    strength = np.ones_like(energy)
    ys, xs = key_points(strength, energy, cells=10, threshold=0.5, max_points=10_000)
    # ~100 cells, 4x as many along x as along y: roughly square cells.
    assert 80 <= len(ys) <= 120
    assert len(np.unique(xs)) > 3 * len(np.unique(ys))
    # zero strength (undefined O_GN) and zero energy give no key points
    assert len(key_points(np.zeros_like(energy), energy, 10, 0.1, 100)[0]) == 0
    assert len(key_points(strength, np.zeros_like(energy), 10, 0.1, 100)[0]) == 0
    # a tiny image and more cells than pixels
    ys, xs = key_points(np.ones((3, 2), np.float32), np.ones((3, 2), np.float32), 40, 0.1, 100)
    assert len(ys) == 6


# --- rbf_orientation -----------------------------------------------------------------------

@pytest.mark.parametrize("const", [0.0, 0.01, 1.0, math.pi / 2, math.pi - 0.01])
def test_rbf_reproduces_constant_field(const):
    rng = np.random.default_rng(3)
    shape = (120, 150)
    theta_gn = np.full(shape, const, dtype=np.float32)
    ys = rng.integers(0, shape[0], 200)
    xs = rng.integers(0, shape[1], 200)
    theta = rbf_orientation(theta_gn, ys, xs, shape, neighbors=32, step=8)
    check_range(theta, shape)
    assert axial_diff(theta, const).max() <= math.radians(1)


@pytest.mark.parametrize("left,right", [(0.2, 1.2), (math.radians(10), math.radians(170))])
def test_rbf_interpolates_between_two_regions(left, right):
    shape = (100, 200)
    theta_gn = np.full(shape, left, dtype=np.float32)
    theta_gn[:, 100:] = right
    gy, gx = np.mgrid[5:100:10, 5:200:10]
    ys, xs = gy.ravel(), gx.ravel()
    theta = rbf_orientation(theta_gn, ys, xs, shape, neighbors=16, step=4)
    check_range(theta, shape)
    assert axial_diff(theta[:, :60], left).max() <= math.radians(3)
    assert axial_diff(theta[:, 140:], right).max() <= math.radians(3)
    # in between: on the short arc from left to right (through 0 for 10°/170°, not through 90°),
    # allowing the local fits' slight overshoot
    span = axial_diff(left, right)
    mid = theta[:, 60:140]
    assert np.all(axial_diff(mid, left) + axial_diff(mid, right) <= span + math.radians(3))
    # and it moves monotonically-ish from one to the other along a row
    row = axial_diff(theta[50], left)
    assert row[0] < row[100] < row[-1] or math.isclose(row[100], span / 2, abs_tol=math.radians(10))


def test_rbf_fallbacks():
    shape = (40, 50)
    theta_gn = np.full(shape, 0.7, dtype=np.float32)
    none = rbf_orientation(theta_gn, np.array([], int), np.array([], int), shape, 32, 8)
    check_range(none, shape)
    assert np.allclose(none, 0.7, atol=1e-5)  # dominant orientation of theta_gn
    one = rbf_orientation(theta_gn, np.array([3]), np.array([4]), shape, 32, 8)
    assert np.allclose(one, 0.7, atol=1e-5)
    theta_gn[10, 10] = math.radians(5)
    theta_gn[20, 20] = math.radians(175)
    two = rbf_orientation(theta_gn, np.array([10, 20]), np.array([10, 20]), shape, 32, 8)
    check_range(two, shape)
    assert np.all(axial_diff(two, 0.0) < 1e-4)  # axial mean of 5° and 175° is 0°
    # collinear key points (a horizontal edge) are not singular
    ys, xs = np.full(10, 15), np.arange(0, 50, 5)
    line = rbf_orientation(np.full(shape, 0.3, np.float32), ys, xs, shape, 4, 3)
    assert axial_diff(line, 0.3).max() <= math.radians(1)


def test_local_rbf_grid_matches_scipy_when_global_and_is_continuous():
    rng = np.random.default_rng(4)
    pts = rng.random((40, 2))
    vals = np.column_stack([np.sin(3 * pts[:, 0]), pts[:, 1] ** 2])
    g = np.linspace(0, 1, 25)
    ours = local_rbf_grid(pts, vals, g, g, neighbors=40, spacing=0.1)
    query = np.stack(np.meshgrid(g, g, indexing="ij"), axis=-1).reshape(-1, 2)
    ref = RBFInterpolator(pts, vals, kernel="linear", degree=0, smoothing=1e-6)(query).reshape(25, 25, 2)
    assert np.allclose(ours, ref, atol=1e-8)
    # local mode: continuous (no jumps between neighbouring grid samples on a fine grid)
    pts = rng.random((300, 2))
    vals = np.column_stack([np.cos(4 * pts[:, 0]), np.sin(4 * pts[:, 1])])
    fine = np.linspace(0, 1, 400)
    out = local_rbf_grid(pts, vals, fine, fine, neighbors=12, spacing=0.06)
    assert np.abs(np.diff(out, axis=0)).max() < 0.1
    assert np.abs(np.diff(out, axis=1)).max() < 0.1


# --- blend_orientations --------------------------------------------------------------------

def test_blend_wraps_around():
    a = np.full((3, 3), math.radians(1), dtype=np.float32)
    b = np.full((3, 3), math.radians(179), dtype=np.float32)
    out = blend_orientations(a, b, np.full((3, 3), 0.5, dtype=np.float32))
    check_range(out, (3, 3))
    assert np.all(axial_diff(out, 0.0) < math.radians(0.01))


def test_blend_weights_and_degenerate():
    g = np.full((2, 2), 0.3, dtype=np.float32)
    r = np.full((2, 2), 1.1, dtype=np.float32)
    assert np.allclose(blend_orientations(g, r, np.ones((2, 2), np.float32)), 0.3, atol=1e-6)
    assert np.allclose(blend_orientations(g, r, np.zeros((2, 2), np.float32)), 1.1, atol=1e-6)
    half = blend_orientations(g, r, np.full((2, 2), 0.5, np.float32))
    assert np.allclose(half, 0.7, atol=1e-5)
    # perpendicular orientations with equal weights cancel: O_GN is taken
    perp = blend_orientations(g, g + math.pi / 2, np.full((2, 2), 0.5, np.float32))
    assert np.allclose(perp, 0.3, atol=1e-6)


@settings(max_examples=200, deadline=None)
@given(st.floats(0, math.pi, exclude_max=True), st.floats(0, math.pi, exclude_max=True), st.floats(0, 1))
def test_blend_lies_on_short_arc(a, b, e):
    out = blend_orientations(np.array([[a]], np.float32), np.array([[b]], np.float32), np.array([[e]], np.float32))
    check_range(out, (1, 1))
    span = axial_diff(a, b)
    if span < math.pi / 2 - 1e-3:
        assert axial_diff(out, a) + axial_diff(out, b) <= span + 1e-4


# --- orientation_field ---------------------------------------------------------------------

@pytest.mark.parametrize("energy_value", [1.0, 0.2])
@pytest.mark.parametrize("phi", ANGLES_DEG)
def test_orientation_field_stripes(phi, energy_value):
    img = stripes(phi)
    energy = np.full(img.shape, energy_value, dtype=np.float32)
    theta = orientation_field(img, energy, Params())
    check_range(theta, img.shape)
    assert fraction_within(theta, expected_tangent(phi)) >= 0.95


@pytest.mark.parametrize("phi", [1, 89, 179])
def test_orientation_field_stripes_rbf_only_and_small_scale(phi):
    img = stripes(phi)
    params = Params()
    scale = math.sqrt(img.size / 1e6)
    for energy_value in (0.0, 0.05, 0.5):  # 0 / 0.05: no key points (below threshold)
        energy = np.full(img.shape, energy_value, dtype=np.float32)
        theta = orientation_field(img, energy, params, scale=scale)
        assert fraction_within(theta, expected_tangent(phi)) >= 0.95


def test_orientation_field_constant_image():
    img = np.full((64, 80), 0.5, dtype=np.float32)
    theta = orientation_field(img, np.zeros_like(img), Params())
    check_range(theta, img.shape)


def test_orientation_field_shapes_and_determinism():
    rng = np.random.default_rng(5)
    img = np.clip(stripes(30, shape=(90, 140)) + 0.1 * rng.standard_normal((90, 140)), 0, 1).astype(np.float32)
    energy = rng.random(img.shape).astype(np.float32)
    a = orientation_field(img, energy, Params(), scale=0.3)
    b = orientation_field(img, energy, Params(), scale=0.3)
    check_range(a, img.shape)
    assert np.array_equal(a, b)
    with pytest.raises(ValueError):
        orientation_field(img, energy[:10], Params())


def test_orientation_field_edge_with_flat_surroundings():
    # A disc: in flat areas (energy 0) the RBF carries the orientation of the nearest edges.
    h = w = 120
    y, x = np.mgrid[0:h, 0:w].astype(np.float32)
    img = np.clip(30.5 - np.hypot(y - 60, x - 60), 0, 1).astype(np.float32)  # anti-aliased disc
    theta_gn, strength = gradient_normal(img, 1.5)
    energy = np.clip(strength / strength.max(), 0, 1).astype(np.float32)
    theta = orientation_field(img, energy, Params(), scale=0.12)
    check_range(theta, img.shape)
    # on the rim the tangent is perpendicular to the radius
    rim = np.abs(np.hypot(y - 60, x - 60) - 30) < 1.0
    radial = np.arctan2(y - 60, x - 60)
    assert np.mean(axial_diff(theta[rim], radial[rim] + math.pi / 2) < math.radians(5)) > 0.95
