"""The painting's strokes as polylines (``core.drawn_strokes``) and laid again after editing (``core.lay_drawn``):
the Grease Pencil round trip's core half, without Blender."""

import dataclasses
import json

import numpy as np
import pytest
from oracles import one_sentence, same_bytes

import core
from core.cli import main
from core.files import reading, writing
from core.files.stroke_file import bristle_colours

WIDTH_M, HEIGHT_M = 0.4, 0.3


@pytest.fixture(scope="module")
def painted(tmp_path_factory, half_textured):
    """(the photograph, its folder painted with seed 3 and its laying data): 64 x 48 px."""
    folder = tmp_path_factory.mktemp("drawn")
    photo = folder / "photo.png"
    writing.write_png(photo, half_textured(48, 64))
    assert main(["paint", str(photo), "-o", str(folder / "painted"), "-q", "--seed", "3", "--strokes-to-lay"]) == 0
    return photo, folder / "painted"


def through_plane(drawn):
    """``drawn`` carried onto the canvas plane and back, as a Grease Pencil object holds it (float32 metres)."""
    radius = (drawn.width * drawn.metres_per_pixel(WIDTH_M) / 2).astype(np.float32)
    return type(drawn).from_plane(
        drawn.counts, drawn.plane_points(WIDTH_M, HEIGHT_M, 0.002), radius, drawn.linear_colour(), drawn.opacity,
        drawn.index, drawn.size, WIDTH_M, HEIGHT_M)


