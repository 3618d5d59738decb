"""Tests of core.strokes.brush: shipped brush maps, loading user brushes, brush tips."""

from __future__ import annotations

import numpy as np
import OpenImageIO as oiio
import pytest
from oracles import one_sentence

from core.errors import InputError, PaintReliefError, ParameterError
from core.strokes.brush import (
    SHIPPED_BRUSHES,
    BrushTip,
    brush_tip,
    crop_to_bristles,
    load_brush,
    procedural_brush,
    resize_map,
    tip_cache,
    tip_length,
)


def write_png(path, pixels: np.ndarray) -> None:
    """Write float (H, W) or (H, W, C) values in [0, 1] as an 8-bit PNG with OpenImageIO."""
    data = np.asarray(pixels, dtype=np.float64)
    if data.ndim == 2:
        data = data[:, :, None]
    quantised = np.ascontiguousarray(np.clip(np.round(data * 255), 0, 255).astype(np.uint8))
    spec = oiio.ImageSpec(data.shape[1], data.shape[0], data.shape[2], "uint8")
    out = oiio.ImageOutput.create(str(path))
    assert out is not None and out.open(str(path), spec), oiio.geterror()
    assert out.write_image(quantised)
    out.close()


# ---------------------------------------------------------------------------
# shipped brushes


@pytest.mark.parametrize("name", SHIPPED_BRUSHES)
def test_shipped_brush_range_and_type(name):
    m = procedural_brush(name)
    assert m.dtype == np.float32 and m.ndim == 2
    assert m.min() >= 0.0 and m.max() <= 1.0
    assert m.max() == 1.0
    assert np.all(np.isfinite(m))


@pytest.mark.parametrize("name", SHIPPED_BRUSHES)
def test_shipped_brush_wider_across_than_along(name):
    m = crop_to_bristles(procedural_brush(name))
    rows, cols = m.shape
    assert cols > 1.4 * rows
    assert 16 <= rows <= 64 and 48 <= cols <= 128


