"""Hertzmann 1998 baseline, its styles, the Fig. 8 ablations and their command-line options."""

from __future__ import annotations

import json

import numpy as np
import pytest
from oracles import one_sentence

from core.cli import main
from core.errors import ParameterError
from core.files import writing
from core.methods import paint
from core.methods.hertzmann98 import paint_hertzmann, scaled_radii
from core.methods.styles import STYLES, get_style
from core.params import Params
from core.results import Painting
from core.strokes.canvas import Canvas
from core.strokes.layout import hertzmann_anchors
from core.strokes.lines import solid_stroke


def textured(h: int = 96, w: int = 128, seed: int = 1) -> np.ndarray:
    """A smooth gradient beside blocky coloured texture and a disc."""
    rng = np.random.default_rng(seed)
    image = np.zeros((h, w, 3), np.float32)
    image[..., 0] = np.linspace(0.1, 0.9, w)[None, :]
    image[..., 1] = np.linspace(0.8, 0.2, h)[:, None]
    image[..., 2] = 0.4
    blocks = rng.random((h // 4, w // 8, 3)).astype(np.float32)
    image[:, w // 2:] = np.kron(blocks, np.ones((4, 4, 1), np.float32))[:h, :w - w // 2]
    yy, xx = np.mgrid[:h, :w]
    image[(yy - h / 2) ** 2 + (xx - w / 4) ** 2 < (h / 5) ** 2] = (0.9, 0.9, 0.2)
    return image


# 128 x 128 images painted as if 512 x 512 were 128 x 128: radii 8, 4, 2 px as Hertzmann's.
SMALL = 128 * 128 / 512 ** 2


@pytest.fixture(scope="module")
def image():
    return textured(128, 128)


@pytest.fixture(scope="module")
def styled(image):
    return {name: paint_hertzmann(image, Params(seed=2, size_reference_megapixels=SMALL), name) for name in STYLES}


def check_maps(p: Painting, shape) -> None:
    h, w = shape
    assert p.colour.shape == (h, w, 3) and p.colour.dtype == np.float32
    assert np.all(np.isfinite(p.colour)) and p.colour.min() >= 0 and p.colour.max() <= 1
    for m in (p.height, p.opacity, p.coverage, p.orientation):
        assert m.shape == (h, w) and np.all(np.isfinite(m))
    assert p.height.min() >= 0 and p.height.max() <= 1.6 and p.height.max() > 0.3
    assert 0 <= p.opacity.min() and p.opacity.max() <= 1 and 0 <= p.coverage.min() and p.coverage.max() <= 1
    assert p.orientation.min() >= 0 and p.orientation.max() <= np.pi + 1e-6
    assert p.statistics["strokes"] == len(p.strokes) == sum(p.statistics["strokes_per_layer"])
    assert p.analysis is not None


def test_flat_image_paints_only_the_largest_layer():
    flat = np.full((128, 128, 3), (0.3, 0.5, 0.7), np.float32)
    p = paint_hertzmann(flat, Params(size_reference_megapixels=SMALL), "impressionist")
    assert p.statistics["radii_px"] == [8, 4, 2]
    counts = p.statistics["strokes_per_layer"]
    assert len(counts) == 3 and counts[0] > 0 and counts[1:] == [0, 0]
    np.testing.assert_allclose(p.colour, flat, atol=1e-5)      # the first layer covers everything
    assert p.coverage.min() > 0.99


def test_style_table():
    assert STYLES["impressionist"].threshold == 100 and STYLES["impressionist"].radii == (8, 4, 2)
    assert STYLES["expressionist"].curvature == 0.25 and STYLES["expressionist"].jitter_value == 0.5
    assert STYLES["colorist_wash"].alpha == 0.5 and STYLES["colorist_wash"].jitter_rgb == 0.3
    assert STYLES["pointillist"].radii == (4, 2) and STYLES["pointillist"].max_length == 0
    assert get_style("colorist-wash") is STYLES["colorist_wash"]
    assert min(STYLES, key=lambda k: STYLES[k].alpha) == "colorist_wash"
    assert scaled_radii((8, 4, 2), 512, 512) == (8, 4, 2) and scaled_radii((8, 4, 2), 1024, 1024) == (16, 8, 4)
    assert scaled_radii((8, 4, 2), 128, 128) == (2, 1, 1) and scaled_radii((8, 4, 2), 128, 128, SMALL) == (8, 4, 2)


def test_styles_change_stroke_counts(styled, image):
    counts = {k: v.statistics["strokes"] for k, v in styled.items()}
    assert counts["pointillist"] == max(counts.values())
    assert counts["expressionist"] > counts["impressionist"] > counts["colorist_wash"]   # T = 50 < 100 < 200
    assert all(len(p.strokes[0].path) == 1 for p in [styled["pointillist"]])          # dabs
    wash, impressionist = styled["colorist_wash"], styled["impressionist"]
    assert wash.opacity.mean() < impressionist.opacity.mean()
    assert wash.coverage.mean() < impressionist.coverage.mean()
    for p in styled.values():
        check_maps(p, image.shape[:2])
        s = p.statistics
        assert s["method"] == "hertzmann98" and s["style"] in STYLES and np.isfinite(s["psnr_db"])


def test_hertzmann_strokes_are_records(styled):
    p = styled["impressionist"]
    radii = p.statistics["radii_px"]
    first = p.strokes[0]
    assert first.layer == 0 and first.size == round(2 * radii[0])
    assert 1 <= len(first.path) <= 17 and len(first.colour) == 3
    assert {tuple(s.to_dict()) for s in p.strokes[:1]} and set(first.to_dict()) == {"layer", "anchor", "size", "path",
                                                                                      "colour"}


def test_determinism(image):
    a = paint_hertzmann(image, Params(seed=5, size_reference_megapixels=SMALL), "expressionist")
    b = paint(image, Params(seed=5, method="hertzmann98", style="expressionist", size_reference_megapixels=SMALL))
    c = paint_hertzmann(image, Params(seed=6, size_reference_megapixels=SMALL), "expressionist")
    assert np.array_equal(a.colour, b.colour) and np.array_equal(a.height, b.height)
    assert not np.array_equal(a.colour, c.colour)


def test_anchors_at_max_error_and_cell_centres():
    error = np.zeros((10, 12))
    error[2, 3] = 500.0
    anchors = hertzmann_anchors(error, 4, 10.0)
    assert anchors.tolist() == [[3, 2]]
    bare = np.full((8, 8), np.inf)
    assert sorted(map(tuple, hertzmann_anchors(bare, 4, 100.0).tolist())) == [(1, 1), (1, 5), (5, 1), (5, 5)]


def test_solid_line_is_one_colour():
    canvas = Canvas.blank((40, 60), (0.9, 0.9, 0.9))
    solid_stroke(canvas, np.array([[10.0, 20.0], [30.0, 15.0], [50.0, 22.0]]), 4.0, np.array([0.2, 0.4, 0.6]), 1.0,
                 "over", 0.5)
    band = canvas.opacity > 0.999
    assert band.sum() > 100
    colours = np.unique(np.round(canvas.colour[band], 5), axis=0)
    assert len(colours) == 1 and np.allclose(colours[0], (0.2, 0.4, 0.6), atol=1e-5)
    edge = (canvas.opacity > 0) & ~band
    assert edge.any() and canvas.height[band].max() == pytest.approx(1.0, abs=0.05)
    assert canvas.height[~(canvas.opacity > 0)].max() == 0


def test_lines_renderer_single_stroke_one_colour():
    from stamp_oracle import paint_one

    from core.strokes.brush import brush_tip, load_brush
    from core.strokes.stroke import colour_sources
    ref = textured(64, 64)
    canvas = Canvas.blank((64, 64), (0.93, 0.90, 0.84))
    orientation = np.zeros((64, 64), np.float32)
    params = Params(renderer="lines")
    tip = brush_tip(load_brush("flat"), 8, params.transparency)
    stroke = paint_one(canvas, colour_sources(ref, [8], params)[8], orientation, (20, 30), 8, tip, params)
    painted = canvas.opacity > 0
    inside = canvas.opacity > 0.999
    assert inside.sum() > 20
    assert len(np.unique(np.round(canvas.colour[inside], 5), axis=0)) == 1
    np.testing.assert_allclose(canvas.colour[inside][0], stroke.colour, atol=1e-5)
    assert len(np.unique(np.round(canvas.colour[painted], 5), axis=0)) >= 1


@pytest.mark.parametrize("changes", [dict(layout="hertzmann98"), dict(renderer="lines"),
                                     dict(layout="hertzmann98", renderer="lines", style="pointillist")])
def test_ablations_run(image, changes):
    p = paint(image, Params(seed=1, size_reference_megapixels=SMALL, **changes))
    check_maps(p, image.shape[:2])
    assert p.statistics["method"] == "huang11"
    for key, value in changes.items():
        assert p.statistics[key] == value
    if changes.get("layout") == "hertzmann98":
        assert len(p.statistics["strokes_per_layer"]) == len(p.analysis.sizes) + 1   # and the detail pass
    assert p.statistics["psnr_db"] > 12


@pytest.mark.parametrize("field, value, words", [
    ("method", "monet", "Unknown method 'monet'"), ("style", "cubist", "Unknown style 'cubist'"),
    ("layout", "spiral", "Unknown layout 'spiral'"), ("renderer", "spray", "Unknown renderer 'spray'")])
def test_invalid_names(field, value, words):
    with pytest.raises(ParameterError) as info:
        Params(**{field: value}).validate()
    text = str(info.value)
    assert words in text and one_sentence(text) == text


@pytest.fixture(scope="module")
def photo(tmp_path_factory):
    path = tmp_path_factory.mktemp("hz") / "photo.png"
    writing.write_png(path, textured(48, 64))
    return path


def test_cli_hertzmann_writes_the_same_files(photo, tmp_path):
    default, hz = tmp_path / "default", tmp_path / "hz"
    assert main(["paint", str(photo), "-o", str(default), "-q"]) == 0
    assert main(["paint", str(photo), "-o", str(hz), "-q", "--method", "hertzmann98", "--style", "pointillist"]) == 0
    assert {p.name for p in hz.iterdir()} == {p.name for p in default.iterdir()}
    report = json.loads((hz / "report.json").read_text())
    assert report["method"] == "hertzmann98" and report["style"] == "pointillist"
    assert set(json.loads((default / "report.json").read_text())) <= set(report)
    assert report["params"]["method"] == "hertzmann98"


def test_cli_options(photo, tmp_path, capsys):
    out = tmp_path / "wash"
    assert main(["paint", str(photo), "-o", str(out), "-q", "--method", "hertzmann98", "--style", "colorist-wash"]) == 0
    assert json.loads((out / "report.json").read_text())["style"] == "colorist_wash"
    out = tmp_path / "ablation"
    assert main(["paint", str(photo), "-o", str(out), "-q", "--layout", "hertzmann98", "--renderer", "lines"]) == 0
    report = json.loads((out / "report.json").read_text())
    assert (report["method"], report["layout"], report["renderer"]) == ("huang11", "hertzmann98", "lines")
    bad = tmp_path / "bad"
    assert main(["paint", str(photo), "-o", str(bad), "-q", "--style", "cubist"]) != 0
    assert "cubist" in one_sentence(capsys.readouterr().err)
    assert not bad.exists() or list(bad.iterdir()) == []
