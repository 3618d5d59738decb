"""Lighting models (core/lighting/models.py) and ``python -m core light``.

Conventions: x = column, y = row (down); angles from +x towards +y; a light
azimuth points from the canvas towards the light; normals are X right, Y up,
Z out of the canvas.
"""

import math
import shutil

import numpy as np
import pytest
from oracles import one_sentence

from core.cli import main
from core.colour import linear_to_srgb, srgb_to_linear
from core.errors import ParameterError
from core.files import reading, writing
from core.lighting import models as lighting

H, W = 12, 16


def grey(value, shape=(H, W)):
    """A uniform (H, W, 3) image of sRGB ``value``."""
    return np.full(shape + (3,), value, np.float32)


def columns():
    return np.arange(W, dtype=np.float32)[None, :].repeat(H, 0)


def rows():
    return np.arange(H, dtype=np.float32)[:, None].repeat(W, 1)


# ---------------------------------------------------------------------------
# Eq. 6-7 (the paper's lighting)


def step_height():
    """4 x 3 height field: 0.2 on rows 0-1, 0 on rows 2-3 (a step across horizontal strokes)."""
    h = np.zeros((4, 3), np.float32)
    h[:2] = 0.2
    return h


@pytest.mark.parametrize("level, expected", [
    (127.5, 127.5 + 51.0),              # D = 255 * 0.2 = 51; min(I, 255 - I) = 127.5: full effect
    (51.0, 51.0 + 51.0 * 51.0 / 127.5),  # 71.4
    (0.0, 0.0),                          # black stays black
    (255.0, 255.0),                      # white stays white
    (229.5, 229.5 + 51.0 * 25.5 / 127.5),  # near white: min = 25.5 -> +10.2
])
def test_eq7_on_a_height_step(level, expected):
    # Strokes run along +x (O = 0), so d = O - pi/2 = -pi/2 points up the image:
    # D(x, y) = h(x, y - 1) - h(x, y). Only row 2 (just below the step) sees D = 51.
    colour = np.full((4, 3, 3), level / 255.0, np.float32)
    out = lighting.paper_lighting(colour, step_height(), np.zeros((4, 3), np.float32), strength=1.0) * 255.0
    want = np.full((4, 3, 3), level, np.float32)
    want[2] = expected
    np.testing.assert_allclose(out, want, atol=2e-3)


def test_eq7_strength_and_sign():
    colour = np.full((4, 3, 3), 0.5, np.float32)
    # a = 0.5 halves the change: 127.5 + 0.5 * 51 = 153.
    out = lighting.paper_lighting(colour, step_height(), np.zeros((4, 3), np.float32), strength=0.5) * 255.0
    np.testing.assert_allclose(out[2], 153.0, atol=2e-3)
    # O = pi: d = pi/2 points down; D(row 1) = h(row 2) - h(row 1) = -51 -> 127.5 - 51 = 76.5.
    out = lighting.paper_lighting(colour, step_height(), np.full((4, 3), math.pi, np.float32), 1.0) * 255.0
    want = np.full((4, 3, 3), 127.5, np.float32)
    want[1] = 76.5
    np.testing.assert_allclose(out, want, atol=2e-3)


def test_eq7_clips_to_the_range():
    colour = np.full((4, 3, 3), 0.5, np.float32)
    h = step_height() * 5.0  # D = 255 at row 2: 127.5 + 255 -> clipped to 255
    out = lighting.paper_lighting(colour, h, np.zeros((4, 3), np.float32), 1.0)
    np.testing.assert_allclose(out[2], 1.0)
    assert out.dtype == np.float32 and out.shape == (4, 3, 3)


def test_eq6_samples_bilinearly():
    # h = 0.01 x; d = pi/4 samples (x + 0.7071, y + 0.7071): D = 255 * 0.01 * 0.7071 inside the image.
    d = lighting.height_difference(0.01 * columns(), math.pi / 4)
    np.testing.assert_allclose(d[2:-2, 2:-2], 2.55 * math.sqrt(0.5), rtol=1e-4)
    # At the right border the sample is clamped to the last column: no change.
    np.testing.assert_allclose(d[:, -1], 0.0, atol=1e-4)


def test_paper_lighting_follows_the_orientation():
    # Vertical strokes (O = pi/2) on a ramp rising to the right: d = 0 looks one pixel right,
    # D = 255 * 0.01 = 2.55 -> a mid grey rises by 2.55 levels.
    out = lighting.paper_lighting(grey(0.5), 0.01 * columns(), np.full((H, W), math.pi / 2, np.float32), 1.0)
    np.testing.assert_allclose(out[:, :-1] * 255.0, 127.5 + 2.55, atol=2e-3)


# ---------------------------------------------------------------------------
# flat canvas


