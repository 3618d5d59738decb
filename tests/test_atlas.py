"""Several sources of one mesh, UDIM tiles and several materials, painted as one texture, the atlas (ALGORITHM §10):
each face painted from its own source and tile, wrapped UVs, each cell's maps, strokes across tile borders."""

import json

import numpy as np
import pytest
from oracles import one_sentence_run
from seam_meshes import baked
from test_apron import ratio
from test_surface_mesh import TWO_ISLANDS, command

from core import api
from core.colour import srgb_to_linear
from core.errors import InputError
from core.files.export import PAINTING_FILES, write_painting
from core.files.reading import read_exr
from core.files.writing import write_png
from core.params import Params
from core.surface.atlas import Cell, build_atlas, triangle_atlas_uv
from core.surface.islands import NO_ISLAND, uv_islands
from core.surface.mesh import SurfaceMesh, check_mesh, read_obj
from core.surface.seams import bilinear, texture_steps
from core.surface.texture import paint_texture, square_texture, surface_layout

TILE = 64
STROKES = (120.0, 60.0, 30.0)


def grid(u0: float, u1: float, v0: float, v1: float, cells_u: int, cells_v: int, x0: float = 0.0,
         metres_per_uv: float = 1.0) -> SurfaceMesh:
    """A flat grid of quads (two triangles each) over UV u0..u1 x v0..v1, at x = x0 + (u - u0) m, y = (v - v0) m
    times ``metres_per_uv``, z = 0."""
    us, vs = np.linspace(u0, u1, cells_u + 1), np.linspace(v0, v1, cells_v + 1)
    uvs, positions = [], []
    for a in range(cells_u):
        for b in range(cells_v):
            quad = [(us[a], vs[b]), (us[a + 1], vs[b]), (us[a + 1], vs[b + 1]), (us[a], vs[b + 1])]
            for triangle in ((0, 1, 2), (0, 2, 3)):
                uvs.append([quad[k] for k in triangle])
                positions.append([(x0 + metres_per_uv * (quad[k][0] - u0), metres_per_uv * (quad[k][1] - v0), 0.0)
                                  for k in triangle])
    return SurfaceMesh(np.array(uvs), np.array(positions))


