"""A painting's stroke list lays the painting again (ALGORITHM §9: each frame's maps are a function of its strokes).

``huang11.paint(..., record_strokes=True)`` hands back the laid strokes as a
``StrokeList``; laying it on a blank canvas with ``lay_strokes`` must give the
painting's colour, height, opacity and coverage to the byte, over random small
photos, stroke sizes, brushes, height modes, layouts, path rules, renderers
and the detail pass. Laid in another order it gives another painting, so the
equality is not vacuous. Subsets and joins keep the order; a stroke list moved
by whole pixels lays the painting moved (the first property of carrying
strokes from frame to frame); a stroke's contact factor fades it.
"""

import dataclasses

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from oracles import MAPS, map_bytes, same_maps
from test_rounds import PAINTINGS, photo

from core.methods import huang11
from core.params import Params
from core.strokes.canvas import Canvas
from core.strokes.path import catmull_rom
from core.strokes.planning import samples_per_segment
from core.strokes.rounds import strokes_footprints
from core.strokes.stroke_list import (
    LAYING_SHARE,
    ROUND_BRUSH,
    StrokeList,
    lay_strokes,
    laying_bands,
    reaching_rows,
    stroke_tips,
)


def laid(strokes: StrokeList, shape: tuple, params: Params) -> Canvas:
    """The canvas of ``shape`` (H, W) with ``strokes`` laid on it, colour clipped to [0, 1] as a painting's is."""
    canvas = Canvas.blank(shape, params.canvas_colour)
    lay_strokes(canvas, strokes, stroke_tips(strokes, params), params)
    np.clip(canvas.colour, 0.0, 1.0, out=canvas.colour)
    return canvas


def same_lists(a: StrokeList, b: StrokeList) -> bool:
    return all(np.array_equal(getattr(a, f.name), getattr(b, f.name), equal_nan=f.name == "control")
               for f in dataclasses.fields(StrokeList))


def recorded(image: np.ndarray, params: Params):
    """The painting of ``image`` with its stroke list."""
    painting = huang11.paint(image, params, record_strokes=True)
    assert isinstance(painting.stroke_list, StrokeList)
    return painting


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(**PAINTINGS, renderer=st.sampled_from(["bristles", "bristles", "bristles", "lines"]))
def test_laying_a_paintings_stroke_list_on_a_blank_canvas_gives_the_painting(seed, h, w, kind, sizes, brush,
                                                                             height_mode, layout, path_rule,
                                                                             renderer, detail_pass, layers):
    image = photo(seed % 1000, h, w, kind)
    params = Params(seed=seed, stroke_sizes=sizes, brush=brush, height_mode=height_mode, layout=layout,
                    path_rule=path_rule, renderer=renderer, detail_pass=detail_pass, layers=layers,
                    size_reference_megapixels=0.003)
    painting = recorded(image, params)
    strokes = painting.stroke_list
    # one entry per stroke record, in the records' order
    assert len(strokes) == len(painting.strokes)
    assert strokes.layer.tolist() == [s.layer for s in painting.strokes]
    assert strokes.size.tolist() == [s.size for s in painting.strokes]
    assert [tuple(a) for a in strokes.anchor.astype(int).tolist()] == [s.anchor for s in painting.strokes]
    assert strokes.anchor_colour.tobytes() == np.array([s.colour for s in painting.strokes], np.float32).tobytes()
    assert (strokes.brush == ROUND_BRUSH).sum() == (painting.statistics["strokes_per_layer"][-1] if detail_pass else 0)
    assert (strokes.contact == 1).all()
    same_maps(laid(strokes, (h, w), params), painting)


def test_recording_the_strokes_changes_nothing_the_painter_hands_back():
    image = photo(7, 44, 52, "blocks")
    params = Params(seed=3, stroke_sizes=(16, 8, 4), layers=2, detail_pass=True, size_reference_megapixels=0.0023)
    plain, recording = huang11.paint(image, params), recorded(image, params)
    assert plain.stroke_list is None
    same_maps(plain, recording)
    assert [s.to_dict() for s in plain.strokes] == [s.to_dict() for s in recording.strokes]
    times = lambda statistics: {k: v for k, v in statistics.items() if "seconds" not in k}  # noqa: E731
    assert times(plain.statistics) == times(recording.statistics)


@pytest.fixture(scope="module")
def painting():
    """A painting of overlapping strokes of three sizes, two layers and the detail pass (dabs of the round brush
    on six small highlights), with its stroke list."""
    image = photo(5, 60, 72, "smooth")
    for y, x in ((10, 12), (30, 40), (45, 20), (20, 60), (50, 55), (8, 35)):
        image[y:y + 2, x:x + 2] = 1.0
    params = Params(seed=1, stroke_sizes=(12, 6, 3), layers=2, detail_pass=True, brush="flat",
                    size_reference_megapixels=0.0043)
    return recorded(image, params)