def test_one_polyline_per_stroke_with_the_strokes_width_and_bristle_colour(painted):
    _, folder = painted
    document = json.loads((folder / "strokes.json").read_text())
    drawn = core.drawn_strokes(folder)
    assert len(drawn) == len(document["strokes"]) > 20 and drawn.size == (64, 48)
    assert drawn.counts.min() >= 2 and drawn.width.min() > 0
    assert drawn.index.tolist() == list(range(len(drawn)))
    for i in (0, len(drawn) // 2, len(drawn) - 1):
        stroke = document["strokes"][i]
        assert drawn.colour[i] == pytest.approx(bristle_colours(stroke).mean(axis=0), abs=1e-6)
        assert drawn.width[i] == stroke["size"]
        path = np.asarray(stroke["path"])
        assert drawn.stroke_points(i)[-1] == pytest.approx(path[-1])
    plane = drawn.plane_points(WIDTH_M, HEIGHT_M, 0.002)
    assert plane[:, 0].min() >= -WIDTH_M / 2 - 0.05 and plane[:, 0].max() <= WIDTH_M / 2 + 0.05
    assert np.all(plane[:, 2] == np.float32(0.002))


def test_unedited_strokes_through_the_plane_lay_the_paintings_bytes(painted, tmp_path):
    photo, folder = painted
    drawn = through_plane(core.drawn_strokes(folder))
    assert np.abs(drawn.points - core.drawn_strokes(folder).points).max() < 0.01
    report = core.lay_drawn(folder, drawn, tmp_path / "laid")
    assert report["strokes"] == len(drawn)
    same_bytes(folder, tmp_path / "laid")


def test_half_the_strokes_deleted_leave_relief_only_where_strokes_remain(painted, tmp_path):
    _, folder = painted
    drawn = through_plane(core.drawn_strokes(folder))
    document = json.loads((folder / "strokes.json").read_text())
    keep = np.array([stroke["anchor"][0] < 32 for stroke in document["strokes"]])     # the right half's deleted
    assert 0.2 < keep.mean() < 0.8
    starts = drawn.starts
    points = np.concatenate([drawn.points[starts[i]:starts[i + 1]] for i in np.flatnonzero(keep)])
    half = dataclasses.replace(drawn, counts=drawn.counts[keep], points=points, width=drawn.width[keep],
                               colour=drawn.colour[keep], opacity=drawn.opacity[keep], index=drawn.index[keep])
    core.lay_drawn(folder, half, tmp_path / "half")
    kept = [document["strokes"][i] for i in np.flatnonzero(keep)]
    laid = json.loads((tmp_path / "half" / "strokes.json").read_text())["strokes"]
    assert [s["lay"] for s in laid] == [s["lay"] for s in kept]
    height = reading.read_exr(tmp_path / "half" / "height.exr")[0][..., 0]
    reach = np.zeros(height.shape, bool)
    for stroke in kept:        # every pixel within a stroke's half width (and the brush's length) of its path
        path = np.asarray(stroke["path"])
        radius = stroke["size"]
        y, x = np.mgrid[0:height.shape[0], 0:height.shape[1]]
        for px, py in path:
            reach |= (x - px) ** 2 + (y - py) ** 2 <= radius ** 2
    assert height.max() > 0 and (~reach).mean() > 0.05 and np.all(height[~reach] == 0), (~reach).mean()
    before = reading.read_exr(folder / "opacity.exr")[0].mean()
    assert reading.read_exr(tmp_path / "half" / "opacity.exr")[0].mean() < before - 0.01


def test_a_moved_recoloured_and_a_new_stroke_are_laid(painted, tmp_path):
    _, folder = painted
    drawn = core.drawn_strokes(folder)
    last = len(drawn) - 1
    points = drawn.points.copy()
    starts = drawn.starts
    points[starts[last]:] += (5.0, 3.0)                            # the last stroke moved 5 px right, 3 px down
    colour = drawn.colour.copy()
    colour[last] = (1.0, 0.0, 0.0)
    new_points = np.array([[4.0, 40.0], [30.0, 40.0]])
    edited = dataclasses.replace(
        drawn, counts=np.append(drawn.counts, 2), points=np.concatenate([points, new_points]),
        width=np.append(drawn.width, 6.0), colour=np.concatenate([colour, [[0.0, 0.0, 1.0]]]).astype(np.float32),
        opacity=np.append(drawn.opacity, 1.0).astype(np.float32), index=np.append(drawn.index, -1))
    core.lay_drawn(folder, edited, tmp_path / "edited")
    document = json.loads((folder / "strokes.json").read_text())
    laid = json.loads((tmp_path / "edited" / "strokes.json").read_text())["strokes"]
    assert len(laid) == len(drawn) + 1
    before, after = document["strokes"][last]["lay"], laid[last]["lay"]
    assert np.asarray(after["control"]) - np.asarray(before["control"]) == pytest.approx(
        np.broadcast_to([5.0, 3.0], np.shape(before["control"])))
    assert bristle_colours(laid[last]).mean(axis=0)[0] > bristle_colours(document["strokes"][last]).mean(axis=0)[0]
    assert laid[-1]["size"] == 6 and laid[-1]["lay"]["brush"] == 0
    colour_map = reading.read_exr(tmp_path / "edited" / "color.exr")[0]
    assert colour_map[40, 10:25, 2].mean() > 0.5 and colour_map[40, 10:25, :2].max() < 0.2   # the new blue stroke


def test_a_painting_without_laying_data_is_one_sentence(tmp_path, half_textured):
    photo = tmp_path / "photo.png"
    writing.write_png(photo, half_textured(32, 40))
    assert main(["paint", str(photo), "-o", str(tmp_path / "painted"), "-q"]) == 0
    drawn = core.drawn_strokes(tmp_path / "painted")
    with pytest.raises(core.InputError) as error:
        core.lay_drawn(tmp_path / "painted", drawn, tmp_path / "laid")
    one_sentence(str(error.value), tmp_path / "painted" / "strokes.json")
    assert not (tmp_path / "laid").exists()
    with pytest.raises(core.InputError) as error:
        core.drawn_strokes(tmp_path)
    one_sentence(str(error.value), tmp_path / "strokes.json")


def test_every_stroke_deleted_lays_a_bare_canvas(painted, tmp_path):
    _, folder = painted
    drawn = core.drawn_strokes(folder)
    empty = type(drawn).from_plane(np.zeros(0, np.int64), np.zeros((0, 3), np.float32), np.zeros(0), np.zeros((0, 3)),
                                   np.zeros(0), np.zeros(0, np.int64), drawn.size, WIDTH_M, HEIGHT_M)
    report = core.lay_drawn(folder, empty, tmp_path / "bare")
    assert report["strokes"] == 0
    assert reading.read_exr(tmp_path / "bare" / "height.exr")[0].max() == 0