@pytest.mark.parametrize("name", SHIPPED_BRUSHES)
def test_shipped_brush_uneven_bristles(name):
    m = procedural_brush(name)
    cols = m.shape[1]
    centre = m[:, cols // 4: 3 * cols // 4]            # away from the soft sides
    means = np.array([c[c > 0].mean() for c in centre.T])
    assert means.std() > 0.05
    assert means.max() - means.min() > 0.2


@pytest.mark.parametrize("name", SHIPPED_BRUSHES)
def test_shipped_brush_ragged_ends(name):
    m = procedural_brush(name)
    present = (m > 0).any(axis=0)
    first = np.argmax(m > 0, axis=0)[present]
    last = (m.shape[0] - 1 - np.argmax(m[::-1] > 0, axis=0))[present]
    cols = m.shape[1]
    centre = slice(cols // 3, 2 * cols // 3)               # even a round brush is roughly level here
    assert len(set(first[centre].tolist())) >= 2
    assert len(set(last[centre].tolist())) >= 2


@pytest.mark.parametrize("name", SHIPPED_BRUSHES)
def test_shipped_brush_zero_outside_footprint(name):
    m = procedural_brush(name)
    assert np.count_nonzero(m == 0) > 0
    assert (m > 0).mean() > 0.5


@pytest.mark.parametrize("name", SHIPPED_BRUSHES)
def test_shipped_brush_roughly_symmetric(name):
    m = procedural_brush(name).astype(np.float64)
    rows, cols = m.shape
    r = np.arange(rows) + 0.5 - rows / 2
    c = np.arange(cols) + 0.5 - cols / 2
    total = m.sum()
    assert abs((m.sum(axis=1) * r).sum() / total) < 0.05 * rows
    assert abs((m.sum(axis=0) * c).sum() / total) < 0.05 * cols


def test_round_and_filbert_shapes():
    rnd = procedural_brush("round")
    # elliptical: the outer columns are much shorter than the middle one
    counts = (rnd > 0).sum(axis=0)
    assert counts[counts > 0][0] < 0.5 * counts.max()
    # denser centre: the middle quarter is brighter on average than the rest
    rows, cols = rnd.shape
    inner = rnd[rows // 4: 3 * rows // 4, cols // 4: 3 * cols // 4]
    assert inner[inner > 0].mean() > rnd[rnd > 0].mean()
    fil = procedural_brush("filbert")
    counts = (fil > 0).sum(axis=0)
    mid = counts[fil.shape[1] // 2 - 8: fil.shape[1] // 2 + 8]
    assert mid.min() > 0.75 * counts.max()                 # flat middle
    assert counts[counts > 0][0] < 0.5 * counts.max()      # rounded ends


@pytest.mark.parametrize("name", SHIPPED_BRUSHES)
def test_shipped_brush_deterministic(name):
    a = procedural_brush(name)
    b = procedural_brush(name)
    assert np.array_equal(a, b)
    a[0, 0] = 0.5                                          # callers get their own copy
    assert not np.shares_memory(a, procedural_brush(name))


def test_shipped_brushes_differ():
    maps = [procedural_brush(n) for n in SHIPPED_BRUSHES]
    assert len({m.shape for m in maps}) == len(maps)


def test_unknown_procedural_name():
    with pytest.raises(ParameterError, match="xyz"):
        procedural_brush("xyz")


# ---------------------------------------------------------------------------
# loading


@pytest.mark.parametrize("name", SHIPPED_BRUSHES)
def test_load_shipped(name):
    m = load_brush(name)
    assert np.array_equal(m, crop_to_bristles(procedural_brush(name)))
    assert np.array_equal(load_brush(name.upper()), m)


def test_load_user_png_cropped(tmp_path):
    grad = np.tile(np.linspace(0.1, 1.0, 40), (10, 1))    # 10 rows x 40 columns
    canvas = np.zeros((30, 60))
    canvas[7:17, 11:51] = grad
    path = tmp_path / "my brush.png"
    write_png(path, canvas)
    m = load_brush(str(path))
    assert m.dtype == np.float32 and m.shape == (10, 40)
    np.testing.assert_allclose(m, np.round(grad * 255) / 255, atol=1e-6)
    assert np.array_equal(load_brush(path), m)             # pathlib.Path works too


def test_load_colour_png_uses_luminance(tmp_path):
    rgb = np.zeros((8, 20, 3))
    rgb[2:6, 3:17] = (0.0, 1.0, 0.0)
    path = tmp_path / "green.png"
    write_png(path, rgb)
    m = load_brush(str(path))
    assert m.shape == (4, 14)
    np.testing.assert_allclose(m, 0.7152, atol=2e-3)


def test_load_black_png_raises_naming_file(tmp_path):
    path = tmp_path / "black.png"
    write_png(path, np.zeros((12, 30)))
    with pytest.raises(PaintReliefError) as info:
        load_brush(str(path))
    message = str(info.value)
    assert "black.png" in message and "no bristles" in message
    assert one_sentence(message) == message


def test_load_unreadable_file_raises(tmp_path):
    path = tmp_path / "notes.png"
    path.write_text("this is not an image\n")
    with pytest.raises(InputError) as info:
        load_brush(str(path))
    assert "notes.png" in str(info.value)
    assert one_sentence(str(info.value)) == str(info.value)


def test_load_too_large_raises(tmp_path):
    path = tmp_path / "huge.png"
    write_png(path, np.ones((200, 300)))
    with pytest.raises(InputError, match="huge.png"):
        load_brush(str(path), max_megapixels=0.01)


@pytest.mark.parametrize("spec", ["xyz", "no/such/brush.png", ""])
def test_load_unknown_name_raises_naming_it(spec):
    with pytest.raises(ParameterError) as info:
        load_brush(spec)
    message = str(info.value)
    assert repr(spec) in message
    assert "neither a shipped brush (flat, round, filbert)" in message
    assert one_sentence(message) == message


# ---------------------------------------------------------------------------
# brush tips


@pytest.mark.parametrize("name", SHIPPED_BRUSHES)
@pytest.mark.parametrize("width", [64, 16, 4, 2, 1])
def test_brush_tip_extents(name, width):
    m = load_brush(name)
    rows, cols = m.shape
    tip = brush_tip(m, width, 0.9)
    assert isinstance(tip, BrushTip)
    length = max(1, int(np.floor(width * rows / cols + 0.5)))
    assert tip.width == width and tip.length == length == tip_length(m.shape, width)
    assert len(tip) >= 1
    for a in (tip.along, tip.across, tip.intensity):
        assert a.dtype == np.float32 and a.shape == (len(tip),)
    assert np.all(np.abs(tip.across) <= width / 2)
    assert np.all(np.abs(tip.along) <= length / 2)
    assert np.all(tip.intensity > 0) and np.all(tip.intensity <= np.float32(0.9))
    assert 0 < tip.mean_intensity() <= 0.9
    # the across and along offsets are pixel centres
    np.testing.assert_allclose((tip.across + width / 2 - 0.5) % 1, 0, atol=1e-5)


@pytest.mark.parametrize("name", SHIPPED_BRUSHES)
@pytest.mark.parametrize("width", [64, 16, 4, 2, 1])
def test_brush_tip_centred(name, width):
    tip = brush_tip(load_brush(name), width, 0.9)
    weights = tip.intensity.astype(np.float64)
    assert abs(np.average(tip.across, weights=weights)) < 0.06 * width + 0.01
    assert abs(np.average(tip.along, weights=weights)) < 0.06 * width + 0.01


def test_brush_tip_wide_tip_has_many_bristles():
    m = load_brush("flat")
    tip = brush_tip(m, 64, 1.0)
    assert len(tip) > 0.7 * 64 * tip.length
    assert tip.intensity.max() > 0.6
    assert tip.intensity.std() > 0.05                      # streaks survive resizing


def test_brush_tip_symmetric_map_exactly_centred():
    m = np.ones((6, 24), np.float32)
    for width in (64, 16, 4, 2, 1):
        tip = brush_tip(m, width, 0.5)
        assert abs(tip.across.mean()) < 1e-5 and abs(tip.along.mean()) < 1e-5
        np.testing.assert_allclose(tip.intensity, 0.5, atol=1e-5)
        assert len(tip) == width * tip.length


def test_brush_tip_transparency_scales():
    m = load_brush("round")
    full = brush_tip(m, 32, 1.0)
    half = brush_tip(m, 32, 0.5)
    keep = full.intensity > 2e-3                           # both keep these
    assert np.all(full.intensity <= 1.0)
    sub = {(a, c): i for a, c, i in zip(half.along, half.across, half.intensity, strict=True)}
    for a, c, i in zip(full.along[keep], full.across[keep], full.intensity[keep], strict=True):
        assert sub[(a, c)] == pytest.approx(0.5 * i, rel=1e-5)


def test_brush_tip_width_one_is_mean_intensity():
    m = load_brush("flat")
    tip = brush_tip(m, 1, 0.8)
    assert len(tip) == 1 and tip.along[0] == 0 and tip.across[0] == 0
    assert tip.intensity[0] == pytest.approx(0.8 * m[m > 0].mean(), rel=1e-5)


def test_brush_tip_fallback_when_nothing_survives():
    m = np.zeros((5, 40), np.float32)
    m[2, 0] = 0.002                                        # a faint single bristle at the edge
    tip = brush_tip(m, 4, 0.9)
    assert len(tip) == 1
    assert tip.intensity[0] == pytest.approx(0.0018, rel=1e-3)


def test_brush_tip_row_major_and_deterministic():
    m = load_brush("filbert")
    a = brush_tip(m, 16, 0.9)
    b = brush_tip(m, 16, 0.9)
    for x, y in ((a.along, b.along), (a.across, b.across), (a.intensity, b.intensity)):
        assert np.array_equal(x, y)
    order = np.lexsort((a.across, -a.along))               # front row first, then left to right
    assert np.array_equal(order, np.arange(len(a)))


def test_brush_tip_front_row_is_map_row_zero():
    m = np.zeros((4, 8), np.float32)
    m[0, :] = 1.0                                          # only the front row has bristles
    m[1:, :] = 0.2
    tip = brush_tip(m, 8, 1.0)
    front = tip.along == tip.along.max()
    assert tip.intensity[front].mean() > tip.intensity[~front].mean()
    assert tip.along.max() > 0


def test_brush_tip_is_frozen():
    tip = brush_tip(load_brush("flat"), 16, 0.9)
    with pytest.raises(AttributeError):
        tip.width = 3
    with pytest.raises(ValueError):
        tip.intensity[0] = 0.1


@pytest.mark.parametrize("width,transparency", [(0, 0.9), (-3, 0.9), (8, 0.0), (8, 1.5)])
def test_brush_tip_bad_arguments(width, transparency):
    with pytest.raises(ParameterError):
        brush_tip(load_brush("flat"), width, transparency)


def test_tip_cache():
    m = load_brush("flat")
    cache = tip_cache(m, (64, 32, 16, 8, 4), 0.9)
    assert sorted(cache) == [4, 8, 16, 32, 64]
    for w, tip in cache.items():
        assert tip.width == w
        assert np.array_equal(tip.intensity, brush_tip(m, w, 0.9).intensity)


# ---------------------------------------------------------------------------
# resizing


@pytest.mark.parametrize("shape", [(24, 96), (10, 40), (7, 13)])
@pytest.mark.parametrize("out", [(1, 4), (4, 16), (16, 64), (40, 160), (3, 5)])
def test_resize_constant_stays_constant(shape, out):
    m = np.full(shape, 0.7, np.float32)
    r = resize_map(m, *out)
    assert r.shape == out and r.dtype == np.float32
    inside = r[out[0] // 4: out[0] - out[0] // 4 or None, out[1] // 4: out[1] - out[1] // 4 or None]
    np.testing.assert_allclose(inside, 0.7, atol=1e-5)
    np.testing.assert_allclose(r, 0.7, atol=1e-4)


def test_resize_identity_and_clipping():
    m = procedural_brush("flat")
    np.testing.assert_allclose(resize_map(m, *m.shape), m, atol=1e-5)
    up = resize_map(m, 48, 192)                            # cubic overshoot is clipped
    assert up.min() >= 0.0 and up.max() <= 1.0


def test_resize_keeps_average_contact():
    m = procedural_brush("flat")
    for cols in (64, 16, 4):
        rows = tip_length(m.shape, cols)
        r = resize_map(m, rows, cols)
        assert r.mean() == pytest.approx(m.mean(), rel=0.15)
