"""The lighting comparison's Blender half: the sweep renders, sample_scenes/compare.py and its errors.

Renders run in subprocesses (``bpy`` can be imported once per process), with
BLENDER_USER_RESOURCES in a temporary folder:
- tests/blender/compare_checks.py: a calibration render of the flat canvas
  and the sweep on a synthetic ramp (RESULTS json, asserted on here);
- sample_scenes/compare.py end to end on a tiny photograph, whose figures
  are recomputed here from its renders and maps with core.lighting and
  core.measures.metrics.
The pure helpers of addon/values.py are tested without Blender.
"""

import json
import math
from functools import partial
from pathlib import Path

import numpy as np
import pytest
from addon_values import values
from blender_run import need_bpy, run_checks, run_script
from blender_run import step as _step
from oracles import one_sentence_run

from core.colour import linear_to_srgb, luminance, srgb_to_linear
from core.files import reading, writing
from core.lighting import bump_lighting, directional_lighting, paper_lighting
from core.measures.metrics import pearson

REPO = Path(__file__).resolve().parent.parent
CHECKS = REPO / "tests" / "blender" / "compare_checks.py"
SCRIPT = REPO / "sample_scenes" / "compare.py"


# --- pure helpers -------------------------------------------------------------

def test_sweep_azimuths():
    assert values.sweep_azimuths(1) == [0.0]
    assert values.sweep_azimuths(4) == [0.0, 90.0, 180.0, 270.0]
    with pytest.raises(ValueError, match="at least one"):
        values.sweep_azimuths(0)


def test_blender_lights_use_the_painters_azimuth():
    # The painter's (cos a, sin a) with y DOWN the image is Blender's (x, -y) with y UP the canvas.
    for painter in (0.0, 30.0, 90.0, 135.0, 300.0):
        x, y, _ = values.light_direction(math.radians(painter), 0.0)
        assert (x, -y) == pytest.approx((math.cos(math.radians(painter)), math.sin(math.radians(painter))), abs=1e-12)


def test_render_names_and_clashes():
    assert values.render_file_name("relief", 45.0) == "relief_045.exr"
    assert values.render_file_name("flat", 0.0) == "flat_000.exr"
    values.check_render_names(values.sweep_azimuths(36))
    with pytest.raises(ValueError, match="share"):
        values.check_render_names(values.sweep_azimuths(720))


def test_relief_pixels():
    # 2 mm of paint on a 40 cm canvas of 400 px (1 mm pixels): 2 pixel widths per height unit.
    assert values.relief_pixels(2.0, 40.0, 400) == pytest.approx(2.0)


# --- inside Blender -------------------------------------------------------------

@pytest.fixture(scope="module")
def checks(tmp_path_factory):
    need_bpy()
    work = tmp_path_factory.mktemp("compare_checks")
    return run_checks(CHECKS, work, work)


@pytest.mark.blender
def test_calibration_render_of_the_flat_canvas_reproduces_the_painting(checks):
    step = _step(checks, "calibration")
    assert step["size"] == step["map_size"] == [256, 192]
    # Lambertian paint under a uniform white world of radiance 1 reflects exactly its albedo; compared
    # on sRGB-encoded values in [0, 1] (peak 1).
    assert step["psnr_srgb"] >= 35.0, step
    assert step["mean_ratio"] == pytest.approx(1.0, abs=0.01)
    assert step["psnr_srgb_upside_down"] < 20.0  # the check can tell a flipped canvas
    assert step["flat_displace_strength"] == 0.0 and step["relief_back_on"] == pytest.approx(0.002)


@pytest.mark.blender
def test_ramp_lit_from_the_right_brightens_and_from_the_left_darkens(checks):
    step = _step(checks, "ramp")
    assert step["relief_px"] == pytest.approx(step["expected_relief_px"], rel=1e-5)
    right, left = step["azimuths"]["0"], step["azimuths"]["180"]
    # Painter azimuth 0 = light on the right; the ramp's slope faces +x: S3D > 0 everywhere on it.
    assert right["s3d_positive"] == 1.0 and right["s3d_mean"] > 0.05
    # Steeper rows (further down the image) brighten more.
    assert right["s3d_bottom_rows"] > right["s3d_top_rows"] > 0
    # The light on the other side flips the sign.
    assert left["s3d_negative"] == 1.0 and left["s3d_mean"] < -0.05
    for entry in (right, left):
        assert entry["json"]["bump"]["pearson"] > 0.9, entry
        assert entry["bump_pearson_here"] > 0.9, entry
    # The sweep left the scene as it found it.
    assert step["key_restored"] and step["engine_after"] != "CYCLES"


@pytest.mark.blender
def test_render_comparison_operator_headless(checks):
    step = _step(checks, "operator")
    assert step["result"] == ["FINISHED"], step["error"]
    for name in ("comparison.json", "comparison.md", "comparison.png", "correlation.png", "light_sweep.gif"):
        assert name in step["files"], name
    assert step["renders"] == ["flat_000.exr", "relief_000.exr"]
    assert step["bad_result"] is None and step["blocker"] in step["bad_error"]
    assert "Traceback" not in step["bad_error"] and len(step["bad_error"].strip().splitlines()) == 1
    assert step["poll_without_canvas"] is False


