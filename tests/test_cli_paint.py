"""``python -m core paint``: the relief maps, the report, determinism and bad parameters."""

import json

import numpy as np
import pytest
from oracles import one_sentence, same_bytes

from core.cli import main
from core.colour import srgb_to_linear
from core.files import reading, writing

OUTPUTS = {"color.exr", "height.exr", "opacity.exr", "orientation.exr", "painting.png", "lit_paper.png",
           "strokes.json", "report.json"}
REPORT_KEYS = {"strokes", "strokes_per_layer", "grids", "psnr_db", "seconds", "params", "seed", "width", "height",
               "version", "height_mode"}


@pytest.fixture(scope="module")
def photo(tmp_path_factory, half_textured):
    """A 48 x 64 photograph-like image: a smooth gradient beside coloured texture."""
    path = tmp_path_factory.mktemp("input") / "photo.png"
    writing.write_png(path, half_textured(48, 64))
    return path


@pytest.fixture(scope="module")
def painted(photo, tmp_path_factory):
    out = tmp_path_factory.mktemp("painted")
    assert main(["paint", str(photo), "-o", str(out), "-q", "--seed", "3"]) == 0
    return out


def test_paint_writes_every_output(painted):
    assert {p.name for p in painted.iterdir()} == OUTPUTS


def test_maps_agree_with_the_painting(painted):
    colour, channels, attributes = reading.read_exr(painted / "color.exr")
    assert channels == ["R", "G", "B"] and colour.shape == (48, 64, 3)
    preview = reading.read_image(painted / "painting.png")
    # color.exr holds the scene-linear version of the sRGB painting.
    np.testing.assert_allclose(colour, srgb_to_linear(preview), atol=0.01)
    height, channels, _ = reading.read_exr(painted / "height.exr")
    opacity, _, _ = reading.read_exr(painted / "opacity.exr")
    assert channels == ["Y"] and height.shape == (48, 64, 1)
    # 1 = one full bristle's contact; ridges and the build-up at a stroke's lift-off reach a little above
    assert height.min() >= 0.0 and height.max() <= 1.6 and height.max() > 0.1
    assert opacity.min() >= 0.0 and opacity.max() <= 1.0
    assert attributes["paint_relief:seed"] == "3"
    assert attributes["paint_relief:height_mode"] == "over"
    assert json.loads(attributes["paint_relief:params"])["layers"] == 4


def test_report_and_strokes(painted):
    report = json.loads((painted / "report.json").read_text())
    assert REPORT_KEYS <= set(report)
    assert report["width"] == 64 and report["height"] == 48 and report["seed"] == 3
    assert report["strokes"] == sum(report["strokes_per_layer"]) and len(report["strokes_per_layer"]) == 4 + 1
    assert report["strokes_per_layer"][-1] == report["detail_strokes"]
    assert set(report["stroke_shape"]) == {"median_length_to_width", "median_length_to_width_first_layer",
                                           "dab_share", "dab_area_share"}
    strokes = json.loads((painted / "strokes.json").read_text())["strokes"]
    assert len(strokes) == report["strokes"]
    first = strokes[0]
    assert set(first) == {"layer", "anchor", "size", "path", "colour"}     # laying data only with --strokes-to-lay
    assert first["layer"] == 0 and len(first["colour"]) == 3 and len(first["path"]) >= 1
    assert all(0 <= s["anchor"][0] < 64 and 0 <= s["anchor"][1] < 48 for s in strokes)


def test_same_seed_same_bytes(photo, painted, tmp_path):
    again = tmp_path / "again"
    assert main(["paint", str(photo), "-o", str(again), "-q", "--seed", "3"]) == 0
    assert set(same_bytes(again, painted)) == OUTPUTS - {"report.json"}


def test_other_seed_other_painting(photo, painted, tmp_path):
    other = tmp_path / "other"
    assert main(["paint", str(photo), "-o", str(other), "-q", "--seed", "4"]) == 0
    assert (other / "color.exr").read_bytes() != (painted / "color.exr").read_bytes()


def test_accumulate_mode_is_recorded(photo, tmp_path):
    out = tmp_path / "acc"
    assert main(["paint", str(photo), "-o", str(out), "-q", "--height-mode", "accumulate"]) == 0
    assert json.loads((out / "report.json").read_text())["height_mode"] == "accumulate"
    _, _, attributes = reading.read_exr(out / "height.exr")
    assert attributes["paint_relief:height_mode"] == "accumulate"


@pytest.mark.parametrize("options, words", [
    (["--sizes", ""], "at least one size"),
    (["--sizes", "16,-4"], "positive"),
    (["--layers", "0"], "Layers"),
    (["--alpha", "1.5"], "Alpha"),
    (["--brush", "sable"], "sable"),
])
def test_invalid_parameters(photo, tmp_path, capsys, options, words):
    out = tmp_path / "out"
    assert main(["paint", str(photo), "-o", str(out), "-q"] + options) != 0
    assert words in one_sentence(capsys.readouterr().err)
    assert not out.exists() or list(out.iterdir()) == []


@pytest.mark.parametrize("kind", ["black", "unreadable"])
def test_bad_brush_png(photo, tmp_path, capsys, kind):
    brush = tmp_path / "brush.png"
    if kind == "black":
        writing.write_png(brush, np.zeros((8, 32), np.float32))
    else:
        brush.write_text("no image here")
    assert main(["paint", str(photo), "-o", str(tmp_path / "out"), "-q", "--brush", str(brush)]) != 0
    assert "brush.png" in one_sentence(capsys.readouterr().err)
