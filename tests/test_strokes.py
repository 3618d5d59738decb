"""Tests of the stroke engine: Eq. 4 compositing, strokes, paths, layout, relief maps, the whole painter.

Expected values are worked out by hand in each test from ALGORITHM §3, §5 and
§6 (not by calling the code under test a second way).
"""

from __future__ import annotations

import math
import pathlib

import numpy as np
import OpenImageIO as oiio
import pytest
from oracles import one_sentence
from scipy import ndimage
from stamp_oracle import box_footprint, stroke_footprint
from stamp_oracle import paint_one as engine_one

from core.errors import PaintReliefError, ParameterError
from core.files.reading import read_image
from core.methods import paint
from core.params import CANVAS_COLOUR, Params
from core.strokes.brush import BrushTip, brush_tip, load_brush
from core.strokes.canvas import Canvas
from core.strokes.compositing import track_footprints
from core.strokes.layout import choose_anchors
from core.strokes.smoothing import smooth
from core.strokes.stroke import ColourSources, colour_sources

ROOT = pathlib.Path(__file__).resolve().parents[1]
C0 = np.array(CANVAS_COLOUR, dtype=np.float64)


# ---------------------------------------------------------------------------
# small shared helpers


def make_tip(bristles) -> BrushTip:
    """A hand-made tip from [(along, across, intensity), ...]."""
    b = np.array(bristles, dtype=np.float32)
    return BrushTip(b[:, 0].copy(), b[:, 1].copy(), b[:, 2].copy(), 3.0, 3.0)


def write_png(path, pixels: np.ndarray) -> None:
    """Write float (H, W) values in [0, 1] as an 8-bit gray PNG with OpenImageIO."""
    data = np.clip(np.round(np.asarray(pixels, np.float64) * 255), 0, 255).astype(np.uint8)[:, :, None]
    spec = oiio.ImageSpec(data.shape[1], data.shape[0], 1, "uint8")
    out = oiio.ImageOutput.create(str(path))
    assert out is not None and out.open(str(path), spec), oiio.geterror()
    assert out.write_image(np.ascontiguousarray(data))
    out.close()


@pytest.fixture(scope="module")
def flat():
    return load_brush("flat")


def straight_samples(x0: int, x1: int, y: int) -> tuple:
    """Integer path samples from x0 to x1 (inclusive) along row y, angle 0."""
    xs = np.arange(x0, x1 + 1, dtype=np.float64)
    samples = np.stack([xs, np.full_like(xs, y)], axis=1)
    return samples, np.zeros(len(xs))


def stripes_reference(h: int, w: int, palette: np.ndarray, period: int) -> np.ndarray:
    """Horizontal stripes: the colour changes with the row (across a horizontal stroke)."""
    idx = (np.arange(h) // period) % len(palette)
    return np.ascontiguousarray(np.repeat(palette[idx][:, None, :], w, axis=1).astype(np.float32))


# ---------------------------------------------------------------------------
# 1. Eq. 4 for one stamp and for two stamps over one pixel


def test_eq4_single_stamp_by_hand():
    # one sample at (x=5, y=5), angle 0: along = +x, across = +y.
    samples = np.array([[5.0, 5.0]])
    angles = np.array([0.0])
    along = np.array([0.0, 2.0, 0.0], np.float32)
    across = np.array([0.0, 0.0, -2.0], np.float32)
    inten = np.array([0.8, 0.5, 0.3], np.float32)
    colours = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.2, 0.4, 0.9]], np.float32)
    canvas_rgb = np.array([0.5, 0.25, 0.75])
    canvas = Canvas.blank((9, 10), canvas_rgb)
    fp = stroke_footprint(samples, angles, along, across, inten, colours, (9, 10))
    canvas.lay(fp, "over", 0.5)

    expected = {  # (x, y): I * C_b + (1 - I) * C_canvas, by hand
        (5, 5): (0.8 * 1.0 + 0.2 * 0.5, 0.8 * 0.0 + 0.2 * 0.25, 0.8 * 0.0 + 0.2 * 0.75),
        (7, 5): (0.5 * 0.0 + 0.5 * 0.5, 0.5 * 1.0 + 0.5 * 0.25, 0.5 * 0.0 + 0.5 * 0.75),
        (5, 3): (0.3 * 0.2 + 0.7 * 0.5, 0.3 * 0.4 + 0.7 * 0.25, 0.3 * 0.9 + 0.7 * 0.75),
    }
    hit = np.zeros((9, 10), bool)
    for (x, y), rgb in expected.items():
        np.testing.assert_allclose(canvas.colour[y, x], rgb, atol=1e-5)
        hit[y, x] = True
    # nothing else changed
    np.testing.assert_array_equal(canvas.colour[~hit], np.broadcast_to(canvas_rgb.astype(np.float32), (int((~hit).sum()), 3)))
    # coverage: 1 - (1 - I) with one bristle per pixel; 0 elsewhere
    np.testing.assert_allclose([canvas.coverage[5, 5], canvas.coverage[5, 7], canvas.coverage[3, 5]],
                               [0.8, 0.5, 0.3], atol=1e-5)
    assert np.all(canvas.coverage[~hit] == 0)
    # relief by hand: deposit h = I (one row); h90 = 90th percentile of (0.3, 0.8, 0.5) = 0.74;
    # f = min(1, h / h90); o = (1 - T) f = I f; on a bare canvas H = (1 - T) h = I h, the paint as thick as it is
    h90 = 0.5 + 0.8 * (0.8 - 0.5)
    for (x, y), i in (((5, 5), 0.8), ((7, 5), 0.5), ((5, 3), 0.3)):
        f = min(1.0, i / h90)
        assert canvas.height[y, x] == pytest.approx(i * i, abs=1e-5)
        assert canvas.opacity[y, x] == pytest.approx(i * f, abs=1e-5)


