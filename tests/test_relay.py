"""A canvas laid again only where its strokes changed gives the bytes of laying every stroke anew (``strokes.relay``).

The cases change a painting's stroke list as a shot's frame does: some
strokes fade (another contact), some are gone, some are born and laid last
on the canvas but sit earlier in the list's order. The boxes of the changed
strokes go to ``relaid`` with the canvas the old list was laid on; the result
must equal the new list laid on a blank canvas, for every tile size. Given
too few boxes, it does not: the boxes are what is laid again.
"""

import dataclasses

import numpy as np
import pytest
from oracles import MAPS, map_bytes
from test_rounds import photo
from test_stroke_list import laid, recorded

from core import tuning
from core.params import Params
from core.strokes.canvas import Canvas
from core.strokes.relay import relaid, tiles_touched, touching
from core.strokes.stroke_list import StrokeList, lay_strokes, reach_boxes, segment_boxes, stroke_tips


def unclipped(strokes: StrokeList, shape: tuple, params: Params) -> Canvas:
    """``strokes`` laid on a blank (H, W) canvas, colour not clipped (as a judging canvas is)."""
    canvas = Canvas.blank(shape, params.canvas_colour)
    lay_strokes(canvas, strokes, stroke_tips(strokes, params), params)
    return canvas


def changed_list(strokes: StrokeList, seed: int):
    """A frame's change of ``strokes``: (the list laid before, the list now, the indices now that changed)."""
    rng = np.random.default_rng(seed)
    n = len(strokes)
    born = np.zeros(n, bool)
    born[rng.choice(n, max(1, n // 8), replace=False)] = True
    kept = ~born & (rng.random(n) > 0.05)                       # a few gone at once
    fading = kept & (rng.random(n) < 0.1)
    contact = np.where(fading, np.float32(2 / 3), np.float32(1)).astype(np.float32)
    before = strokes.subset(np.concatenate([np.flatnonzero(~born), np.flatnonzero(born)]))  # births laid last
    now = dataclasses.replace(strokes, contact=contact).subset(kept | born)
    changed = np.flatnonzero((fading | born)[kept | born])
    gone = strokes.subset(~kept & ~born)
    return before, now, changed, gone


@pytest.mark.parametrize("most", [1.0, 0.0])        # laid again on the marked tiles whatever their share; anew
@pytest.mark.parametrize("renderer", ["bristles", "lines"])
@pytest.mark.parametrize("tile", [4, 13, 32, 1000])
@pytest.mark.parametrize("seed", [1, 2])
def test_a_canvas_laid_again_where_strokes_changed_is_the_new_list_laid_anew(seed, tile, renderer, most, monkeypatch):
    monkeypatch.setattr(tuning, "RELAY_TILE", tile)
    monkeypatch.setattr(tuning, "RELAY_MOST_MARKED", most)
    image = photo(seed, 70, 90, "blocks")
    params = Params(seed=seed, stroke_sizes=(16, 8, 4), layers=2, detail_pass=True, size_reference_megapixels=0.0063,
                    renderer=renderer)
    strokes = recorded(image, params).stroke_list
    before, now, changed, gone = changed_list(strokes, seed)
    shape = image.shape[:2]
    canvas = unclipped(before, shape, params)
    kept_bytes = map_bytes(canvas)
    boxes = np.concatenate([segment_boxes(now.subset(changed))[0], segment_boxes(gone)[0]])
    result = relaid(canvas, boxes, now, stroke_tips(now, params), params)
    np.clip(result.colour, 0.0, 1.0, out=result.colour)
    assert map_bytes(result) == map_bytes(laid(now, shape, params))
    assert map_bytes(canvas) == kept_bytes                      # the canvas handed in is left as it was
    # one stroke of the first layer laid last: without its boxes the canvas keeps it above the later layers
    moved = np.r_[1:len(strokes), 0]
    last = unclipped(strokes.subset(moved), shape, params)
    tips = stroke_tips(strokes, params)
    assert map_bytes(relaid(last, segment_boxes(strokes.subset([0]))[0], strokes, tips, params)) == \
        map_bytes(unclipped(strokes, shape, params))
    assert map_bytes(relaid(last, np.zeros((0, 4)), strokes, tips, params)) != \
        map_bytes(unclipped(strokes, shape, params))


def test_no_change_lays_nothing_again_and_returns_a_copy():
    image = photo(3, 40, 50, "blocks")
    params = Params(seed=3, stroke_sizes=(12, 6), layers=1, size_reference_megapixels=0.002)
    strokes = recorded(image, params).stroke_list
    canvas = unclipped(strokes, image.shape[:2], params)
    result = relaid(canvas, np.zeros((0, 4)), strokes, stroke_tips(strokes, params), params)
    assert map_bytes(result) == map_bytes(canvas)
    assert all(getattr(result, name) is not getattr(canvas, name) for name in MAPS)


def test_segment_boxes_hold_a_strokes_paint_and_lie_within_its_reach_box():
    image = photo(5, 64, 80, "noise")
    params = Params(seed=5, stroke_sizes=(14, 7), layers=2, detail_pass=True, size_reference_megapixels=0.005)
    strokes = recorded(image, params).stroke_list
    boxes, owner = segment_boxes(strokes)
    whole = reach_boxes(strokes)
    assert np.array_equal(np.unique(owner), np.arange(len(strokes)))
    assert np.all(boxes[:, 0] >= whole[owner, 0]) and np.all(boxes[:, 1] <= whole[owner, 1])
    assert np.all(boxes[:, 2] >= whole[owner, 2]) and np.all(boxes[:, 3] <= whole[owner, 3])
    rows, columns = np.mgrid[0:64, 0:80]
    for i in range(0, len(strokes), 7):
        painted = laid(strokes.subset([i]), image.shape[:2], params).coverage > 0
        mine = boxes[owner == i]
        inside = np.zeros_like(painted)
        for x0, x1, y0, y1 in mine:
            inside |= (columns >= x0) & (columns <= x1) & (rows >= y0) & (rows <= y1)
        assert not np.any(painted & ~inside), i


def test_tiles_touched_and_touching_agree_with_a_pixel_count():
    shape, tile = (50, 70), 8
    rng = np.random.default_rng(4)
    low = rng.uniform(-20, 75, (30, 2))
    boxes = np.stack([low[:, 0], low[:, 0] + rng.uniform(0, 30, 30), low[:, 1], low[:, 1] + rng.uniform(0, 30, 30)],
                     axis=1)
    marked = tiles_touched(boxes[:5], shape, tile)
    expected = np.zeros_like(marked)
    for x0, x1, y0, y1 in boxes[:5]:
        r0, r1 = (int(np.clip(np.floor(v / tile), 0, marked.shape[0] - 1)) for v in (y0, y1))
        c0, c1 = (int(np.clip(np.floor(v / tile), 0, marked.shape[1] - 1)) for v in (x0, x1))
        expected[r0:r1 + 1, c0:c1 + 1] = True
    assert np.array_equal(marked, expected)
    near = touching(marked, boxes, shape, tile)
    assert near[:5].all()
    for k, (x0, x1, y0, y1) in enumerate(boxes):
        r0, r1 = (int(np.clip(np.floor(v / tile), 0, marked.shape[0] - 1)) for v in (y0, y1))
        c0, c1 = (int(np.clip(np.floor(v / tile), 0, marked.shape[1] - 1)) for v in (x0, x1))
        assert near[k] == marked[r0:r1 + 1, c0:c1 + 1].any()
