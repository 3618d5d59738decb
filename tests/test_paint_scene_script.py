"""sample_scenes/paint_scene.py on the animated test scene of sample_scenes/world_scene.py, small: every mesh
painted, the four films and their side-by-side frames, scene.json's figures, the painted scene saved; a second
run keeps every texture; a scene that is no .blend file is one sentence and exit 1."""

import json
import subprocess
import sys
from pathlib import Path

import pytest
from blender_run import need_bpy, user_env

pytestmark = pytest.mark.blender
SCRIPTS = Path(__file__).resolve().parent.parent / "sample_scenes"
FRAMES = 3


def run(work, *args):
    return subprocess.run([sys.executable, str(SCRIPTS / "paint_scene.py"), *map(str, args)], capture_output=True,
                          text=True, timeout=900, env=user_env(work), cwd=work)


@pytest.fixture(scope="module")
def painted(tmp_path_factory):
    need_bpy()
    work = tmp_path_factory.mktemp("paint_scene")
    built = subprocess.run([sys.executable, str(SCRIPTS / "world_scene.py"), "-o", str(work / "world.blend"),
                            "--frames", str(FRAMES)], capture_output=True, text=True, timeout=300,
                           env=user_env(work), cwd=work)
    assert built.returncode == 0, built.stderr[-3000:]
    options = ["--texture-size", "64", "--samples", "1", "--resolution-percentage", "10"]
    first = run(work, work / "world.blend", "-o", work / "out", *options)
    assert first.returncode == 0, first.stdout[-3000:] + first.stderr[-3000:]
    summary = json.loads((work / "out" / "scene.json").read_text())
    again = run(work, work / "world.blend", "-o", work / "out", *options)
    assert again.returncode == 0, again.stderr[-3000:]
    return work, summary, json.loads((work / "out" / "scene.json").read_text())


def test_every_mesh_of_the_scene_is_painted_with_one_set_of_widths(painted):
    _, summary, _ = painted
    assert sorted(summary["objects"]) == ["Ball", "Column", "Crate", "Ground", "Wall"]
    assert summary["refused"] == {}
    assert summary["objects"]["Crate"]["folder"] == summary["objects"]["Column"]["folder"]     # one photograph
    assert len(summary["paintings"]) == 4
    assert summary["stroke_mm_from"]["chosen_by"] == "camera" and summary["render_px"] == [64, 36]
    agreement = summary["stroke_width_agreement"]
    assert agreement["islands"] >= 4 and len(agreement["per_width"]) == len(summary["stroke_mm"])


def test_the_four_films_and_their_warping_errors_are_written(painted):
    work, summary, _ = painted
    for film in ("relit", "original", "paper", "shot", "side_by_side"):
        assert sorted(p.name for p in (work / "out" / "film" / film).iterdir()) == [
            f"{n:04d}.png" for n in range(1, FRAMES + 1)], film
    for film in ("relit", "original", "paper", "shot"):
        errors = summary["warping_error"][film]
        assert len(errors) == FRAMES - 1 and all(e >= 0 for e in errors), film
    assert summary["over_original"]["original"] == pytest.approx(1.0)
    assert set(summary["seconds"]) >= {"scene", "paint", "renders", "shot", "figures"}
    assert (work / "out" / "scene.blend").is_file() and (work / "out" / "original.blend").is_file()
    assert not (work / "out" / "original.partial.blend").exists()


def test_running_again_keeps_every_texture(painted):
    _, summary, again = painted
    assert all(not entry["kept"] for entry in summary["paintings"].values())
    assert all(entry["kept"] for entry in again["paintings"].values())
    assert again["stroke_mm"] == summary["stroke_mm"]


def test_a_scene_that_is_no_blend_file_is_one_sentence_and_exit_1(tmp_path):
    need_bpy()
    (tmp_path / "scene.txt").write_text("not a scene")
    failed = run(tmp_path, tmp_path / "scene.txt", "-o", tmp_path / "out")
    assert failed.returncode == 1
    assert failed.stderr.strip().splitlines()[-1].startswith(f"The scene {tmp_path / 'scene.txt'} is no .blend file")
    assert not (tmp_path / "out").exists()


WITHOUT_DASK = '''
import runpy, sys
sys.modules["distributed"] = None                   # as inside a Blender without Dask distributed
sys.argv = sys.argv[1:]
runpy.run_path(sys.argv[0], run_name="__main__")
'''


def test_a_farm_without_dask_is_one_sentence_and_exit_1_before_anything_is_painted(tmp_path):
    need_bpy()
    saved = subprocess.run([sys.executable, "-c", "import bpy, sys; bpy.ops.wm.save_as_mainfile(filepath=sys.argv[1])",
                            str(tmp_path / "cube.blend")], capture_output=True, text=True, timeout=300,
                           env=user_env(tmp_path), cwd=tmp_path)
    assert saved.returncode == 0, saved.stderr[-3000:]
    for farm in (["--workers", "2"], ["--scheduler", "tcp://127.0.0.1:8786"]):
        result = subprocess.run([sys.executable, "-c", WITHOUT_DASK, str(SCRIPTS / "paint_scene.py"),
                                 str(tmp_path / "cube.blend"), "-o", str(tmp_path / "out"), *farm],
                                capture_output=True, text=True, timeout=300, env=user_env(tmp_path), cwd=tmp_path)
        assert result.returncode == 1, result.stderr[-3000:]
        assert result.stderr.strip().splitlines()[-1] == (
            "Painting on a Dask cluster needs Dask distributed, which is not installed here: pip install "
            "'paint-relief[farm]' (or dask[distributed]).")
        assert "[paint]" not in result.stdout and not (tmp_path / "out").exists()
