"""A source's rule beyond the UV square 0..1, as Blender's Image Texture node's extension (ALGORITHM §10, the
atlas): REPEAT and MIRROR paint a face where the repeated image shows it, CLIP and EXTEND only its part inside."""

import json
from fractions import Fraction

import numpy as np
import pytest
from oracles import one_sentence_run
from test_atlas import STROKES, TILE, blocks, grid
from test_surface_mesh import TWO_ISLANDS, command

from core import api
from core.errors import InputError, ParameterError
from core.files.reading import read_exr
from core.files.writing import write_png
from core.params import Params
from core.surface.atlas import build_atlas, checked_extensions, triangle_atlas_uv
from core.surface.islands import NO_ISLAND
from core.surface.mesh import SurfaceMesh
from core.surface.texture import surface_layout

SIZE = 10
"""Texels a side of the island maps worked out by hand: texel (r, c) has its centre at u = (c + 1/2) / 10,
v = 1 - (r + 1/2) / 10."""


def expected_texels(corners, size: int = SIZE) -> np.ndarray:
    """(size, size) bool: the texels whose centre lies strictly inside the triangle ``corners`` (three (u, v) given
    as decimal strings), in exact rational arithmetic; asserts that no centre lies on an edge, where rounding would
    decide."""
    points = [(Fraction(u), Fraction(v)) for u, v in corners]
    out = np.zeros((size, size), bool)
    for r in range(size):
        for c in range(size):
            u, v = Fraction(2 * c + 1, 2 * size), 1 - Fraction(2 * r + 1, 2 * size)
            sides = [(q[0] - p[0]) * (v - p[1]) - (q[1] - p[1]) * (u - p[0])
                     for p, q in zip(points, points[1:] + points[:1], strict=True)]
            assert all(side != 0 for side in sides)
            out[r, c] = all(side > 0 for side in sides) or all(side < 0 for side in sides)
    return out


def covered(corners, rule: str) -> np.ndarray:
    """(SIZE, SIZE) bool: the texels the island map of the one triangle ``corners`` covers under ``rule``."""
    uv = np.array([[[float(Fraction(u)), float(Fraction(v))] for u, v in corners]])
    position = np.array([[[float(Fraction(u)), float(Fraction(v)), 0.0] for u, v in corners]])
    atlas = build_atlas(uv, None, [False], [rule])
    return surface_layout(SurfaceMesh(atlas.uv, position), SIZE, False, atlas).islands != NO_ISLAND


FAR = (("1.2", "0.2"), ("1.8", "0.2"), ("1.2", "0.7"))
"""A triangle over u 1.2..1.8, in the unit square right of 0..1."""
BACK = (("0.2", "0.2"), ("0.8", "0.2"), ("0.2", "0.7"))
"""The same triangle moved back by one in u."""


def test_a_triangle_at_u_1_2_to_1_8_is_painted_at_0_2_to_0_8_under_repeat_and_nowhere_under_clip_or_extend():
    at_home = expected_texels(BACK)
    assert at_home.sum() == 15      # rows of v 0.25, 0.35, .., 0.65 hold 5, 4, 3, 2, 1 centres of u from 0.25
    assert np.array_equal(covered(FAR, "REPEAT"), at_home)
    assert not covered(FAR, "CLIP").any()
    assert not covered(FAR, "EXTEND").any()


def test_under_mirror_a_triangle_in_an_odd_unit_square_is_painted_mirrored_in_u():
    """u 1.2..1.8 lies in the square of floor u 1, where the mirrored image shows u - 1 as 1 - (u - 1)."""
    mirrored = (("0.8", "0.2"), ("0.2", "0.2"), ("0.8", "0.7"))
    assert np.array_equal(covered(FAR, "MIRROR"), expected_texels(mirrored))
    assert np.array_equal(covered(FAR, "MIRROR"), covered(FAR, "REPEAT")[:, ::-1])
    below = tuple((u, str(Fraction(v) - 2)) for u, v in BACK)     # floor v = -2: even, not mirrored
    assert np.array_equal(covered(below, "MIRROR"), expected_texels(BACK))


CROSSING = (("0.8", "0.2"), ("1.6", "0.2"), ("1.6", "0.8"))
"""A triangle over u 0.8..1.6, its centroid at u 1.33."""


