"""The round engine against its one-at-a-time reference: the same bytes for every map and every stroke.

The reference (``tests/one_by_one.py``) plans each stroke of a round alone
against the canvas as the round began and lays each alone on its whole box;
the engine plans a round's strokes together and lays them pass by pass
(``Canvas.lay``). Random small photos, stroke sizes, brushes, height modes,
layouts, path rules and seeds must give identical colour, height, opacity
and coverage maps and identical stroke records. The reference is built of
the engine's own pieces, so this proves that planning together, runs,
chunks and passes change no byte, not that the bytes are right (the
stamp-by-stamp oracle and the by-hand tests hold the pieces to that).
"""

import numpy as np
import one_by_one
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from oracles import same_maps, same_painting

from core.methods import huang11
from core.params import Params
from core.strokes.canvas import Canvas
from core.strokes.compositing import full_deposits
from core.strokes.streams import visit_uniforms


def photo(seed: int, h: int, w: int, kind: str) -> np.ndarray:
    """A small test photo: smooth gradients with blobs, fine noise, or hard-edged blocks."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:h, 0:w] / max(h, w)
    image = np.stack([0.2 + 0.6 * x, 0.3 + 0.4 * y, 0.5 + 0.3 * np.sin(6 * x * y)], axis=-1)
    if kind == "noise":
        image = image + rng.normal(0, 0.15, image.shape)
    elif kind == "blocks":
        for _ in range(6):
            y0, x0 = rng.integers(0, h - 4), rng.integers(0, w - 4)
            image[y0:y0 + rng.integers(3, h // 2 + 4), x0:x0 + rng.integers(3, w // 2 + 4)] = rng.uniform(0, 1, 3)
    else:
        for _ in range(4):
            cy, cx, r = rng.uniform(0, h), rng.uniform(0, w), rng.uniform(2, 8)
            image[(np.mgrid[0:h, 0:w][0] - cy) ** 2 + (np.mgrid[0:h, 0:w][1] - cx) ** 2 < r * r] = rng.uniform(0, 1, 3)
    return np.clip(image, 0, 1).astype(np.float32)


PAINTINGS = dict(seed=st.integers(0, 2 ** 32 - 1), h=st.integers(12, 56), w=st.integers(12, 56),
                 kind=st.sampled_from(["smooth", "noise", "blocks"]),
                 sizes=st.sampled_from([(64, 32, 16, 8, 4), (24, 6), (9, 5, 3), (40,)]),
                 brush=st.sampled_from(["flat", "round", "filbert"]),
                 height_mode=st.sampled_from(["over", "accumulate"]),
                 layout=st.sampled_from(["paper", "paper", "hertzmann98"]),
                 path_rule=st.sampled_from(["natural", "natural", "literal"]),
                 detail_pass=st.booleans(), layers=st.integers(1, 3))
"""Hypothesis strategies of small random paintings: a ``photo`` (seed, h, w, kind) and the settings that change
how strokes are planned and laid."""


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(**PAINTINGS)
def test_the_engine_paints_the_bytes_of_one_stroke_at_a_time(seed, h, w, kind, sizes, brush, height_mode, layout,
                                                             path_rule, detail_pass, layers):
    image = photo(seed % 1000, h, w, kind)
    params = Params(seed=seed, stroke_sizes=sizes, brush=brush, height_mode=height_mode, layout=layout,
                    path_rule=path_rule, detail_pass=detail_pass, layers=layers, size_reference_megapixels=0.003)
    engine = huang11.paint(image, params)
    reference = one_by_one.paint(image, params)
    same_painting(engine, reference)


def test_a_round_lays_overlapping_strokes_in_order():
    # many long strokes crossing one small canvas, so pixels see several strokes of one round
    image = photo(3, 40, 40, "blocks")
    params = Params(seed=2, stroke_sizes=(12,), layers=2, max_length=16, min_length=5,
                    size_reference_megapixels=0.0016)
    engine = huang11.paint(image, params)
    reference = one_by_one.paint(image, params)
    same_painting(engine, reference)
    assert len(engine.strokes) >= 8


def test_laying_a_round_in_passes_equals_laying_stroke_after_stroke():
    # two strokes over the same pixels: the pass laying keeps their order; swapped, the canvas differs
    from stamp_oracle import box_footprint

    from core.strokes.compositing import Footprints

    red = box_footprint(1, 1, np.full((3, 3), 0.3), np.tile([0.7, 0, 0], (3, 3, 1)), np.full((3, 3), 0.8),
                        np.full((3, 3), 0.8), 6)
    blue = box_footprint(2, 2, np.full((3, 3), 0.5), np.tile([0, 0, 0.5], (3, 3, 1)), np.full((3, 3), 0.6),
                         np.full((3, 3), 0.9), 6)

    def both(first, second):
        starts = np.array([0, len(first.pixel), len(first.pixel) + len(second.pixel)])
        return Footprints(starts, *(np.concatenate([getattr(first, k), getattr(second, k)])
                                    for k in ("pixel", "transmittance", "paint", "deposit", "height", "full")))

    for first, second in ((red, blue), (blue, red)):
        together, apart = Canvas.blank((6, 6), (0.9, 0.9, 0.9)), Canvas.blank((6, 6), (0.9, 0.9, 0.9))
        together.lay(both(first, second), "accumulate", 0.5)
        one_by_one.lay_one(apart, first, 0, "accumulate", 0.5)
        one_by_one.lay_one(apart, second, 0, "accumulate", 0.5)
        same_maps(together, apart)
    # the shared pixel (3, 3) shows the later stroke on top
    canvas = Canvas.blank((6, 6), (0.9, 0.9, 0.9))
    canvas.lay(both(red, blue), "over", 0.5)
    np.testing.assert_allclose(canvas.colour[3, 3], 0.5 * (0.3 * 0.9 + np.array([0.7, 0, 0])) + [0, 0, 0.5],
                               atol=1e-6)
    # strokes left out by ``keep`` are laid as if they were not in the run
    for keep in ([True, False], [False, True], [False, False]):
        kept, alone = Canvas.blank((6, 6), (0.9, 0.9, 0.9)), Canvas.blank((6, 6), (0.9, 0.9, 0.9))
        kept.lay(both(red, blue), "accumulate", 0.5, np.array(keep))
        for footprint, laid in zip((red, blue), keep, strict=True):
            if laid:
                one_by_one.lay_one(alone, footprint, 0, "accumulate", 0.5)
        same_maps(kept, alone)


def test_a_canvas_of_arrays_that_are_not_contiguous_is_refused_rather_than_laid_on_a_copy():
    # laying writes through flat views of the canvas; a strided array would be reshaped into a copy
    from stamp_oracle import box_footprint

    stroke = box_footprint(1, 1, np.full((3, 3), 0.3), np.tile([0.7, 0, 0], (3, 3, 1)), np.full((3, 3), 0.8),
                           np.full((3, 3), 0.8), 6)
    wide = Canvas.blank((6, 12), (0.9, 0.9, 0.9))
    for name in ("colour", "coverage", "height", "opacity"):
        arrays = {key: getattr(wide, key)[:, :6].copy() for key in ("colour", "coverage", "height", "opacity")}
        arrays[name] = getattr(wide, name)[:, ::2]
        with pytest.raises(ValueError, match="C-contiguous"):
            Canvas(**arrays).lay(stroke, "over", 0.5)
    laid = Canvas(**{key: getattr(wide, key)[:, :6].copy() for key in ("colour", "coverage", "height", "opacity")})
    laid.lay(stroke, "over", 0.5)
    assert np.allclose(laid.colour[2, 2], 0.3 * 0.9 + np.array([0.7, 0, 0]))


def test_full_deposits_are_the_90th_percentile_of_each_strokes_positive_deposits():
    # runs of many lengths, so that rows of several widths are sorted from several ranks; some all zero
    rng = np.random.default_rng(4)
    counts = [0, 1, 2, 7, 50, 3, 64, 65, 1000, 257, 5, 64]
    runs = [np.where(rng.uniform(size=c) < 0.2, 0.0, rng.uniform(0.01, 2, c)).astype(np.float32) for c in counts]
    runs[10][:] = 0.0
    starts = np.concatenate(([0], np.cumsum(counts)))
    full = full_deposits(np.concatenate(runs), starts)
    for run, value in zip(runs, full, strict=True):
        positive = run[run > 0]
        expected = np.percentile(positive.astype(np.float64), 90) if positive.size else 0.0
        assert value == np.float32(expected)


def test_every_visit_draws_from_its_own_stream():
    # the same visit gives the same numbers whatever else is drawn with it; seeds, layers and visits differ
    alone = visit_uniforms(5, 2, np.array([7]), 4)
    among = visit_uniforms(5, 2, np.arange(20), 4)
    assert alone.tobytes() == among[7:8].tobytes()
    assert ((among >= 0) & (among < 1)).all()
    assert not np.array_equal(visit_uniforms(6, 2, np.array([7]), 4), alone)
    assert not np.array_equal(visit_uniforms(5, 3, np.array([7]), 4), alone)
    many = visit_uniforms(1, 0, np.arange(20000), 1).ravel()
    assert abs(many.mean() - 0.5) < 0.01 and np.histogram(many, 10, (0, 1))[0].min() > 1800


def test_rounds_planned_and_laid_in_small_chunks_give_the_same_bytes(monkeypatch):
    # memory bounds split a round into chunks of strokes; the painting must not notice
    from core import tuning
    from core.strokes import compositing, rounds

    image = photo(11, 48, 56, "blocks")
    params = Params(seed=4, stroke_sizes=(16, 8, 4), layers=2, size_reference_megapixels=0.0027, detail_pass=True)
    whole = huang11.paint(image, params)
    monkeypatch.setattr(tuning, "PLAN_CHUNK_SAMPLES", 1)
    monkeypatch.setattr(tuning, "LAY_CHUNK_SAMPLES", 200)
    monkeypatch.setattr(tuning, "SPLAT_CHUNK_PIXELS", 50)
    cuts = {}

    def counted(module, name):
        cut = getattr(module, name)
        monkeypatch.setattr(module, name, lambda *args: cuts.setdefault(name, []).append(cut(*args)) or
                            cuts[name][-1])

    counted(rounds, "lay_chunks")
    counted(rounds, "balanced_runs")                                     # plan_round's runs (and in_runs')
    counted(compositing, "bounded_runs")                                 # the splat's chunks
    chunked = huang11.paint(image, params)
    assert all(max(len(runs) for runs in cuts[name]) > 3 for name in ("lay_chunks", "balanced_runs", "bounded_runs"))
    same_painting(whole, chunked)


def one_stroke_plan(reference: np.ndarray, canvas: Canvas, anchor, size: int, params: Params) -> tuple:
    """(The plan of one stroke of ``size`` px anchored at (x, y), colours taken from ``reference``; its tip)."""
    from core.strokes.brush import brush_tip, load_brush
    from core.strokes.rounds import plan_round
    from core.strokes.stroke import colour_sources
    tip = brush_tip(load_brush(params.brush), size, params.transparency)
    orientation = np.zeros(reference.shape[:2], np.float32)
    plan = plan_round(canvas, colour_sources(reference, [size], params)[size], orientation,
                      np.array([anchor]), size, tip, np.full((1, 4), 0.5), params)
    return plan, tip


def mend_and_spoil_by_hand(canvas: Canvas, plan, size: int, tip, params: Params, reference: np.ndarray):
    """Squared error mended and spoiled by one stroke, pixel by pixel in a Python loop."""
    from core.strokes.rounds import strokes_footprints
    fp = strokes_footprints(plan, size, tip, params, canvas.height.shape)
    mended = spoiled = 0.0
    for k in range(fp.starts[0], fp.starts[1]):
        y, x = divmod(int(fp.pixel[k]), canvas.colour.shape[1])
        before = canvas.colour[y, x].astype(np.float64)
        after = before * float(fp.transmittance[k]) + fp.paint[k].astype(np.float64)
        e0 = float(np.sum((before - reference[y, x]) ** 2))
        e1 = float(np.sum((after - reference[y, x]) ** 2))
        mended += max(0.0, e0 - e1)
        spoiled += max(0.0, e1 - e0)
    return mended, spoiled


def test_a_stroke_is_laid_when_it_mends_more_than_twice_what_it_spoils():
    from core.strokes.rounds import improves, strokes_footprints
    params = Params(seed=1)
    h, w, size = 40, 60, 8
    light = np.full((h, w, 3), 0.8, np.float32)
    # a stroke of the reference's colour over a canvas that misses it everywhere only mends
    canvas = Canvas.blank((h, w), (0.2, 0.2, 0.2))
    plan, tip = one_stroke_plan(light, canvas, (30, 20), size, params)
    mended, spoiled = mend_and_spoil_by_hand(canvas, plan, size, tip, params, light)
    assert mended > 0 and spoiled == 0
    assert improves(canvas.colour, strokes_footprints(plan, size, tip, params, (h, w)), light,
                    2.0).tolist() == [True]
    # the same stroke over a canvas that already matches a dark line beside it: a light stroke anchored
    # one row off a two-pixel dark line mends its own row and spoils the line
    line = light.copy()
    line[20:22] = 0.1
    canvas = Canvas.blank((h, w), (0.8, 0.8, 0.8))
    canvas.colour[20:22] = 0.1
    canvas.colour[19] = 0.45                                            # the line's own stroke spilled here
    plan, tip = one_stroke_plan(light, canvas, (30, 19), 2, params)
    mended, spoiled = mend_and_spoil_by_hand(canvas, plan, 2, tip, params, line)
    assert 0 < mended <= 2.0 * spoiled, (mended, spoiled)
    footprints = strokes_footprints(plan, 2, tip, params, (h, w))
    assert improves(canvas.colour, footprints, line, 2.0).tolist() == [False]
    assert improves(canvas.colour, footprints, line, 0.5 * mended / spoiled).tolist() == [True]



def test_improves_judges_some_of_the_strokes_as_it_judges_each_alone():
    from stamp_oracle import box_footprint

    from core.strokes.compositing import Footprints
    from core.strokes.rounds import improves

    rng = np.random.default_rng(7)
    colour, reference = rng.random((8, 8, 3), dtype=np.float32), rng.random((8, 8, 3), dtype=np.float32)
    strokes = [box_footprint(int(rng.integers(0, 5)), int(rng.integers(0, 5)), rng.uniform(0.2, 1, (3, 3)),
                             rng.uniform(0, 0.6, (3, 3, 3)), np.ones((3, 3)), np.ones((3, 3)), 8) for _ in range(5)]
    run = Footprints(np.arange(0, 46, 9), *(np.concatenate([getattr(f, k) for f in strokes])
                                           for k in ("pixel", "transmittance", "paint", "deposit", "height", "full")))
    alone = [bool(improves(colour, f, reference, 1.0)[0]) for f in strokes]
    assert 0 < sum(alone) < 5                                                   # some mend, some do not
    judged = np.array([True, False, True, True, False])
    some = improves(colour, run, reference, np.ones(3), judged)
    assert some.tolist() == [a for a, j in zip(alone, judged, strict=True) if j]
    assert improves(colour, run, reference, 1.0).tolist() == alone

def test_a_later_stroke_over_a_bare_spot_is_refused_when_it_spoils_twice_what_it_mends():
    from core.methods.huang11 import mend_ratios
    from core.strokes.brush import brush_tip, load_brush
    from core.strokes.rounds import paint_round
    from core.strokes.stroke import colour_sources
    assert mend_ratios(np.array([True, False]), 0, 2.0).tolist() == [2.0, 0.0]     # the first layer lays the ground
    assert mend_ratios(np.array([True, False]), 1, 2.0).tolist() == [2.0, 0.5]
    assert mend_ratios(np.array([True, False]), 1, 0.0) is None                   # the paper: no stroke judged
    # a dark sky with a bright galaxy, both painted, and one bare spot left beside the galaxy
    params = Params(seed=1)
    h, w, size = 40, 80, 32
    sky, canvas = galaxy_with_a_bare_spot(h, w)
    plan, tip = one_stroke_plan(sky, canvas, (30, 20), size, params)
    mended, spoiled = mend_and_spoil_by_hand(canvas, plan, size, tip, params, sky)
    assert spoiled > 2.0 * mended > 0, (mended, spoiled)          # it sweeps the sky's dark over the galaxy
    sources = colour_sources(sky, [size], params)[size]
    tip = brush_tip(load_brush(params.brush), size, params.transparency)
    orientation = np.zeros((h, w), np.float32)
    for ratio, laid in ((0.0, 1), (0.5, 0)):
        painted = Canvas(canvas.colour.copy(), canvas.coverage.copy(), canvas.height.copy(), canvas.opacity.copy())
        strokes = paint_round(painted, sources, orientation, np.array([(30, 20)]), size, 1, tip, np.full((1, 4), 0.5),
                              params, ratios=np.array([ratio]))
        assert len(strokes) == laid
        assert (painted.colour[20, 40] == sky[20, 40]).all() == (laid == 0)


def galaxy_with_a_bare_spot(h: int, w: int) -> tuple:
    """A dark sky with a bright galaxy at (40, 20), painted, and one bare spot left at x 29-30, y 19-21:
    (sky (h, w, 3), canvas)."""
    yy, xx = np.mgrid[0:h, 0:w]
    sky = np.full((h, w, 3), 0.05, np.float32)
    sky[(yy - 20) ** 2 + (xx - 40) ** 2 <= 9] = 0.9
    canvas = Canvas.blank((h, w), (0.93, 0.9, 0.84))
    canvas.colour[:] = sky
    canvas.opacity[:] = canvas.coverage[:] = 1.0
    canvas.colour[19:22, 29:31] = (0.93, 0.9, 0.84)
    canvas.opacity[19:22, 29:31] = canvas.coverage[19:22, 29:31] = 0.0
    return sky, canvas


def test_a_bare_spot_refused_to_a_wide_brush_is_covered_by_the_next_smaller_one():
    from core.methods.huang11 import paint_layer
    from core.strokes.brush import brush_tip, load_brush
    from core.strokes.stroke import colour_sources
    params = Params(seed=1)
    h, w = 40, 80
    sky, canvas = galaxy_with_a_bare_spot(h, w)
    sizes = (32, 6)
    grids = np.array([(0, 0, 64, 40), (64, 0, 80, 20), (64, 20, 80, 40)])      # the spot lies in the wide grid
    runs = [(32, 0, 1), (6, 1, 3)]
    sources = colour_sources(sky, sizes, params)
    tips = {s: brush_tip(load_brush(params.brush), s, params.transparency) for s in sizes}
    orientation = np.zeros((h, w), np.float32)
    reports = []
    for layer, ratio, widths in ((1, 2.0, [6]), (0, 2.0, [32]), (1, 0.0, [32])):
        painted = Canvas(canvas.colour.copy(), canvas.coverage.copy(), canvas.height.copy(), canvas.opacity.copy())
        strokes = paint_layer(painted, layer, grids, runs, orientation, tips, sources,
                              Params(seed=1, mend_ratio=ratio), lambda done, count: reports.append((done, count)))
        # later layers: the wide brush would sweep the sky over the galaxy, so the small one covers the spot;
        # the first layer (and the paper, ratio 0) lays the wide one
        assert [s.size for s in strokes] == widths
        assert strokes[0].anchor in {(29, 19), (30, 19), (29, 20), (30, 20), (29, 21), (30, 21)}
        assert painted.opacity[19:22, 29:31].min() >= params.coverage_threshold
        assert (np.abs(painted.colour[20, 40] - sky[20, 40]).max() < 0.1) == (widths == [6])
    assert reports[:2] == [(1, 0), (2, 1)]                                        # progress after each run
