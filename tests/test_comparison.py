"""The comparison's figures and pictures, from synthetic renders (no Blender needed here)."""

import json
import math

import numpy as np
import pytest

from core.colour import luminance, srgb_to_linear
from core.errors import InputError, ParameterError
from core.evaluation.comparison import render_path, run_comparison, shading
from core.files import reading, writing
from core.lighting import bump_lighting
from core.measures.metrics import pearson


@pytest.fixture
def painted(tmp_path):
    """A painted folder: grey-brown colour, a bumpy height field, orientation 0."""
    h, w = 48, 64
    yy, xx = np.mgrid[0:h, 0:w]
    height = (0.5 + 0.25 * np.sin(xx / 4.0) * np.cos(yy / 5.0)).astype(np.float32)
    srgb = np.dstack([np.full((h, w), 0.6), np.full((h, w), 0.5), np.full((h, w), 0.4)]).astype(np.float32)
    folder = tmp_path / "painting"
    folder.mkdir()
    writing.write_exr(folder / "color.exr", srgb_to_linear(srgb))
    writing.write_exr(folder / "height.exr", height, channels=("Y",))
    writing.write_exr(folder / "orientation.exr", np.zeros((h, w), np.float32), channels=("Y",))
    return folder, srgb, height


def fake_renders(folder, srgb, height, azimuths, elevation, relief, gain=0.8):
    """'Renders' made by the bump model itself, so the bump model must match them exactly."""
    renders = folder.parent / "renders"
    renders.mkdir(exist_ok=True)
    for az in azimuths:
        lit = bump_lighting(srgb, height, math.radians(az), math.radians(elevation), relief=relief)
        writing.write_exr(render_path(renders, "relief", az), gain * srgb_to_linear(lit))
        writing.write_exr(render_path(renders, "flat", az), gain * srgb_to_linear(srgb))
    return renders


def test_shading_of_a_doubled_image_is_one():
    base = np.full((4, 5, 3), 0.2, np.float32)
    np.testing.assert_allclose(shading(2 * base, base), 1.0, rtol=1e-6)
    np.testing.assert_allclose(shading(base, base), 0.0, atol=1e-7)


def test_the_bump_model_matches_renders_made_by_it(painted, tmp_path):
    folder, srgb, height = painted
    azimuths = [0, 90, 180, 270]
    renders = fake_renders(folder, srgb, height, azimuths, 30, 4.0)
    result = run_comparison(folder, renders, azimuths, 30, tmp_path / "out", relief_px=4.0)
    out = tmp_path / "out"
    assert {p.name for p in out.iterdir()} >= {"comparison.json", "comparison.md", "comparison.png",
                                               "correlation.png", "light_sweep.gif"}
    saved = json.loads((out / "comparison.json").read_text())
    assert saved["best_azimuth_deg"] == result["best_azimuth_deg"]
    for entry in saved["azimuths"]:
        bump = entry["models"]["bump"]
        assert bump["pearson"] > 0.999 and bump["rms"] < 1e-3
    # The fixed-light 2-D model turns with the light as the renders do ...
    assert all(e["models"]["directional"]["pearson"] > 0.9 for e in saved["azimuths"])
    # ... while the paper's light follows the strokes (all horizontal here, so it always looks along -y):
    # light from the bottom and from the top give it correlations of opposite sign.
    paper = {e["azimuth_deg"]: e["models"]["paper"]["pearson"] for e in saved["azimuths"]}
    assert paper[90.0] * paper[270.0] < 0
    assert saved["best_pearson"] == max(paper.values())


def test_figures_agree_with_a_recomputation_from_the_saved_images(painted, tmp_path):
    folder, srgb, height = painted
    renders = fake_renders(folder, srgb, height, [45], 40, 6.0)
    saved = run_comparison(folder, renders, [45], 40, tmp_path / "out", relief_px=4.0)
    relief = reading.read_exr(render_path(renders, "relief", 45))[0]
    flat = reading.read_exr(render_path(renders, "flat", 45))[0]
    s3d = luminance(relief) / luminance(flat) - 1.0
    lit = bump_lighting(srgb, height, math.radians(45), math.radians(40), relief=4.0)
    s2d = luminance(srgb_to_linear(lit)) / luminance(srgb_to_linear(srgb)) - 1.0
    bump = saved["azimuths"][0]["models"]["bump"]
    assert bump["pearson"] == pytest.approx(pearson(s3d, s2d), abs=1e-3)
    assert bump["rms"] == pytest.approx(float(np.sqrt(np.mean((s3d - s2d) ** 2))), abs=1e-3)


def test_missing_render_and_empty_sweep(painted, tmp_path):
    folder, _, _ = painted
    with pytest.raises(InputError, match="flat_090.exr"):
        run_comparison(folder, tmp_path, [90], 30, tmp_path / "out")
    with pytest.raises(ParameterError, match="at least one"):
        run_comparison(folder, tmp_path, [], 30, tmp_path / "out")