def test_eq4_two_stamps_fold_later_on_top():
    # stamp 0 at x=5 puts bristle A (along 0) on pixel (5, 5);
    # stamp 1 at x=6 puts bristle B (along -1) on the same pixel, later.
    samples = np.array([[5.0, 5.0], [6.0, 5.0]])
    angles = np.zeros(2)
    along = np.array([0.0, -1.0], np.float32)
    across = np.zeros(2, np.float32)
    inten = np.array([0.6, 0.5], np.float32)
    a = np.array([1.0, 0.0, 0.0])
    b = np.array([0.0, 0.0, 1.0])
    colours = np.array([a, b], np.float32)
    canvas = Canvas.blank((11, 11), C0)
    fp = stroke_footprint(samples, angles, along, across, inten, colours, (11, 11))
    canvas.lay(fp, "over", 0.5)

    first = 0.6 * a + 0.4 * C0                     # stamp 0
    later_on_top = 0.5 * b + 0.5 * first           # stamp 1 over it
    wrong_order = 0.6 * a + 0.4 * (0.5 * b + 0.5 * C0)
    assert np.abs(later_on_top - wrong_order).max() > 0.1  # the order is visible
    np.testing.assert_allclose(canvas.colour[5, 5], later_on_top, atol=1e-5)
    # the other pixels: only one contribution each
    np.testing.assert_allclose(canvas.colour[5, 4], 0.5 * b + 0.5 * C0, atol=1e-5)   # stamp 0, bristle B
    np.testing.assert_allclose(canvas.colour[5, 6], 0.6 * a + 0.4 * C0, atol=1e-5)   # stamp 1, bristle A
    assert canvas.coverage[5, 5] == pytest.approx(1 - 0.4 * 0.5, abs=1e-5)
    # deposit: the contact of every bristle that passed over the pixel (one row)
    assert fp.deposit[fp.pixel == 5 * 11 + 5][0] == pytest.approx(0.6 + 0.5, abs=1e-5)


def test_relief_rule_by_hand():
    # a hand-made footprint over old paint H = 0.4, A = 0.5: a = 1 - T, f = min(1, deposit / deposit_90);
    # over: H + a (h - f H); accumulate (b = 0.5): H + a (h - f (1 - b) H)
    fp = box_footprint(0, 0, np.full((2, 5), 0.1, np.float32), np.zeros((2, 5, 3), np.float32),
                       np.array([1, 1, 1, 1, 1, 1, 1, 1, 1, 0.25], np.float32).reshape(2, 5),
                       np.array([1.2, 1, 1, 1, 1, 1, 1, 1, 1, 0.25], np.float32).reshape(2, 5), 5)
    for mode, loss in (("over", 1.0), ("accumulate", 0.5)):
        canvas = Canvas.blank((2, 5), C0)
        canvas.height[...] = 0.4
        canvas.opacity[...] = 0.5
        canvas.lay(fp, mode, 0.5)
        h = canvas.height.reshape(-1)
        assert h[0] == pytest.approx(0.4 + 0.9 * 1.2 - 0.9 * loss * 0.4, abs=1e-6)       # f = 1, a ridge
        assert h[5] == pytest.approx(0.4 + 0.9 * 1.0 - 0.9 * loss * 0.4, abs=1e-6)
        assert h[9] == pytest.approx(0.4 + 0.9 * (0.25 - 0.25 * loss * 0.4), abs=1e-6)  # f = 0.25: a thin end
        o = 0.9 * 0.25
        assert h[9] >= 0.4                                                               # lies on the old paint
        assert canvas.opacity.reshape(-1)[9] == pytest.approx(o + (1 - o) * 0.5, abs=1e-6)


