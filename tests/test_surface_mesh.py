"""A mesh read from a Wavefront OBJ file for the texture painter, and the `core object` command (ALGORITHM §10)."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from oracles import one_sentence_run

from core.errors import InputError
from core.files.writing import write_png
from core.surface.mesh import SurfaceMesh, check_mesh, read_obj

ROOT = Path(__file__).resolve().parents[1]

TWO_ISLANDS = """# island 1: a 1 m square over UV 0.05..0.55; island 2: a 2 m square over UV 0.6..0.85
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 3 0 0
v 5 0 0
v 5 2 0
v 3 2 0
vt 0.05 0.05
vt 0.55 0.05
vt 0.55 0.55
vt 0.05 0.55
vt 0.6 0.6
vt 0.85 0.6
vt 0.85 0.85
vt 0.6 0.85
vn 0 0 1
f 1/1/1 2/2/1 3/3/1 4/4/1
f -4/-4 -3/-3 -2/-2 -1/-1
"""


def test_an_obj_file_gives_its_polygons_as_fans_of_triangles_with_their_uvs_and_positions(tmp_path):
    path = tmp_path / "two.obj"
    path.write_text(TWO_ISLANDS)
    mesh = read_obj(path)
    assert mesh.uv.shape == (4, 3, 2) and mesh.position.shape == (4, 3, 3)
    assert mesh.uv[0].tolist() == [[0.05, 0.05], [0.55, 0.05], [0.55, 0.55]]
    assert mesh.uv[1].tolist() == [[0.05, 0.05], [0.55, 0.55], [0.05, 0.55]]
    assert mesh.position[3].tolist() == [[3, 0, 0], [5, 2, 0], [3, 2, 0]]         # negative indices: the last read
    pentagon = "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0.5 1\nvt 0 1\n" \
               "f 1/1 2/2 3/3 4/4 5/5\n"
    path.write_text(pentagon)
    assert len(read_obj(path).uv) == 3


@pytest.mark.parametrize("text, problem", [
    ("v 0 0\nvt 0 0\nf 1/1 1/1 1/1\n", "line 1: a position needs three numbers"),
    ("v 0 0 0\nvt 0 zero\n", "line 2: a UV needs two numbers"),
    ("v 0 0 0\nvt 0 0\nf 1/1 2/1 1/1\n", "line 3: the face's position index 2 points to none of the 1 read so far"),
    ("v 0 0 0\nvt 0 0\nf 1/1 1/1\n", "line 3: a face needs three corners"),
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "has faces without texture coordinates: unwrap it (a UV map) first"),
    ("v 0 0 0\nvt 0 0\n", "has no faces to paint"),
])
def test_an_obj_file_that_cannot_be_painted_is_one_sentence_naming_it(tmp_path, text, problem):
    path = tmp_path / "bad.obj"
    path.write_text(text)
    with pytest.raises(InputError) as refused:
        read_obj(path)
    assert str(refused.value).startswith(f"The mesh {path} ") and problem in str(refused.value)
    with pytest.raises(InputError, match="does not exist"):
        read_obj(tmp_path / "none.obj")


def test_a_mesh_of_arrays_that_do_not_fit_is_one_sentence():
    with pytest.raises(InputError, match=r"three UV points and three positions for each triangle"):
        check_mesh(SurfaceMesh(np.zeros((2, 3, 2)), np.zeros((3, 3, 3))), "given")
    with pytest.raises(InputError, match="not a finite number"):
        check_mesh(SurfaceMesh(np.full((1, 3, 2), np.nan), np.zeros((1, 3, 3))), "given")


def command(*arguments) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "core", "object", *map(str, arguments), "-q"], cwd=ROOT,
                          capture_output=True, text=True, timeout=600)


def test_core_object_writes_the_texture_s_maps_and_each_island_s_statistics(tmp_path):
    (tmp_path / "two.obj").write_text(TWO_ISLANDS)
    rng = np.random.default_rng(5)
    write_png(tmp_path / "texture.png", np.repeat(np.repeat(rng.random((8, 8, 3)), 12, 0), 12, 1), bits=16)
    run = command(tmp_path / "texture.png", "--mesh", tmp_path / "two.obj", "-o", tmp_path / "out",
                  "--texture-size", 128, "--stroke-mm", "80,40,20")
    assert run.returncode == 0, run.stderr
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    assert report["width"] == report["height"] == 128 and report["stroke_mm"] == [80.0, 40.0, 20.0]
    assert (report["method"], report["layout"]) == ("huang11", "paper")
    first, second = report["islands"]
    assert (first["density_m_per_uv"], second["density_m_per_uv"]) == (2.0, 8.0)
    assert (first["sizes_texels"], second["sizes_texels"]) == ([5, 3, 2], [2])       # 15.625 and 62.5 mm texels
    assert report["seam_steps"]["edges"] == {"seam": 0, "inner": 2}                  # apart in 3-D: two diagonals
    assert report["seam_steps"]["offset_mm"] == 125.0                                # 2 of the coarser texels
    assert sorted(report["files"]) == ["color.exr", "height.exr", "lit_paper.png", "opacity.exr",
                                       "orientation.exr", "painting.png", "strokes.json"]


def test_core_object_refuses_a_mesh_without_uvs_in_one_sentence_and_writes_nothing(tmp_path):
    (tmp_path / "flat.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    write_png(tmp_path / "texture.png", np.full((16, 16, 3), 0.5))
    run = command(tmp_path / "texture.png", "--mesh", tmp_path / "flat.obj", "-o", tmp_path / "out")
    assert run.returncode == 2
    assert one_sentence_run(run).endswith("has faces without texture coordinates: unwrap it (a UV map) first.")
    assert not (tmp_path / "out").exists()
    run = command(tmp_path / "texture.png", "--mesh", tmp_path / "flat.obj", "-o", tmp_path / "out",
                  "--texture-size", 20000)
    assert "The texture size must be a whole number of texels from 64 to 16384, got 20000." in run.stderr


def test_a_kept_source_is_committed_with_the_maps_and_named_as_the_input(tmp_path):
    from core import api
    from core.params import Params

    (tmp_path / "two.obj").write_text(TWO_ISLANDS)
    write_png(tmp_path / "scratch.png", np.random.default_rng(2).random((64, 64, 3)))
    report = api.paint_object(tmp_path / "scratch.png", tmp_path / "two.obj", tmp_path / "out", Params(seed=1), 64,
                              (80, 40), keep_source=True)
    kept = tmp_path / "out" / "source.png"
    assert kept.read_bytes() == (tmp_path / "scratch.png").read_bytes()
    assert report["input"] == str(kept.resolve())
    assert json.loads((tmp_path / "out" / "report.json").read_text())["input"] == str(kept.resolve())


OBJECT_METHOD = "Objects are painted with the paper's method (Huang 2011, huang11); Hertzmann 1998 (hertzmann98) " \
                "paints still images only."


def test_an_object_with_hertzmann_1998_is_refused_in_one_sentence_before_anything_is_written(tmp_path):
    from core import api
    from core.errors import ParameterError
    from core.params import Params
    from core.surface.texture import paint_texture, surface_layout

    (tmp_path / "two.obj").write_text(TWO_ISLANDS)
    write_png(tmp_path / "texture.png", np.random.default_rng(2).random((64, 64, 3)))
    with pytest.raises(ParameterError) as caught:
        api.paint_object(tmp_path / "texture.png", tmp_path / "two.obj", tmp_path / "out",
                         Params(method="hertzmann98"), 64)
    assert str(caught.value) == OBJECT_METHOD
    with pytest.raises(ParameterError) as caught:
        api.paint_object(tmp_path / "texture.png", tmp_path / "two.obj", tmp_path / "out",
                         Params(layout="hertzmann98"), 64)
    assert str(caught.value) == ("Objects are painted with the paper's layout; the layout hertzmann98 paints still "
                                 "images only.")
    assert not (tmp_path / "out").exists()
    layout = surface_layout(read_obj(tmp_path / "two.obj"), 64)
    with pytest.raises(ParameterError, match="^Objects are painted with the paper's method"):
        paint_texture(np.full((64, 64, 3), 0.5, np.float32), layout, Params(method="hertzmann98"))


def test_the_object_command_has_no_method_to_choose(tmp_path):
    (tmp_path / "two.obj").write_text(TWO_ISLANDS)
    write_png(tmp_path / "texture.png", np.full((16, 16, 3), 0.5))
    run = command(tmp_path / "texture.png", "--mesh", tmp_path / "two.obj", "-o", tmp_path / "out",
                  "--method", "hertzmann98")
    assert run.returncode == 2
    assert "Unrecognized arguments: --method hertzmann98" in one_sentence_run(run)
    assert not (tmp_path / "out").exists()


def cube_obj(path: Path) -> Path:
    """``seam_meshes.cube(cells=2)`` written as an OBJ file, each triangle's corners and UVs of their own."""
    from seam_meshes import cube

    mesh = cube(cells=2)
    lines = [f"v {float(x)!r} {float(y)!r} {float(z)!r}" for x, y, z in mesh.position.reshape(-1, 3)]
    lines += [f"vt {float(u)!r} {float(v)!r}" for u, v in mesh.uv.reshape(-1, 2)]
    lines += [f"f {3 * t + 1}/{3 * t + 1} {3 * t + 2}/{3 * t + 2} {3 * t + 3}/{3 * t + 3}" for t in range(len(mesh.uv))]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_core_object_paints_across_the_seams_by_default_and_apart_with_apart_seams(tmp_path):
    """The default is the painting of ``core.paint_object(..., across_seams=True)``; --apart-seams that of
    across_seams=False, and the two differ on a cube, whose seams run on over its edges."""
    from core import api
    from core.params import Params

    mesh = cube_obj(tmp_path / "cube.obj")
    write_png(tmp_path / "texture.png", np.random.default_rng(3).random((64, 64, 3)), bits=16)
    arguments = (tmp_path / "texture.png", "--mesh", mesh, "--texture-size", 64, "--stroke-mm", "120,60",
                 "--seed", 2)
    for flags, across in (((), True), (("--apart-seams",), False)):
        folder = tmp_path / f"cli_{across}"
        run = command(*arguments, *flags, "-o", folder)
        assert run.returncode == 0, run.stderr
        api.paint_object(tmp_path / "texture.png", mesh, tmp_path / f"api_{across}", Params(seed=2), 64, (120, 60),
                         across_seams=across)
        assert (folder / "color.exr").read_bytes() == (tmp_path / f"api_{across}" / "color.exr").read_bytes()
    assert (tmp_path / "cli_True" / "color.exr").read_bytes() != (tmp_path / "cli_False" / "color.exr").read_bytes()