def test_a_triangle_crossing_u_1_under_clip_paints_only_its_part_inside():
    inside = expected_texels(CROSSING)
    assert inside.any() and not inside[:, :8].any()             # columns 8 and 9: u 0.85 and 0.95
    assert np.array_equal(covered(CROSSING, "CLIP"), inside)
    assert np.array_equal(covered(CROSSING, "EXTEND"), inside)


def test_a_triangle_crossing_u_1_under_repeat_paints_both_parts_where_the_repeated_image_shows_them():
    """Texel p shows the surface at u p and p + 1: its part of u 0.8..1 at 0.8..1, its part of u 1..1.6 at 0..0.6."""
    moved = tuple((str(Fraction(u) - 1), v) for u, v in CROSSING)
    here, beyond = expected_texels(CROSSING), expected_texels(moved)
    assert here.any() and beyond.any() and not (here & beyond).any()
    assert np.array_equal(covered(CROSSING, "REPEAT"), here | beyond)


def test_a_triangle_crossing_u_1_under_mirror_paints_its_part_beyond_mirrored():
    """Mirrored, texel p shows the surface at u p and 2 - p: its part of u 1..1.6 at 0.4..1, over the part of u
    0.8..1 at 0.8..1."""
    mirrored = tuple((str(2 - Fraction(u)), v) for u, v in CROSSING)
    assert np.array_equal(covered(CROSSING, "MIRROR"), expected_texels(CROSSING) | expected_texels(mirrored))


def test_a_plane_at_u_1_to_2_paints_the_bytes_of_0_to_1_under_repeat_and_is_one_sentence_under_clip(tmp_path):
    write_png(tmp_path / "paint.png", blocks(12), bits=16)
    home = grid(0.125, 0.875, 0.125, 0.875, 6, 6)
    far = SurfaceMesh(home.uv + [1.0, 0.0], home.position)
    api.paint_object(tmp_path / "paint.png", home, tmp_path / "home", Params(seed=3), TILE, STROKES)
    report = api.paint_object(tmp_path / "paint.png", far, tmp_path / "far", Params(seed=3), TILE, STROKES,
                              extensions=["REPEAT"])
    for name in ("color.exr", "height.exr", "opacity.exr"):
        assert (tmp_path / "home" / name).read_bytes() == (tmp_path / "far" / name).read_bytes()
    assert report["atlas"]["cells"][0]["extension"] == "REPEAT"
    for rule in ("CLIP", "EXTEND", "clip"):
        with pytest.raises(InputError) as error:
            api.paint_object(tmp_path / "paint.png", far, tmp_path / rule, Params(seed=3), TILE, STROKES,
                             extensions=rule)
        assert str(error.value) == ("No face of the mesh covers a texel of the texture: its UV map is empty, or "
                                    "lies outside the square 0..1 where its image does not repeat (Clip or Extend).")
        assert not (tmp_path / rule).exists()