@pytest.mark.parametrize("model", lighting.MODELS)
def test_flat_height_changes_nothing(model):
    rng = np.random.default_rng(1)
    colour = rng.random((H, W, 3), dtype=np.float32)
    flat = np.full((H, W), 0.3, np.float32)
    orientation = rng.random((H, W), dtype=np.float32) * np.float32(math.pi)
    if model == "bump":
        # The diffuse term is normalised by sin(elevation): a flat canvas keeps its colour,
        # plus only the flat highlight specular * cos^n((90 deg - elevation) / 2).
        out = lighting.bump_lighting(colour, flat, azimuth=1.0, elevation=math.radians(35), specular=0.0)
        np.testing.assert_allclose(out, colour, atol=2e-5)
        out = lighting.bump_lighting(colour, flat, azimuth=1.0, elevation=math.radians(35))
        glint = lighting.BUMP_SPECULAR * math.cos(math.radians(55) / 2) ** lighting.BUMP_SHININESS
        np.testing.assert_allclose(out, linear_to_srgb(srgb_to_linear(colour) + glint), atol=2e-5)
    else:
        out = lighting.light(model, colour, flat, orientation)
        np.testing.assert_allclose(out, colour, atol=1e-6)


# ---------------------------------------------------------------------------
# directional variant


def test_directional_light_from_plus_x_brightens_slopes_facing_plus_x():
    facing = 0.01 * (W - 1 - columns())  # height falls towards +x: the slope faces +x
    away = 0.01 * columns()
    lit = lighting.directional_lighting(grey(0.5), facing, azimuth=0.0, strength=1.0) * 255.0
    dark = lighting.directional_lighting(grey(0.5), away, azimuth=0.0, strength=1.0) * 255.0
    # D = h(p - l) - h(p) = +-2.55 (the first column samples itself, clamped).
    np.testing.assert_allclose(lit[:, 1:], 127.5 + 2.55, atol=2e-3)
    np.testing.assert_allclose(dark[:, 1:], 127.5 - 2.55, atol=2e-3)


def test_directional_light_from_below():
    facing_down = 0.01 * (H - 1 - rows())  # rises towards the image top: faces +y (down)
    out = lighting.directional_lighting(grey(0.5), facing_down, azimuth=math.pi / 2, strength=1.0)
    assert np.all(out[1:] * 255.0 > 127.5 + 2.5)
    out = lighting.directional_lighting(grey(0.5), facing_down, azimuth=-math.pi / 2, strength=1.0)
    assert np.all(out[:-1] * 255.0 < 127.5 - 2.5)


# ---------------------------------------------------------------------------
# normals


def test_normal_map_of_a_tilted_plane():
    relief = 3.0
    n = lighting.normal_map(columns() * math.tan(math.radians(30)) / relief, relief)
    assert n.shape == (H, W, 3) and n.dtype == np.float32
    np.testing.assert_allclose(np.linalg.norm(n, axis=2), 1.0, atol=1e-6)
    # Rising towards +x: the normal leans 30 degrees towards -X.
    np.testing.assert_allclose(n[..., 0], -math.sin(math.radians(30)), atol=1e-6)
    np.testing.assert_allclose(n[..., 1], 0.0, atol=1e-6)
    np.testing.assert_allclose(n[..., 2], math.cos(math.radians(30)), atol=1e-6)


def test_normal_map_y_points_up_the_image():
    relief = 2.0
    # Rising towards the image top (height falls as the row grows): the surface faces down the
    # image, which is -Y in the Y-up (OpenGL) convention Blender's Normal Map node reads.
    n = lighting.normal_map((H - 1 - rows()) * math.tan(math.radians(20)) / relief, relief)
    np.testing.assert_allclose(n[..., 1], -math.sin(math.radians(20)), atol=1e-6)
    np.testing.assert_allclose(n[..., 0], 0.0, atol=1e-6)
    np.testing.assert_allclose(n[..., 2], math.cos(math.radians(20)), atol=1e-6)


def test_encode_normals():
    n = lighting.normal_map(np.zeros((H, W), np.float32), 4.0)
    np.testing.assert_allclose(lighting.encode_normals(n), np.broadcast_to([0.5, 0.5, 1.0], (H, W, 3)))
    tilted = lighting.encode_normals(lighting.normal_map(columns() * 0.25, 4.0))
    assert np.all((tilted >= 0) & (tilted <= 1)) and np.all(tilted[..., 0] < 0.5)


# ---------------------------------------------------------------------------
# bump (Blinn-Phong)


@pytest.mark.parametrize("specular", [0.0, lighting.BUMP_SPECULAR])
def test_bump_light_from_plus_x(specular):
    facing = 0.1 * (W - 1 - columns())  # rises towards -x: faces +x
    away = 0.1 * columns()
    colour = grey(0.5)
    lit = lighting.bump_lighting(colour, facing, azimuth=0.0, elevation=math.radians(35), specular=specular)
    dark = lighting.bump_lighting(colour, away, azimuth=0.0, elevation=math.radians(35), specular=specular)
    assert np.all(lit > 0.5 + 0.05) and np.all(dark < 0.5 - 0.05)