def test_the_same_strokes_laid_in_another_order_give_another_painting(painting):
    strokes, params, shape = painting.stroke_list, painting.params, painting.height.shape
    same_maps(laid(strokes, shape, params), painting)
    backwards = laid(strokes.subset(np.arange(len(strokes))[::-1]), shape, params)
    for name in MAPS:
        assert getattr(backwards, name).tobytes() != getattr(painting, name).tobytes(), name
    # two strokes that overlap swapped (the last such pair): the maps change, and only where both lie
    alone = [laid(strokes.subset([i]), shape, params).coverage > 0 for i in range(len(strokes))]
    i = max(i for i in range(len(strokes) - 1) if (alone[i] & alone[i + 1]).any())
    swapped = laid(strokes.subset(np.r_[0:i, i + 1, i, i + 2:len(strokes)]), shape, params)
    changed = np.any(swapped.colour != painting.colour, axis=-1)
    for name in ("height", "opacity", "coverage"):
        changed |= getattr(swapped, name) != getattr(painting, name)
    assert changed.any() and not (changed & ~(alone[i] & alone[i + 1])).any()


def test_subsets_and_joins_keep_the_order(painting):
    strokes, params, shape = painting.stroke_list, painting.params, painting.height.shape
    n = len(strokes)
    assert (strokes.brush == ROUND_BRUSH).sum() == 6
    assert len(set(strokes.control_count.tolist())) > 1                  # the dabs' one control point is padded
    assert len(set(np.diff(strokes.bristle_starts).tolist())) > 1         # bristles of several brush tips
    for cut in (0, 1, n // 3, n - 1, n):
        assert same_lists(StrokeList.joined([strokes.subset(slice(0, cut)), strokes.subset(slice(cut, n))]), strokes)
    picked = np.random.default_rng(0).random(n) < 0.5
    assert same_lists(strokes.subset(picked), strokes.subset(np.flatnonzero(picked)))
    assert same_lists(StrokeList.joined([strokes.subset(~picked)]), strokes.subset(np.flatnonzero(~picked)))
    assert same_lists(StrokeList.joined([]), StrokeList.empty()) and len(StrokeList.empty()) == 0
    # laying the two halves one after another is laying the whole
    canvas = Canvas.blank(shape, params.canvas_colour)
    tips = stroke_tips(strokes, params)
    for part in (strokes.subset(slice(0, n // 2)), strokes.subset(slice(n // 2, n))):
        lay_strokes(canvas, part, tips, params)
    np.clip(canvas.colour, 0.0, 1.0, out=canvas.colour)
    same_maps(canvas, painting)


def strokes_inside(strokes: StrokeList, tips: dict, shape: tuple) -> np.ndarray:
    """(N,) bool: the strokes whose brush stays on an (H, W) canvas all along their kept curve."""
    h, w = shape
    inside = np.zeros(len(strokes), bool)
    for i in range(len(strokes)):
        tip = tips[int(strokes.brush[i]), int(strokes.size[i])]
        reach = float(np.hypot(tip.along, tip.across).max()) + 2.0                 # the brush and its splat
        control = strokes.control[i:i + 1, :int(strokes.control_count[i])]
        curve = catmull_rom(control, samples_per_segment(int(strokes.size[i])))[0, strokes.first[i]:strokes.last[i] + 1]
        inside[i] = (curve.min() >= reach and curve[:, 0].max() <= w - 1 - reach
                     and curve[:, 1].max() <= h - 1 - reach)
    return inside


def test_strokes_moved_by_whole_pixels_lay_the_painting_moved(painting):
    # the strokes that stay on the canvas, laid on it and moved onto a larger one. Stroke positions are rounded
    # to float32 where they are splatted, so a moved stroke lays the same to about 1e-5, not to the byte.
    strokes, params, shape = painting.stroke_list, painting.params, painting.height.shape
    tips = stroke_tips(strokes, params)
    inside = strokes.subset(strokes_inside(strokes, tips, shape))
    assert len(inside) >= 20 and len(set(inside.size.tolist())) == 3
    here = laid(inside, shape, params)
    bare = Canvas.blank((1, 1), params.canvas_colour)
    for dx, dy in ((5, 3), (0, 17), (64, 40)):
        moved = dataclasses.replace(inside, anchor=inside.anchor + (dx, dy), control=inside.control + (dx, dy))
        there = laid(moved, (shape[0] + dy, shape[1] + dx), params)
        for name in MAPS:
            np.testing.assert_allclose(getattr(there, name)[dy:, dx:], getattr(here, name), rtol=0, atol=5e-5,
                                       err_msg=name)
            canvas = getattr(bare, name)[0, 0]                           # the margin the strokes left is bare
            assert (getattr(there, name)[:dy] == canvas).all() and (getattr(there, name)[:, :dx] == canvas).all()


def test_a_strokes_contact_factor_fades_it(painting):
    strokes, params, shape = painting.stroke_list, painting.params, painting.height.shape
    # a factor of 1 given explicitly is multiplied in and changes no byte of any stroke's footprints
    tips = stroke_tips(strokes, params)
    for first, stop in strokes.runs():
        plan = strokes.round_plan(first, stop)
        assert plan.contact is None
        size, tip = int(strokes.size[first]), tips[int(strokes.brush[first]), int(strokes.size[first])]
        full = strokes_footprints(plan, size, tip, params, shape)
        plan.contact = np.ones(stop - first, np.float32)
        ones = strokes_footprints(plan, size, tip, params, shape)
        for field in dataclasses.fields(full):
            assert getattr(full, field.name).tobytes() == getattr(ones, field.name).tobytes(), field.name
    # one stroke alone at contact 0, 1/3, 2/3 and 1: nothing, then more and more of it (a solid line's opacity)
    one = strokes.subset([0])
    for renderer in ("bristles", "lines"):
        drawn = dataclasses.replace(params, renderer=renderer)
        faded = [laid(dataclasses.replace(one, contact=np.array([k / 3], np.float32)), shape, drawn)
                 for k in range(4)]
        same_maps(faded[0], Canvas.blank(shape, params.canvas_colour))
        same_maps(faded[3], laid(one, shape, drawn))
        for name in ("opacity", "coverage", "height"):
            totals = [float(getattr(canvas, name).sum()) for canvas in faded]
            assert totals[0] == 0 < totals[1] < totals[2] < totals[3], (renderer, name)
    # the whole painting with the last layer's strokes half faded differs only where they lie
    last = strokes.layer == strokes.layer.max()
    half = laid(dataclasses.replace(strokes, contact=np.where(last, 0.5, 1.0).astype(np.float32)), shape, params)
    assert map_bytes(half) != map_bytes(painting)
    same_maps(laid(strokes.subset(~last), shape, params),
              laid(dataclasses.replace(strokes, contact=np.where(last, 0.0, 1.0).astype(np.float32)), shape, params))


def test_a_fading_stroke_over_thick_paint_moves_the_relief_part_way_and_digs_no_dip(painting):
    """Over paint twice as thick as a stroke, a stroke at full contact lays its own height (about 1), a stroke at
    contact c moves the height only about c of the way down to it: a fading stroke is a thinner coat, not a hole."""
    strokes, params, shape = painting.stroke_list, painting.params, painting.height.shape
    one = strokes.subset([int(np.argmax(strokes.size))])
    tips = stroke_tips(one, params)

    def over_thick(contact: float) -> Canvas:
        canvas = Canvas.blank(shape, params.canvas_colour)
        canvas.height[...] = 2.0
        lay_strokes(canvas, dataclasses.replace(one, contact=np.array([contact], np.float32)), tips, params)
        return canvas

    full = over_thick(1.0)
    body = full.opacity > 0.95                               # where the stroke at full contact covers fully
    assert body.sum() > 20 and full.height[body].max() < 1.6
    for contact in (1 / 3, 2 / 3):
        lowered = 2.0 - over_thick(contact).height[body]
        assert lowered.max() <= contact * (2.0 - full.height[body].min()) + 0.05, contact
        assert lowered.mean() > 0.5 * contact * (2.0 - full.height[body].mean()), contact


def band_work(strokes: StrokeList, height: int, first: int, stop: int) -> float:
    """The work ``laying_bands`` gives rows first .. stop - 1, worked out stroke by stroke with ``reaching_rows``."""
    steps = np.linalg.norm(np.diff(strokes.control, axis=1), axis=2)
    work = (np.nansum(steps, axis=1) + strokes.size) * strokes.size
    reaching = work[reaching_rows(strokes, first, stop)].sum()
    return (1 - LAYING_SHARE) * reaching + LAYING_SHARE * work.sum() * (stop - first) / height


@pytest.mark.parametrize("crowded", [False, True])
def test_laying_bands_tile_the_rows_and_lay_no_more_in_their_largest_than_equal_bands_do(crowded):
    image = photo(4, 96, 128, "blocks")
    params = Params(seed=4, stroke_sizes=(32, 16, 8, 4), size_reference_megapixels=0.012)
    strokes = recorded(image, params).stroke_list
    h = image.shape[0]
    if crowded:                                               # strokes reaching into the top quarter only
        strokes = strokes.subset(np.nanmin(strokes.control[:, :, 1], axis=1) < h / 4)
        assert 0 < len(strokes) < len(recorded(image, params).stroke_list)
    for parts in (1, 2, 3, 8, 500):
        bands = laying_bands(strokes, h, parts)
        assert bands[0][0] == 0 and bands[-1][1] == h and len(bands) <= min(parts, h)
        assert all(a < b for a, b in bands) and all(b == c for (_, b), (c, _) in zip(bands, bands[1:], strict=False))
        count = min(parts, h)
        equal = [(h * k // count, h * (k + 1) // count) for k in range(count)]
        largest = max(band_work(strokes, h, a, b) for a, b in bands)
        assert largest <= max(band_work(strokes, h, a, b) for a, b in equal) * 1.001
    if crowded:
        assert laying_bands(strokes, h, 4)[0][1] < h / 4       # the crowded top is cut finer than equal rows