# ---------------------------------------------------------------------------
# 2. One stroke: streaks of bristle colours, coverage


PALETTE = np.array([[0.8, 0.1, 0.1], [0.1, 0.6, 0.1], [0.1, 0.1, 0.8], [0.2, 0.2, 0.2]], np.float32)


def paint_one(reference, orientation, anchor, size, brush_map, params=None, canvas=None, seed=0):
    params = params or Params()
    canvas = canvas or Canvas.blank(reference.shape[:2], params.canvas_colour)
    tip = brush_tip(brush_map, size, params.transparency)
    sources = colour_sources(reference, [size], params)[size]
    stroke = engine_one(canvas, sources, orientation, anchor, size, tip, params, seed)
    return canvas, stroke, tip


def exact_sources(reference, deviation=None):
    """ColourSources that read the reference itself (no smoothing)."""
    exact = smooth(reference, 0.0)
    return ColourSources(reference, exact, exact, exact, deviation)


def test_stroke_streaks_and_coverage(flat):
    h, w, size = 80, 200, 32
    ref = stripes_reference(h, w, PALETTE, 4)
    ori = np.zeros((h, w), np.float32)
    # bristles read the reference itself and may stray from the anchor colour as far as Eq. 5 takes them
    params = Params(bristle_deviation=10.0)
    canvas = Canvas.blank((h, w), params.canvas_colour)
    tip = brush_tip(flat, size, params.transparency)
    stroke = engine_one(canvas, exact_sources(ref), ori, (100, 40), size, tip, params)
    # the stroke runs horizontally, well beyond one brush length
    assert stroke.path[:, 0].min() < 100 - size and stroke.path[:, 0].max() > 100 + size
    np.testing.assert_allclose(stroke.path[:, 1], 40, atol=1e-3)

    half = int(0.35 * size)
    band = canvas.colour[40 - half:40 + half + 1, 100 - size:100 + size].astype(np.float64)
    # several distinct bristle colours across the stroke: nearest palette colour of each row
    cut = band[:, band.shape[1] // 2]
    labels = np.argmin(((cut[:, None, :] - PALETTE[None, :, :]) ** 2).sum(axis=2), axis=1)
    assert len(set(labels.tolist())) >= 3
    assert np.linalg.norm(cut.max(axis=0) - cut.min(axis=0)) > 0.3
    # streaks: colour nearly constant along each row, varying across the stroke
    along_std = band.std(axis=1).mean()
    across_std = band.std(axis=0).mean()
    assert along_std < 0.02
    assert across_std > 5 * along_std
    # coverage near 1 under the stroke's central band
    assert canvas.coverage[40 - half:40 + half + 1, 100 - size:100 + size].min() >= 0.9
    # and 0 far away
    assert np.all(canvas.coverage[:40 - size, :] == 0) and np.all(canvas.coverage[40 + size:, :] == 0)


def test_single_stamp_stroke_eq5_and_coverage_by_hand():
    # max_length = 1: the path is the anchor alone, so one stamp; orientation pi/2 (stroke runs down):
    # bristle (along a, across c) lands at (x - c, y + a) (d = (0, 1), n = (-1, 0)), on whole pixels.
    h, w = 20, 20
    rng = np.random.default_rng(3)
    ref = rng.uniform(0.0, 1.0, (h, w, 3)).astype(np.float32)
    ori = np.full((h, w), np.pi / 2, np.float32)
    tip = make_tip([(0.0, 0.0, 0.7), (2.0, 0.0, 0.5), (0.0, 3.0, 0.25)])     # 3 rows long
    params = Params(max_length=1, perturbation=0.0, bristle_alpha=0.7, bristle_deviation=10.0)
    canvas = Canvas.blank((h, w), C0)
    ax, ay = 9, 8
    sources = exact_sources(ref)
    stroke = engine_one(canvas, sources, ori, (ax, ay), 3, tip, params)
    assert stroke.anchor == (ax, ay)
    pixels = [(ax, ay, 0.7), (ax, ay + 2, 0.5), (ax - 3, ay, 0.25)]
    anchor_rgb = ref[ay, ax].astype(np.float64)
    passes = 4.0 / 3.0                   # a 3-row tip covers as a 4-row one (MIN_ROWS)
    for x, y, i in pixels:
        c_b = 0.7 * ref[y, x] + 0.3 * anchor_rgb                      # Eq. 5, no perturbation
        a = 1 - (1 - i) ** passes
        np.testing.assert_allclose(canvas.colour[y, x], a * c_b + (1 - a) * C0, atol=1e-5)   # Eq. 4
        assert canvas.coverage[y, x] == pytest.approx(a, abs=1e-5)
    assert np.count_nonzero(canvas.coverage) == 3
    # the same stroke again: coverage = 1 - (1 - a)^2
    engine_one(canvas, sources, ori, (ax, ay), 3, tip, params)
    for x, y, i in pixels:
        assert canvas.coverage[y, x] == pytest.approx(1 - (1 - i) ** (2 * passes), abs=1e-5)


# ---------------------------------------------------------------------------
# 3. height range and zero where no paint fell


def test_stroke_height_range_and_zero_outside(flat):
    h, w = 80, 200
    ref = stripes_reference(h, w, PALETTE, 4)
    ori = np.zeros((h, w), np.float32)
    canvas, _, _ = paint_one(ref, ori, (100, 40), 24, flat, params=Params(height_mode="over"))
    height = canvas.height
    assert height.min() >= 0.0 and height.max() <= 1.0
    untouched = np.all(canvas.colour == np.float32(C0), axis=2) & (canvas.coverage == 0)
    assert untouched.sum() > 0.5 * h * w
    assert np.all(height[untouched] == 0.0)
    assert np.all(height[canvas.coverage == 0] == 0.0)
    assert height[40, 80:120].min() > 0.2  # paint on the path has height


# ---------------------------------------------------------------------------
# 4. opacity as wide as the brush's footprint


@pytest.mark.parametrize("size", [16, 32])
def test_opacity_band_width(flat, size):
    h, w = 90, 220
    ref = np.empty((h, w, 3), np.float32)
    ref[...] = (0.2, 0.3, 0.5)
    ori = np.zeros((h, w), np.float32)
    canvas, stroke, _ = paint_one(ref, ori, (110, 45), size, flat)
    assert stroke.path[:, 0].min() < 110 - size and stroke.path[:, 0].max() > 110 + size
    for x in (105, 110, 115):
        width = int(np.count_nonzero(canvas.opacity[:, x] >= 0.5))
        assert abs(width - size) <= 2, (x, width)
        # and no wider than the paint: opacity only where there is height
        assert np.all(canvas.height[:, x][canvas.opacity[:, x] > 0.05] > 0)


# ---------------------------------------------------------------------------
# 5. the path stops at an edge (rules (a) and (b))


RED = np.array([0.85, 0.1, 0.1], np.float32)
BLUE = np.array([0.05, 0.05, 0.6], np.float32)


@pytest.mark.parametrize("size", [16, 32])
@pytest.mark.parametrize("case", ["control", "colour", "turn"])
def test_stroke_stops_by_colour_and_orientation_at_control_points(flat, size, case):
    # rules (a) and (b), checked at control points once the stroke has its minimum length
    # (5 control points: 2 each side of the anchor). The anchor sits 2.5 radii left of x = edge, so the
    # forward side reaches its minimum (2 radii) before the edge; its next control point (3 radii) is past
    # the edge: that point fails the test, is kept, and the rest is dropped.
    h, w = 80, 320
    edge = 160
    step = size / 2
    ref = np.empty((h, w, 3), np.float32)
    ref[...] = RED
    ori = np.zeros((h, w), np.float32)
    canvas = Canvas.blank((h, w), CANVAS_COLOUR)
    if case == "colour":
        canvas.colour[:, edge:] = RED           # rule (a): the canvas already matches there
    elif case == "turn":
        ori[:, edge:] = np.pi / 2               # rule (b): orientation turns by 90 degrees > T_o
    anchor_x = int(edge - 2.5 * step)
    canvas, stroke, tip = paint_one(ref, ori, (anchor_x, 40), size, flat, canvas=canvas)
    end = stroke.path[:, 0].max()
    if case == "control":
        assert end > anchor_x + 5 * step        # without either rule it runs on
    else:
        assert end == pytest.approx(anchor_x + 3 * step, abs=1.0)


@pytest.mark.parametrize("size", [16, 32])
def test_literal_rule_stops_at_the_first_failing_sample(flat, size):
    # path_rule 'literal': rule (a) at every curve sample from the anchor, no minimum length
    h, w, edge = 80, 200, 100
    ref = np.empty((h, w, 3), np.float32)
    ref[...] = RED
    ori = np.zeros((h, w), np.float32)
    canvas = Canvas.blank((h, w), CANVAS_COLOUR)
    canvas.colour[:, edge:] = RED
    canvas, stroke, tip = paint_one(ref, ori, (edge - 4, 40), size, flat, params=Params(path_rule="literal"),
                                    canvas=canvas)
    assert stroke.path[:, 0].max() < edge
    assert stroke.path[:, 0].min() < edge - size


# ---------------------------------------------------------------------------
# 6. layout: p_min first, p_max only when coverage is satisfied


def layout_arrays():
    h, w = 10, 12
    coverage = np.full((h, w), 0.9, np.float32)
    reference = np.full((h, w, 3), 0.5, np.float32)
    colour = reference.copy()
    # outside the grid: worse values that must be ignored
    coverage[0, 0] = 0.0
    colour[9, 11] = (0.0, 0.0, 0.0)
    return coverage, colour, reference


GRID = (2, 1, 9, 7)  # x0, y0, x1, y1 (half-open)


def choose_anchor(grid, coverage, colour, reference, tc, td, tie=0.0):
    """The anchor (x, y) ``choose_anchors`` gives one grid, or None."""
    anchors, chosen, _ = choose_anchors(np.array([grid]), coverage, colour, smooth(reference, 0.0), tc, td,
                                     np.array([tie]))
    return tuple(anchors[0].tolist()) if chosen[0] else None


def test_choose_anchor_prefers_least_covered():
    coverage, colour, reference = layout_arrays()
    coverage[3, 5] = 0.3                        # p_min at x=5, y=3
    coverage[5, 7] = 0.45                       # also below T_c, but not the least
    colour[4, 6] = (1.0, 0.0, 0.0)              # large colour difference elsewhere
    assert choose_anchor(GRID, coverage, colour, reference, 0.5, 0.1) == (5, 3)


def test_choose_anchor_p_max_when_covered():
    coverage, colour, reference = layout_arrays()
    coverage[3, 5] = 0.5                        # min coverage == T_c: satisfied (not < T_c)
    colour[4, 6] = (0.5, 0.5, 0.8)              # distance 0.3
    colour[2, 3] = (0.5, 0.7, 0.5)              # distance 0.2
    assert choose_anchor(GRID, coverage, colour, reference, 0.5, 0.1) == (6, 4)


def test_choose_anchor_breaks_ties_by_the_visit_draw():
    # a grid all at coverage 0: every pixel ties; tied pixel floor(u k) of k in row-major order
    coverage = np.zeros((40, 40), np.float32)
    colour = reference = np.full((40, 40, 3), 0.5, np.float32)
    grid = (0, 0, 40, 40)
    assert choose_anchor(grid, coverage, colour, reference, 0.5, 0.1, 0.0) == (0, 0)
    assert choose_anchor(grid, coverage, colour, reference, 0.5, 0.1, 0.5) == (0, 20)
    assert choose_anchor(grid, coverage, colour, reference, 0.5, 0.1, 0.999999) == (39, 39)
    assert choose_anchor(grid, coverage, colour, reference, 0.5, 0.1, 0.5 + 7.5 / 1600) == (7, 20)


def test_choose_anchor_none_when_satisfied():
    coverage, colour, reference = layout_arrays()
    colour[4, 6] = (0.55, 0.55, 0.5)            # distance 0.0707 < 0.1
    assert choose_anchor(GRID, coverage, colour, reference, 0.5, 0.1) is None
    colour[4, 6] = (0.65, 0.5, 0.5)             # 0.15 > 0.1
    assert choose_anchor(GRID, coverage, colour, reference, 0.5, 0.1) == (6, 4)


def test_choose_anchors_of_many_grids_equal_each_grid_alone():
    # grids of all kinds in one call (bare, covered and missing colour, satisfied) give what each gives alone
    rng = np.random.default_rng(7)
    coverage = rng.choice([0.0, 0.2, 0.6, 0.9], size=(30, 40)).astype(np.float32)
    colour = rng.uniform(0, 1, (30, 40, 3)).astype(np.float32)
    reference = np.clip(colour + rng.normal(0, 0.06, colour.shape), 0, 1).astype(np.float32)
    coverage[0:10, 0:10] = 0.7                                  # covered: p_max decides
    coverage[10:20, 20:30] = 0.8
    reference[10:20, 20:30] = colour[10:20, 20:30]              # covered and satisfied: no stroke
    grids = np.array([[x, y, x + 10, y + 10] for y in (0, 10, 20) for x in (0, 10, 20, 30)])
    ties = rng.uniform(size=len(grids))
    anchors, chosen, _ = choose_anchors(grids, coverage, colour, smooth(reference, 0.0), 0.5, 0.1, ties)
    alone = [choose_anchor(tuple(g), coverage, colour, reference, 0.5, 0.1, u) for g, u in zip(grids, ties, strict=True)]
    assert [tuple(a) if c else None for a, c in zip(anchors.tolist(), chosen, strict=True)] == alone
    assert alone[6] is None and alone[0] is not None


def test_grids_known_to_hold_no_eligible_pixel_are_skipped_with_the_same_anchors():
    """``holding`` (``grids_holding`` of the eligible places) changes nothing but what is looked at: the grids
    without an eligible pixel get no stroke either way, and the others the same anchors."""
    from core.strokes.layout import grids_holding

    rng = np.random.default_rng(3)
    coverage = rng.choice([0.0, 0.3, 0.9], size=(30, 40)).astype(np.float32)
    colour = rng.uniform(0, 1, (30, 40, 3)).astype(np.float32)
    reference = smooth(np.clip(colour + rng.normal(0, 0.2, colour.shape), 0, 1).astype(np.float32), 0.0)
    eligible = np.zeros((30, 40), bool)
    eligible[3, 5] = eligible[25, 38] = eligible[12:14, 21:23] = True
    grids = np.array([[x, y, x + 10, y + 10] for y in (0, 10, 20) for x in (0, 10, 20, 30)])
    holding = grids_holding(grids, eligible)
    assert holding.tolist() == [k in (0, 6, 11) for k in range(12)]
    ties = rng.uniform(size=len(grids))
    looked_at_all = choose_anchors(grids, coverage, colour, reference, 0.5, 0.1, ties, eligible)
    skipped = choose_anchors(grids, coverage, colour, reference, 0.5, 0.1, ties, eligible, holding)
    for every, some in zip(looked_at_all, skipped, strict=True):
        assert np.array_equal(every, some)
    assert looked_at_all.chosen[holding].any() and not looked_at_all.chosen[~holding].any()


# ---------------------------------------------------------------------------
# 7. accumulate vs over


def test_height_modes_over_and_accumulate(flat):
    size = 16
    tip = brush_tip(flat, size, 0.9)
    samples, angles = straight_samples(20, 60, 20)
    colours = np.tile(np.array([[0.3, 0.4, 0.5]], np.float32), (len(tip), 1))
    fp = stroke_footprint(samples, angles, tip.along, tip.across, tip.intensity, colours, (40, 80),
                          rows=tip.length)
    over = Canvas.blank((40, 80), C0)
    over.lay(fp, "over", 0.5)
    h1 = over.height.astype(np.float64).copy()
    over.lay(fp, "over", 0.5)
    touched = fp.deposit > 0
    full = touched & (fp.deposit >= np.percentile(fp.deposit[touched], 90))   # f = 1
    assert full.sum() > 50
    where = np.divmod(fp.pixel[full], 80)
    o = 1 - fp.transmittance[full].astype(np.float64)
    h = fp.height[full].astype(np.float64)
    np.testing.assert_allclose(h1[where], o * h, rtol=1e-5)                    # bare canvas: H = o h
    np.testing.assert_allclose(over.height[where], o * h + (1 - o) * h1[where], rtol=1e-5)   # the weighted sum

    acc = Canvas.blank((40, 80), C0)
    heights = []
    for _ in range(40):
        acc.lay(fp, "accumulate", 0.5)
        heights.append(acc.height[where].astype(np.float64).copy())
    np.testing.assert_allclose(heights[0], h1[where], rtol=1e-5)               # the first coat is the stroke
    assert np.all(heights[1] > heights[0])                                     # paint builds up ...
    np.testing.assert_allclose(heights[-1], heights[-2], rtol=1e-5)            # ... and converges
    np.testing.assert_allclose(heights[-1], h / (1 - 0.5), rtol=1e-4)         # to h / (1 - b)
    # bounded everywhere: H -> h / (f (1 - b)) <= (1 / (1 - b)) max(h, h90 height / deposit)
    h90 = np.percentile(fp.deposit[touched], 90)
    bound = 2.0 * max(fp.height.max(), h90 * np.max(fp.height / np.maximum(fp.deposit, 1e-9)))
    assert acc.height.max() <= bound + 1e-5


# ---------------------------------------------------------------------------
# 8. whole painter: textured areas get smaller, more numerous strokes


def test_textured_half_gets_smaller_strokes():
    h, w = 160, 240
    rng = np.random.default_rng(1)
    img = np.zeros((h, w, 3), np.float32)
    x = np.linspace(0.0, 1.0, w // 2)[None, :]
    y = np.linspace(0.0, 1.0, h)[:, None]
    img[:, :w // 2, 0] = 0.2 + 0.6 * x
    img[:, :w // 2, 1] = 0.3 + 0.4 * y
    img[:, :w // 2, 2] = 0.5
    palette = np.array([[0.9, 0.1, 0.1], [0.1, 0.8, 0.2], [0.1, 0.2, 0.9], [0.95, 0.9, 0.1], [0.1, 0.1, 0.1]],
                       np.float32)
    img[:, w // 2:] = palette[rng.integers(0, len(palette), (h // 4, w // 8))].repeat(4, 0).repeat(4, 1)
    painting = paint(img, Params())
    anchors = np.array([s.anchor for s in painting.strokes])
    sizes = np.array([s.size for s in painting.strokes])
    left = anchors[:, 0] < w // 2
    assert left.sum() > 0 and (~left).sum() > 0
    assert sizes[~left].mean() < sizes[left].mean()
    assert (~left).sum() > left.sum()


# ---------------------------------------------------------------------------
# 9. degenerate images and invalid parameters


def gradient(h, w):
    img = np.zeros((h, w, 3), np.float32)
    img[..., 0] = np.linspace(0, 1, w)[None, :]
    img[..., 1] = np.linspace(0, 1, h)[:, None]
    img[..., 2] = 0.4
    return img


@pytest.mark.parametrize("image", [
    pytest.param(np.full((1, 1, 3), 0.5, np.float32), id="1x1"),
    pytest.param(gradient(10, 1000), id="10x1000"),
    pytest.param(gradient(1000, 10), id="1000x10"),
    pytest.param(np.zeros((64, 48, 3), np.float32), id="black"),
    pytest.param(np.ones((64, 48, 3), np.float32), id="white"),
])
def test_degenerate_images(image):
    painting = paint(image, Params())
    hh, ww = image.shape[:2]
    assert painting.colour.shape == (hh, ww, 3)
    for m in (painting.height, painting.opacity, painting.coverage):
        assert m.shape == (hh, ww)
    for m in (painting.colour, painting.height, painting.opacity, painting.coverage):
        assert np.all(np.isfinite(m))
    assert painting.colour.min() >= 0 and painting.colour.max() <= 1
    assert painting.height.min() >= 0
    assert len(painting.strokes) >= 1
    assert painting.coverage.max() > 0.5     # paint fell


@pytest.mark.parametrize("changes", [
    {"stroke_sizes": ()},
    {"stroke_sizes": (32, -4)},
    {"layers": 0},
    {"bristle_alpha": 1.5},
], ids=["no-sizes", "negative-size", "zero-layers", "alpha"])
def test_invalid_parameters(changes):
    with pytest.raises(ParameterError) as info:
        paint(gradient(16, 16), Params(**changes))
    message = str(info.value)
    assert one_sentence(message) == message and len(message) > 10


def test_bad_brush_files(tmp_path):
    black = tmp_path / "black.png"
    write_png(black, np.zeros((8, 16)))
    garbage = tmp_path / "garbage.png"
    garbage.write_bytes(b"this is not a PNG file at all" * 4)
    for path in (black, garbage):
        with pytest.raises(PaintReliefError) as info:
            paint(gradient(16, 16), Params(brush=str(path)))
        assert type(info.value) is not PaintReliefError
        message = str(info.value)
        assert one_sentence(message) == message and len(message) > 10
    # control: a good brush file paints
    good = tmp_path / "good.png"
    write_png(good, np.full((6, 18), 0.8))
    assert len(paint(gradient(16, 16), Params(brush=str(good))).strokes) > 0


# ---------------------------------------------------------------------------
# 10. determinism


def test_determinism():
    rng = np.random.default_rng(5)
    img = gradient(64, 96)
    img[20:44, 30:70] = rng.uniform(0, 1, (24, 40, 3)).astype(np.float32)
    a = paint(img, Params(seed=7))
    b = paint(img, Params(seed=7))
    for name in ("colour", "height", "opacity", "coverage"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert len(a.strokes) == len(b.strokes) > 0
    for s, t in zip(a.strokes, b.strokes, strict=True):
        assert s.to_dict() == t.to_dict()
        np.testing.assert_array_equal(s.path, t.path)
    c = paint(img, Params(seed=8))
    assert not np.array_equal(a.colour, c.colour)


@pytest.mark.parametrize("method", ["huang11", "hertzmann98"])
def test_the_painter_reads_its_input_and_never_writes_it(method):
    """The painter works on the caller's array itself when it is float32 in [0, 1] (no copy of the
    photo is held), so it must leave that array as it was; an image out of range is painted as its
    clipped copy, and the caller's array is still left as it was."""
    rng = np.random.default_rng(2)
    img = gradient(48, 64)
    img[10:30, 20:50] = rng.uniform(0, 1, (20, 30, 3)).astype(np.float32)
    before = img.copy()
    painted = paint(img, Params(seed=3, method=method))
    np.testing.assert_array_equal(img, before)
    wide = img * np.float32(1.5) - np.float32(0.25)              # some values below 0 and above 1
    wide_before = wide.copy()
    stretched = paint(wide, Params(seed=3, method=method))
    np.testing.assert_array_equal(wide, wide_before)
    clipped = paint(np.clip(wide, 0, 1), Params(seed=3, method=method))
    np.testing.assert_array_equal(stretched.colour, clipped.colour)
    assert not np.array_equal(stretched.colour, painted.colour)


# ---------------------------------------------------------------------------
# 11. bundled samples


@pytest.mark.parametrize("name", ["coffee", "chelsea"])
def test_bundled_samples_psnr(name):
    image = read_image(ROOT / "sample_scenes" / f"{name}.png")
    painting = paint(image, Params())
    assert painting.statistics["psnr_db"] >= 20
    assert math.isfinite(painting.statistics["psnr_db"])


def test_grids_are_visited_largest_first_one_run_per_size():
    from core.strokes.layout import painting_order, size_runs

    grids = np.array([[0, 0, 2, 2], [2, 0, 10, 8], [0, 2, 2, 8], [10, 0, 12, 2], [12, 0, 15, 2]], dtype=np.int32)
    sizes = np.array([4, 16, 8, 4, 8])
    # by stroke size, then area (4, 64, 12, 4, 6), ties in partition order
    order = painting_order(grids, sizes)
    assert order.tolist() == [1, 2, 4, 0, 3]
    assert size_runs(sizes[order]) == [(16, 0, 1), (8, 1, 3), (4, 3, 5)]


def test_a_repeated_stamp_folds_like_that_many_identical_stamps():
    # the engine's footprints (``track_footprints``): a stamp of one bristle of contact 0.6 standing for three
    # passes (as a round counts a short brush's rows) lays what three such stamps fold to by Eq. 4
    tip = BrushTip(np.zeros(1, np.float32), np.zeros(1, np.float32), np.array([0.6], np.float32), 1.0, 1.0)
    colour = np.array([0.2, 0.4, 0.8], np.float32)
    once, thrice = (track_footprints(np.array([[5.0, 5.0]]), np.zeros(1), np.array([0, 1]), tip,
                                     colour[None, None], (10, 10), passes=passes) for passes in (1, 3))
    assert once.pixel.tolist() == thrice.pixel.tolist() == [5 * 10 + 5]
    np.testing.assert_allclose(once.transmittance, 0.4, rtol=1e-5)
    np.testing.assert_allclose(thrice.transmittance, 0.4 ** 3, rtol=1e-5)
    np.testing.assert_allclose(thrice.paint, colour[None] * (1 - 0.4 ** 3), rtol=1e-5)
    np.testing.assert_allclose(thrice.deposit, once.deposit)      # the passes fold the colour, not the paint's depth
    canvas, by_hand = Canvas.blank((10, 10), (0.9, 0.5, 0.1)), np.array([0.9, 0.5, 0.1])
    canvas.lay(thrice, "over", 0.5)
    for _ in range(3):
        by_hand = 0.6 * colour + 0.4 * by_hand                    # C <- a C_b + (1 - a) C
    np.testing.assert_allclose(canvas.colour[5, 5], by_hand, rtol=1e-5)


@pytest.mark.parametrize("mode", ["over", "accumulate"])
def test_two_strokes_side_by_side_leave_no_groove_between_them(flat, mode):
    # two parallel strokes one brush width apart: where their feathered edges meet the paint is still
    # at least half as thick as around it (no crack pixel: height < 0.5 x its 7 x 7 median)
    size = 8
    tip = brush_tip(flat, size, 0.9)
    colours = np.tile(np.array([[0.3, 0.4, 0.5]], np.float32), (len(tip), 1))
    canvas = Canvas.blank((48, 80), C0)
    for y in (20, 20 + size):
        samples, angles = straight_samples(16, 64, y)
        canvas.lay(stroke_footprint(samples, angles, tip.along, tip.across, tip.intensity, colours, (48, 80),
                                    rows=tip.length), mode, 0.5)
    between = canvas.height[20:29, 24:56]
    median = ndimage.median_filter(canvas.height, size=7)[20:29, 24:56]
    assert np.all(between >= 0.5 * median), (between.min(axis=1), median.min(axis=1))