def test_bump_light_from_the_top():
    facing_up = 0.1 * rows()  # rises towards the image bottom: faces the top of the image
    top = lighting.bump_lighting(grey(0.5), facing_up, azimuth=-math.pi / 2, elevation=math.radians(35))
    bottom = lighting.bump_lighting(grey(0.5), facing_up, azimuth=math.pi / 2, elevation=math.radians(35))
    assert np.all(top > 0.55) and np.all(bottom < 0.45)


def test_bump_rejects_a_light_below_the_canvas():
    with pytest.raises(ParameterError, match="elevation"):
        lighting.bump_lighting(grey(0.5), np.zeros((H, W), np.float32), 0.0, 0.0)


def test_unknown_model():
    with pytest.raises(ParameterError) as info:
        lighting.light("moon", grey(0.5), np.zeros((H, W), np.float32))
    assert str(info.value) == "Unknown lighting model 'moon'; choose paper, directional or bump."


def test_light_dispatches_with_defaults():
    rng = np.random.default_rng(2)
    colour = rng.random((H, W, 3), dtype=np.float32)
    h = rng.random((H, W), dtype=np.float32)
    o = rng.random((H, W), dtype=np.float32) * np.float32(math.pi)
    np.testing.assert_array_equal(lighting.light("paper", colour, h, o), lighting.paper_lighting(colour, h, o))
    np.testing.assert_array_equal(lighting.light("directional", colour, h, azimuth=0.3),
                                  lighting.directional_lighting(colour, h, 0.3))
    np.testing.assert_array_equal(lighting.light("bump", colour, h, azimuth=0.3, elevation=0.6, strength=2.0),
                                  lighting.bump_lighting(colour, h, 0.3, 0.6, relief=2.0))


# ---------------------------------------------------------------------------
# python -m core light


@pytest.fixture(scope="module")
def painted(tmp_path_factory, half_textured):
    """A folder written by ``python -m core paint`` for a small photograph-like image."""
    source = tmp_path_factory.mktemp("input") / "small.png"
    writing.write_png(source, half_textured(40, 56, seed=7))
    out = tmp_path_factory.mktemp("painted")
    assert main(["paint", str(source), "-o", str(out), "-q"]) == 0
    return out


@pytest.mark.parametrize("model", lighting.MODELS)
def test_light_cli_writes_each_model(painted, model):
    assert main(["light", str(painted), "--model", model, "-q"]) == 0
    lit = reading.read_image(painted / f"lit_{model}.png")
    assert lit.shape == (40, 56, 3)
    if model == "paper":
        # The same as the lit_paper.png `paint` wrote, up to the EXR round trip and 8-bit rounding.
        np.testing.assert_allclose(lit, reading.read_image(painted / "lit_paper.png"), atol=2.5 / 255)


def test_light_cli_options(painted):
    assert main(["light", str(painted), "--model", "bump", "--azimuth", "0", "--elevation", "20",
                 "--strength", "8", "-q"]) == 0
    assert main(["light", str(painted), "--model", "directional", "--azimuth", "-45.5", "--strength", "0.5",
                 "-q"]) == 0


def partial(painted, tmp_path, names):
    folder = tmp_path / "partial"
    folder.mkdir()
    for name in names:
        shutil.copy(painted / name, folder / name)
    return folder


@pytest.mark.parametrize("case, words", [
    ("model", "Unknown lighting model 'moon'"),
    ("no folder", "does not exist"),
    ("no height", "height.exr is missing"),
    ("no orientation", "orientation.exr is missing"),
    ("azimuth", "--azimuth"),
    ("elevation", "--elevation"),
    ("strength", "--strength"),
    ("negative strength", "--strength"),
])
def test_light_cli_bad_input(painted, tmp_path, capsys, case, words):
    folder, options = painted, ["--model", "bump"]
    if case == "model":
        options = ["--model", "moon"]
    elif case == "no folder":
        folder = tmp_path / "nowhere"
    elif case == "no height":
        folder = partial(painted, tmp_path, ["color.exr", "orientation.exr"])
    elif case == "no orientation":
        folder, options = partial(painted, tmp_path, ["color.exr", "height.exr"]), ["--model", "paper"]
    elif case == "azimuth":
        options += ["--azimuth", "north"]
    elif case == "elevation":
        options += ["--elevation", "0"]
    elif case == "strength":
        options += ["--strength", "lots"]
    else:
        options += ["--strength", "-1"]
    before = sorted(p.name for p in folder.iterdir()) if folder.exists() else None
    assert main(["light", str(folder)] + options + ["-q"]) != 0
    assert words in one_sentence(capsys.readouterr().err)
    if before is not None:
        assert sorted(p.name for p in folder.iterdir()) == before