# --- sample_scenes/compare.py -----------------------------------------------------

def _photo(path, w=48, h=32):
    y, x = np.mgrid[0:h, 0:w]
    stripes = 0.5 + 0.4 * np.sin(x / 3.0) * np.cos(y / 4.0)
    writing.write_png(path, np.stack([x / w, y / h, stripes], axis=-1).astype(np.float32))
    return path


_compare = partial(run_script, SCRIPT)


@pytest.fixture(scope="module")
def end_to_end(tmp_path_factory):
    need_bpy()
    work = tmp_path_factory.mktemp("compare_script")
    photo = _photo(work / "photo.png", 64, 48)
    out = work / "out"
    args = [photo, "-o", out, "--azimuths", 2, "--size", 48, "--samples", 4]
    first = _compare(args, work)
    assert first.returncode == 0, first.stdout[-3000:] + first.stderr[-3000:]
    again = _compare(args, work)
    assert again.returncode == 0, again.stdout[-3000:] + again.stderr[-3000:]
    return {"out": out, "first": first, "again": again}


@pytest.mark.blender
def test_compare_script_writes_everything(end_to_end):
    out = end_to_end["out"]
    for name in ("comparison.json", "comparison.md", "comparison.png", "correlation.png", "light_sweep.gif",
                 "scene.blend", "input.png", "painting/color.exr", "painting/report.json",
                 "renders/relief_000.exr", "renders/flat_000.exr", "renders/relief_180.exr", "renders/flat_180.exr"):
        assert (out / name).is_file(), name
    height = reading.read_exr(out / "painting" / "height.exr")[0]
    assert max(height.shape[:2]) == 48  # the --size cap
    for render in (out / "renders").glob("*.exr"):
        assert reading.read_exr(render)[0].shape[:2] == height.shape[:2]
    stdout = end_to_end["first"].stdout
    for step in ("extension", "paint", "scene", "renders", "blend", "comparison", "total"):
        assert step in stdout.split("Seconds per step:")[1], step
    assert "comparison.png" in stdout and "light_sweep.gif" in stdout
    # The second run reuses the painting (same input, same parameters).
    assert "reusing the painting" in end_to_end["again"].stdout


@pytest.mark.blender
def test_compare_script_figures_recomputed_from_its_renders(end_to_end):
    """comparison.json's Pearson r, recomputed here with core.lighting and core.measures.metrics from the files."""
    out = end_to_end["out"]
    result = json.loads((out / "comparison.json").read_text())
    linear = reading.read_exr(out / "painting" / "color.exr")[0][..., :3]
    colour = linear_to_srgb(linear)
    height = reading.read_exr(out / "painting" / "height.exr")[0][..., 0]
    orientation = reading.read_exr(out / "painting" / "orientation.exr")[0][..., 0]
    elevation = math.radians(result["elevation_deg"])
    unlit = luminance(linear)
    assert [e["azimuth_deg"] for e in result["azimuths"]] == [0.0, 180.0]
    for entry in result["azimuths"]:
        az = entry["azimuth_deg"]
        relief = luminance(reading.read_exr(out / "renders" / "relief_{:03.0f}.exr".format(az))[0][..., :3])
        flat = luminance(reading.read_exr(out / "renders" / "flat_{:03.0f}.exr".format(az))[0][..., :3])
        mask = (flat > 0.01) & (unlit > 0.01)
        assert mask.mean() > 0.5
        s3d = relief[mask] / flat[mask] - 1.0
        lit = {"paper": paper_lighting(colour, height, orientation),
               "directional": directional_lighting(colour, height, math.radians(az)),
               "bump": bump_lighting(colour, height, math.radians(az), elevation, relief=result["relief_px"])}
        for model, image in lit.items():
            s2d = luminance(srgb_to_linear(image))[mask] / unlit[mask] - 1.0
            assert entry["models"][model]["pearson"] == pytest.approx(pearson(s3d, s2d), abs=1e-3), (az, model)


# --- bad input ----------------------------------------------------------------------

@pytest.mark.blender
def test_compare_script_bad_input_ends_withone_sentence_run(tmp_path):
    need_bpy()
    photo = _photo(tmp_path / "photo.png")
    broken = tmp_path / "broken.png"
    broken.write_bytes(b"not a picture\n" * 10)
    blocker = tmp_path / "a_file"
    blocker.write_text("a file where a folder should be")
    out = tmp_path / "out"

    assert "required" in one_sentence_run(_compare([], tmp_path))
    # Blender's launcher: the script's arguments follow "--" (here without an image).
    assert "INPUT" in one_sentence_run(_compare(["--", "-o", out], tmp_path))
    assert "no_such.png" in one_sentence_run(_compare([tmp_path / "no_such.png", "-o", out], tmp_path))
    assert "broken.png" in one_sentence_run(_compare([broken, "-o", out], tmp_path))
    assert not out.exists()  # a bad image is found before any output is written
    assert "a_file" in one_sentence_run(_compare([photo, "-o", blocker / "out"], tmp_path))
    text = one_sentence_run(_compare(["--", photo, "-o", out, "--azimuths", "0"], tmp_path))
    assert "at least 1 azimuth" in text
    assert not out.exists()