def test_a_plane_over_u_half_to_one_and_a_half_under_clip_paints_only_u_half_to_one(tmp_path):
    """Faces whose centroid lies beyond u 1 are painted at u 0..0.5 under REPEAT; under CLIP that part of the
    texture stays bare (opacity 0 farther than the bleed from u 0.5) and u 0.5..1 is painted."""
    write_png(tmp_path / "paint.png", blocks(13), bits=16)
    plane = grid(0.5, 1.5, 0.25, 0.75, 8, 4)
    clip = api.paint_object(tmp_path / "paint.png", plane, tmp_path / "clip", Params(seed=4), TILE, STROKES,
                            extensions=["CLIP"])
    api.paint_object(tmp_path / "paint.png", plane, tmp_path / "repeat", Params(seed=4), TILE, STROKES)
    bleed = int(np.ceil(clip["bleed_texels"]))
    left = slice(0, TILE // 2 - bleed - 1)
    rows = slice(TILE // 4 + 2, 3 * TILE // 4 - 2)
    clipped, repeated = (read_exr(tmp_path / k / "opacity.exr")[0][..., 0] for k in ("clip", "repeat"))
    assert np.all(clipped[:, left] == 0) and clipped[rows, TILE // 2 + 2:].min() > 0
    assert repeated[rows, left].min() > 0
    assert clip["atlas"]["cells"][0]["extension"] == "CLIP"
    atlas = build_atlas(plane.uv, None, [False], ["CLIP"])
    assert np.array_equal(triangle_atlas_uv(plane.uv, None, None, clip["atlas"]), atlas.uv)
    assert np.array_equal(atlas.uv, plane.uv)


def test_each_source_follows_its_own_rule_and_a_tiled_source_stays_udim():
    """Source 0 clipped, source 1 repeating, source 2 tiled and clipped in name only: its tile is found by u."""
    uv = np.array([[[1.2, 0.2], [1.8, 0.2], [1.2, 0.7]]] * 3)
    atlas = build_atlas(uv, np.array([0, 1, 2]), [False, False, True], ["CLIP", "REPEAT", "CLIP"])
    assert [(c.source, c.tile) for c in atlas.cells] == [(0, None), (1, None), (2, 1002)]
    local = atlas.uv * atlas.columns - np.array([[c.column, atlas.rows - 1 - c.row] for c in atlas.cells])[:, None]
    assert np.allclose(local[0], uv[0]) and np.allclose(local[1], uv[0] - [1, 0]) and np.allclose(local[2],
                                                                                                  uv[0] - [1, 0])


def test_extensions_are_checked_in_one_sentence():
    assert checked_extensions(None, 2) == ("REPEAT", "REPEAT")
    assert checked_extensions("clip", 2) == ("CLIP", "CLIP")
    assert checked_extensions(["Extend"], 3) == ("EXTEND",) * 3
    with pytest.raises(ParameterError, match="must be one of REPEAT, EXTEND, CLIP, MIRROR, got 'WRAP'"):
        checked_extensions(["WRAP"], 1)
    with pytest.raises(ParameterError, match="Give one extension for each of the 3 textures or one for all, got 2"):
        checked_extensions(["CLIP", "REPEAT"], 3)


def test_core_object_takes_an_extension_and_refuses_a_clipped_map_beyond_the_square_with_exit_2(tmp_path):
    far = TWO_ISLANDS
    for line in [line for line in TWO_ISLANDS.splitlines() if line.startswith("vt ")]:
        u, v = line.split()[1:3]
        far = far.replace(line, f"vt {float(u) + 1} {v}")
    (tmp_path / "far.obj").write_text(far)
    write_png(tmp_path / "a.png", blocks(14))
    run = command(tmp_path / "a.png", "--mesh", tmp_path / "far.obj", "-o", tmp_path / "repeat", "--texture-size",
                  TILE, "--stroke-mm", "80,40", "--extension", "REPEAT")
    assert run.returncode == 0, run.stderr
    assert json.loads((tmp_path / "repeat" / "report.json").read_text())["atlas"]["cells"][0]["extension"] == "REPEAT"
    run = command(tmp_path / "a.png", "--mesh", tmp_path / "far.obj", "-o", tmp_path / "clip", "--texture-size",
                  TILE, "--stroke-mm", "80,40", "--extension", "clip")
    assert run.returncode == 2
    assert one_sentence_run(run).endswith("No face of the mesh covers a texel of the texture: its UV map is empty, "
                                          "or lies outside the square 0..1 where its image does not repeat (Clip or "
                                          "Extend).")
    assert not (tmp_path / "clip").exists()
    run = command(tmp_path / "a.png", "--mesh", tmp_path / "far.obj", "-o", tmp_path / "bad", "--extension", "WRAP")
    assert run.returncode == 2 and "must be one of REPEAT, EXTEND, CLIP, MIRROR" in run.stderr


def test_one_face_over_u_quarter_to_one_and_a_quarter_under_repeat_paints_every_column(tmp_path):
    """Both triangles of the quad cross u 1; repeated, the texture's rows of v 0.25..0.75 show the face at every u
    (u 0.25..1 and, past u 1, 0..0.25), so every texel there is painted; clipped, only u 0.25..1 is."""
    write_png(tmp_path / "paint.png", blocks(15), bits=16)
    quad = grid(0.25, 1.25, 0.25, 0.75, 1, 1)
    rows = slice(TILE // 4 + 1, 3 * TILE // 4 - 1)
    for rule in ("REPEAT", "CLIP"):
        api.paint_object(tmp_path / "paint.png", quad, tmp_path / rule, Params(seed=6), TILE, STROKES,
                         extensions=rule)
    repeated, clipped = (read_exr(tmp_path / rule / "opacity.exr")[0][rows, :, 0] for rule in ("REPEAT", "CLIP"))
    assert repeated.min() > 0
    assert clipped[:, TILE // 4 + 1:].min() > 0 and clipped[:, :TILE // 8].max() == 0