def blocks(seed: int, size: int = TILE) -> np.ndarray:
    """A random (size, size, 3) sRGB picture of 8 x 8 flat blocks."""
    coarse = np.random.default_rng(seed).random((8, 8, 3))
    return np.repeat(np.repeat(coarse, size // 8, axis=0), size // 8, axis=1)


def cell_colour(folder, name: str) -> np.ndarray:
    """(H, W, 3) scene-linear colour of the map ``name`` in ``folder``."""
    return read_exr(folder / name)[0][..., :3]


def correlation(a: np.ndarray, b: np.ndarray) -> float:
    """The correlation of (S, 3) colours ``a`` and ``b`` over samples and channels, each channel's mean removed."""
    return float(np.corrcoef((a - a.mean(axis=0)).ravel(), (b - b.mean(axis=0)).ravel())[0, 1])


def centres(mesh: SurfaceMesh) -> np.ndarray:
    """(T, 2): each triangle's UV centroid wrapped into its unit square."""
    centre = mesh.uv.mean(axis=1)
    return centre - np.floor(centre)


@pytest.fixture(scope="module")
def two_tiles(tmp_path_factory):
    """A 2 m x 1 m plane over UDIM tiles 1001 (u 0..1) and 1002 (u 1..2), each tile a picture of its own, painted
    with normal maps: (folder, mesh, tile pictures {1001: .., 1002: ..}, report)."""
    folder = tmp_path_factory.mktemp("tiles")
    pictures = {1001: blocks(1), 1002: blocks(2)}
    for tile, picture in pictures.items():
        write_png(folder / f"paint.{tile}.png", picture, bits=16)
    mesh = grid(0.0, 2.0, 0.0, 1.0, 16, 8)
    report = api.paint_object(str(folder / "paint.<UDIM>.png"), mesh, folder / "out", Params(seed=2), TILE,
                              STROKES, normal_map=True)
    return folder / "out", mesh, pictures, report


def test_each_udim_tile_s_faces_are_painted_from_their_own_tile_and_not_the_other(two_tiles):
    out, mesh, pictures, _ = two_tiles
    uv = centres(mesh)
    tile = 1001 + np.floor(mesh.uv.mean(axis=1)[:, 0]).astype(int)
    for own, other in ((1001, 1002), (1002, 1001)):
        faces = tile == own
        painted = bilinear(cell_colour(out, f"color.s0.{own}.exr"), uv[faces])
        assert correlation(painted, bilinear(srgb_to_linear(pictures[own]), uv[faces])) >= 0.7
        assert abs(correlation(painted, bilinear(srgb_to_linear(pictures[other]), uv[faces]))) < 0.3


def test_each_cell_s_maps_are_named_for_its_source_and_tile_and_equal_its_region_of_the_atlas(two_tiles):
    out, mesh, _, report = two_tiles
    atlas = report["atlas"]
    assert (atlas["columns"], atlas["rows"], atlas["tile_texels"]) == (2, 2, TILE)
    assert [(c["source"], c["tile"], c["column"], c["row"]) for c in atlas["cells"]] == [(0, 1001, 0, 0),
                                                                                        (0, 1002, 1, 0)]
    assert atlas["cells"][1]["path"].endswith("paint.1002.png")
    whole = {name: read_exr(out / f"{name}.exr")[0] for name in ("color", "height", "opacity")}
    assert whole["color"].shape[:2] == (2 * TILE, 2 * TILE)
    for cell in atlas["cells"]:
        suffix = f".s0.{cell['tile']}"
        assert cell["files"] == {name: f"{name}{suffix}.exr" for name in ("color", "height", "opacity", "normal")}
        for name in ("color", "height", "opacity"):
            part = read_exr(out / cell["files"][name])[0]
            assert part.shape[:2] == (TILE, TILE)
            region = whole[name][cell["row"] * TILE:(cell["row"] + 1) * TILE,
                                 cell["column"] * TILE:(cell["column"] + 1) * TILE]
            assert np.array_equal(part, region)
        assert read_exr(out / cell["files"]["normal"])[0].shape == (TILE, TILE, 3)
        assert set(cell["files"].values()) <= set(report["files"])
    assert json.loads((out / "report.json").read_text())["atlas"] == atlas


def test_the_atlas_uv_from_the_report_puts_each_face_in_its_cell(two_tiles):
    """Tile 1001 in the top-left quarter of the atlas, 1002 in the top-right: u / 2 and v / 2 + 1 / 2."""
    _, mesh, _, report = two_tiles
    atlas_uv = triangle_atlas_uv(mesh.uv, None, [True], report["atlas"])
    wrapped = mesh.uv - np.floor(mesh.uv.mean(axis=1))[:, None, :]
    left = mesh.uv.mean(axis=1)[:, 0] < 1
    expected = np.where(left[:, None, None], wrapped / 2 + [0.0, 0.5], wrapped / 2 + [0.5, 0.5])
    assert np.allclose(atlas_uv, expected)
    assert np.array_equal(atlas_uv, build_atlas(mesh.uv, None, [True]).uv)
    assert np.array_equal(triangle_atlas_uv(mesh.uv, None, None, report["atlas"]), atlas_uv)


def test_a_missing_tile_is_one_sentence_naming_its_file_and_nothing_is_written(tmp_path):
    write_png(tmp_path / "paint.1001.png", blocks(1))
    with pytest.raises(InputError) as error:
        api.paint_object(str(tmp_path / "paint.<UDIM>.png"), grid(0.0, 2.0, 0.0, 1.0, 4, 2), tmp_path / "out",
                         Params(seed=1), TILE, STROKES)
    message = str(error.value)
    assert message == f"The UDIM tile {tmp_path / 'paint.1002.png'} that the mesh's UV map uses does not exist."
    assert not (tmp_path / "out").exists()


def test_a_plain_source_repeats_so_v_in_minus_one_to_zero_paints_the_bytes_of_v_in_zero_to_one(tmp_path):
    """A glTF mesh's v runs from -1 to 0 where Blender's runs from 0 to 1; dyadic UVs, so v - 1 + 1 is v."""
    write_png(tmp_path / "paint.png", blocks(4), bits=16)
    mesh = grid(0.125, 0.875, 0.125, 0.875, 6, 6)
    below = SurfaceMesh(mesh.uv - [0.0, 1.0], mesh.position)
    api.paint_object(tmp_path / "paint.png", mesh, tmp_path / "up", Params(seed=3), TILE, STROKES)
    report = api.paint_object(tmp_path / "paint.png", below, tmp_path / "down", Params(seed=3), TILE, STROKES)
    for name in ("color.exr", "height.exr", "opacity.exr"):
        assert (tmp_path / "up" / name).read_bytes() == (tmp_path / "down" / name).read_bytes()
    assert len(report["atlas"]["cells"]) == 1


def test_one_cell_writes_no_cell_maps_and_the_bytes_of_the_texture_painted_alone(tmp_path):
    write_png(tmp_path / "paint.png", blocks(5), bits=16)
    (tmp_path / "two.obj").write_text(TWO_ISLANDS)
    report = api.paint_object(tmp_path / "paint.png", tmp_path / "two.obj", tmp_path / "out", Params(seed=4), TILE,
                              STROKES)
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == sorted(PAINTING_FILES)
    assert report["atlas"] == {"columns": 1, "rows": 1, "tile_texels": TILE, "cells": [
        {"source": 0, "path": str(tmp_path / "paint.png"), "tile": None, "column": 0, "row": 0, "extension": "REPEAT",
         "files": {"color": "color.exr", "height": "height.exr", "opacity": "opacity.exr"}}]}
    from core.files.reading import read_image
    mesh = read_obj(tmp_path / "two.obj")
    alone = paint_texture(square_texture(read_image(tmp_path / "paint.png"), TILE),
                          surface_layout(mesh, TILE, across_seams=False), Params(seed=4), STROKES)
    (tmp_path / "alone").mkdir()
    write_painting(tmp_path / "alone", alone, "paint.png")
    for name in ("color.exr", "height.exr", "opacity.exr"):
        assert (tmp_path / "out" / name).read_bytes() == (tmp_path / "alone" / name).read_bytes()


def two_materials() -> SurfaceMesh:
    """Two 1 m squares side by side, both over UV 0.1..0.9 (each its own material): source 0 left, 1 right."""
    left, right = grid(0.1, 0.9, 0.1, 0.9, 8, 8, 0.0, 1.25), grid(0.1, 0.9, 0.1, 0.9, 8, 8, 1.0, 1.25)
    return SurfaceMesh(np.concatenate([left.uv, right.uv]), np.concatenate([left.position, right.position]),
                       np.repeat([0, 1], len(left.uv)))


def test_two_sources_on_two_halves_paint_each_half_from_its_own_the_same_bytes_twice(tmp_path):
    pictures = [blocks(6), blocks(7)]
    for k, picture in enumerate(pictures):
        write_png(tmp_path / f"m{k}.png", picture, bits=16)
    paths = [tmp_path / "m0.png", tmp_path / "m1.png"]
    mesh = two_materials()
    report = api.paint_object(paths, mesh, tmp_path / "out", Params(seed=5), TILE, STROKES)
    api.paint_object(paths, mesh, tmp_path / "again", Params(seed=5), TILE, STROKES)
    assert [(c["source"], c["tile"], c["files"]["color"]) for c in report["atlas"]["cells"]] == [
        (0, None, "color.s0.exr"), (1, None, "color.s1.exr")]
    assert report["input"] == str((tmp_path / "out" / "source.png").resolve())
    uv = centres(mesh)[: len(mesh.uv) // 2]
    for k in (0, 1):
        painted = bilinear(cell_colour(tmp_path / "out", f"color.s{k}.exr"), uv)
        assert correlation(painted, bilinear(srgb_to_linear(pictures[k]), uv)) >= 0.7
        assert abs(correlation(painted, bilinear(srgb_to_linear(pictures[1 - k]), uv))) < 0.3
    names = [name for name in report["files"]] + ["report.json", "source.png"]
    assert sorted(p.name for p in (tmp_path / "again").iterdir()) == sorted(names)
    for name in report["files"]:
        assert (tmp_path / "out" / name).read_bytes() == (tmp_path / "again" / name).read_bytes()


def test_a_strip_over_two_tiles_painted_across_seams_runs_on_over_the_tile_border():
    """One continuous picture over a 2 m strip split at u = 1 between tiles 1001 and 1002: the tile border is a seam
    (two islands, the edges there sampled as seams) and painted across seams the texture steps there, against its
    inner edges, about as its source does; its islands painted apart step more."""
    mesh = grid(0.0, 2.0, 0.1, 0.9, 16, 6, metres_per_uv=0.5)
    atlas = build_atlas(mesh.uv, None, [True])
    assert [(c.tile, c.column, c.row) for c in atlas.cells] == [(1001, 0, 0), (1002, 1, 0)]
    flat = SurfaceMesh(atlas.uv, mesh.position)
    size = 2 * 128
    assert uv_islands(flat.uv).max() == 1 and uv_islands(flat.uv, atlas.cell).max() == 2
    source = baked(flat, size)
    across = surface_layout(flat, size, True, atlas)
    apart = surface_layout(flat, size, False, atlas)
    assert across.edges.edges[0] > 0 and (across.charts.neighbour != NO_ISLAND).sum() > 0
    own = ratio(texture_steps(source, across.edges))
    painted = paint_texture(source, across, Params(seed=6), (60.0, 30.0, 15.0))
    alone = paint_texture(source, apart, Params(seed=6), (60.0, 30.0, 15.0))
    assert ratio(texture_steps(painted.colour, across.edges)) < 1.25 * own
    assert ratio(texture_steps(alone.colour, across.edges)) > 1.3 * own


def test_a_mesh_s_sources_are_checked_and_read_from_an_obj_file_s_materials(tmp_path):
    with pytest.raises(InputError, match="must give each of its 1 triangles a source image"):
        check_mesh(SurfaceMesh(np.zeros((1, 3, 2)), np.zeros((1, 3, 3)), np.array([-1])), "given")
    assert check_mesh(SurfaceMesh(np.zeros((1, 3, 2)), np.zeros((1, 3, 3))), "given").source is None
    text = TWO_ISLANDS.replace("f 1/1/1", "usemtl wood\nf 1/1/1").replace("f -4/-4", "usemtl stone\nf -4/-4")
    (tmp_path / "two.obj").write_text(text + "usemtl wood\nf 1/1 2/2 3/3\n")
    assert read_obj(tmp_path / "two.obj").source.tolist() == [0, 0, 1, 1, 0]
    (tmp_path / "first.obj").write_text(TWO_ISLANDS.replace("f -4/-4", "usemtl stone\nf -4/-4"))
    assert read_obj(tmp_path / "first.obj").source.tolist() == [0, 0, 0, 0]
    (tmp_path / "plain.obj").write_text(TWO_ISLANDS)
    assert read_obj(tmp_path / "plain.obj").source is None


def test_triangle_atlas_uv_refuses_a_face_whose_cell_the_atlas_lacks():
    atlas = {"columns": 2, "rows": 2, "cells": [{"source": 0, "tile": None, "column": 0, "row": 0}]}
    with pytest.raises(InputError, match="no cell of source 1"):
        triangle_atlas_uv(np.full((1, 3, 2), 0.5), np.array([1]), [False, False], atlas)
    assert Cell(0, None, 0, 0).tile is None


def test_core_object_paints_one_texture_for_each_material_and_refuses_a_missing_tile_with_exit_2(tmp_path):
    text = TWO_ISLANDS.replace("f 1/1/1", "usemtl a\nf 1/1/1").replace("f -4/-4", "usemtl b\nf -4/-4")
    (tmp_path / "two.obj").write_text(text)
    write_png(tmp_path / "a.png", blocks(8))
    write_png(tmp_path / "b.1001.png", blocks(9))
    run = command(tmp_path / "a.png", tmp_path / "b.<UDIM>.png", "--mesh", tmp_path / "two.obj", "-o",
                  tmp_path / "out", "--texture-size", TILE, "--stroke-mm", "80,40")
    assert run.returncode == 0, run.stderr
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    assert [(c["source"], c["tile"]) for c in report["atlas"]["cells"]] == [(0, None), (1, 1001)]
    assert (tmp_path / "out" / "color.s1.1001.exr").is_file() and (tmp_path / "out" / "source.png").is_file()
    (tmp_path / "far.obj").write_text(text.replace("vt 0.6 0.6\nvt 0.85 0.6\nvt 0.85 0.85\nvt 0.6 0.85",
                                                   "vt 1.6 0.6\nvt 1.85 0.6\nvt 1.85 0.85\nvt 1.6 0.85"))
    run = command(tmp_path / "a.png", tmp_path / "b.<UDIM>.png", "--mesh", tmp_path / "far.obj", "-o",
                  tmp_path / "far", "--texture-size", TILE)
    assert run.returncode == 2
    assert one_sentence_run(run).endswith(f"The UDIM tile {tmp_path / 'b.1002.png'} that the mesh's UV map uses "
                                          f"does not exist.")
    assert not (tmp_path / "far").exists()


def test_a_cell_s_triangles_and_bleed_stay_in_its_cell():
    """Source 0: a square over u 0.5..1 and a triangle reaching u 1.3 (its centroid at u 0.9: in the square 0..1);
    source 1: a square over u 0.5..0.9. In the atlas (cells side by side) no texel of cell 1 shows source 0's
    islands, and cell 1's texels beside the border, far from its own island, take no bleed from cell 0's."""
    own = grid(0.5, 1.0, 0.25, 0.75, 2, 2)
    reaching = SurfaceMesh(np.array([[[0.7, 0.3], [1.3, 0.5], [0.7, 0.7]]]), np.array([[[3, 0, 0], [3.6, 0.2, 0],
                                                                                        [3, 0.4, 0]]], float))
    other = grid(0.5, 0.9, 0.25, 0.75, 2, 2, x0=5.0)
    mesh = SurfaceMesh(np.concatenate([own.uv, reaching.uv, other.uv]),
                       np.concatenate([own.position, reaching.position, other.position]),
                       np.repeat([0, 0, 1], [len(own.uv), 1, len(other.uv)]))
    atlas = build_atlas(mesh.uv, mesh.source, [False, False])
    size = 2 * TILE
    layout = surface_layout(SurfaceMesh(atlas.uv, mesh.position), size, False, atlas)
    first = set(np.unique(uv_islands(atlas.uv, atlas.cell)[mesh.source == 0]).tolist())
    assert not set(np.unique(layout.islands[:TILE, TILE:]).tolist()) & first
    picture = np.concatenate([np.concatenate([blocks(10), blocks(11)], axis=1)] * 2, axis=0).astype(np.float32)
    painted = paint_texture(picture, layout, Params(seed=7), STROKES)
    beside = painted.opacity[:TILE, TILE:TILE + 8]             # cell 1's first 8 columns: its island starts at 32
    assert painted.opacity[:TILE, TILE - 2:TILE].max() > 0 and np.all(beside == 0)
