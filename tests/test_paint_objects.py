"""Several objects painted side by side (core.paint_objects): the bytes of paint_object alone, one sentence for a bad
job while the others are painted, a second call keeping every painting, a change repainting its job only, cancel
leaving every unfinished folder as it was, and the path in this process."""

import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest
from seam_meshes import cube, uv_sphere

import core
from core.errors import Cancelled, InputError, ParameterError
from core.files.writing import write_png
from core.objects import side_by_side
from core.params import Params
from core.surface.mesh import SurfaceMesh

SAMPLES = Path(__file__).resolve().parent.parent / "sample_scenes"


def two_sources_cube() -> SurfaceMesh:
    """The cube of six islands, its faces painted from two sources in turn."""
    mesh = cube()
    return SurfaceMesh(mesh.uv, mesh.position, (np.arange(len(mesh.uv)) // 32 % 2).astype(np.int64))


def scene_jobs(root: Path) -> list:
    """Three small objects' jobs, painted into folders under ``root``: a sphere, a cube with a normal map and
    stroke widths of its own, a cube of two sources, clipped, its source kept."""
    return [dict(texture_path=SAMPLES / "coffee.png", mesh=uv_sphere(), output_dir=root / "sphere",
                 params=Params(seed=1), texture_size=96),
            dict(texture_path=str(SAMPLES / "chelsea.png"), mesh=cube(), output_dir=str(root / "cube"),
                 params=Params(seed=2), texture_size=96, normal_map=True, stroke_mm=(40.0, 20.0)),
            dict(texture_path=[SAMPLES / "astronaut.png", SAMPLES / "coffee.png"], mesh=two_sources_cube(),
                 output_dir=root / "two", params=Params(seed=3), texture_size=64, extensions="CLIP",
                 keep_source=True)]


def folder_bytes(folder) -> dict:
    """{name: bytes} of the files in ``folder`` (hidden ones too), {} for no folder."""
    folder = Path(folder)
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())} if folder.exists() else {}


def stamps(folder) -> dict:
    """{name: (size, modification time in ns)} of the files in ``folder``."""
    return {p.name: (p.stat().st_size, p.stat().st_mtime_ns) for p in sorted(Path(folder).iterdir())}


def painted_files(folder) -> dict:
    """{name: bytes} of the files of the painting in ``folder`` but its report (which holds the seconds taken)."""
    return {name: data for name, data in folder_bytes(folder).items() if name != "report.json"}


@pytest.fixture(scope="module")
def alone(tmp_path_factory):
    """Each job of ``scene_jobs`` painted by paint_object alone: [painted_files of its folder]."""
    root = tmp_path_factory.mktemp("alone")
    return [painted_files(core.paint_object(**job)["output_dir"]) for job in scene_jobs(root)]


@pytest.fixture
def own_temp(tmp_path, monkeypatch):
    """A temporary folder of this test's own for the folders that hand the jobs over."""
    folder = tmp_path / "temporary"
    folder.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(folder))
    return folder


def test_each_object_is_painted_in_a_worker_process_with_the_bytes_paint_object_writes_alone(tmp_path, alone,
                                                                                             own_temp):
    heard = []
    outcomes = core.paint_objects(scene_jobs(tmp_path), progress=lambda f, m: heard.append((f, m)), processes=2)
    assert [outcome.error for outcome in outcomes] == [None] * 3
    for outcome, job, files in zip(outcomes, scene_jobs(tmp_path), alone, strict=True):
        assert outcome.ok and outcome.report["batch"] == "painted"
        assert outcome.report["output_dir"] == str(Path(job["output_dir"]).resolve())
        assert painted_files(job["output_dir"]) == files
    assert sorted(files) == sorted(alone[2]) and "source.png" in files and "color.s1.exr" in files
    fractions = [f for f, _ in heard]
    assert fractions == sorted(fractions) or max(fractions) == 1.0
    assert heard[-1][0] == 1.0 and {m.split(":")[0] for _, m in heard} == {"Object 1/3", "Object 2/3", "Object 3/3"}
    assert any("Island" in m for _, m in heard)                 # the workers' own progress reaches the caller
    assert list(own_temp.iterdir()) == []                       # the jobs' hand-over folder is gone


def test_a_bad_job_is_its_one_sentence_and_the_others_are_painted(tmp_path, alone, own_temp):
    good = scene_jobs(tmp_path)
    jobs = [good[0],
            dict(good[1], texture_path=tmp_path / "missing.png", output_dir=tmp_path / "missing"),
            dict(good[1], output_dir=tmp_path / "sphere"),
            {"texture_path": "a.png", "mesh": cube(), "output_dir": tmp_path / "x", "params": Params(), "seed": 3},
            dict(good[1], mesh=SurfaceMesh(np.zeros((0, 3, 2)), np.zeros((0, 3, 3)))),
            good[2]]
    outcomes = core.paint_objects(jobs, processes=2)
    assert [outcome.ok for outcome in outcomes] == [True, False, False, False, False, True]
    assert [type(outcome.error) for outcome in outcomes[1:5]] == [InputError, ParameterError, ParameterError,
                                                                   InputError]
    assert str(outcomes[1].error) == f"The input file {tmp_path / 'missing.png'} does not exist."
    assert str(outcomes[2].error) == (f"Object 3 would be painted into {(tmp_path / 'sphere').resolve()}, as "
                                      f"object 1 is.")
    assert str(outcomes[3].error).startswith("Object 4's job names seed, which paint_objects does not take")
    assert str(outcomes[4].error) == "The mesh given has no faces to paint."
    assert not (tmp_path / "missing").exists() and not (tmp_path / "cube").exists()
    assert painted_files(tmp_path / "sphere") == alone[0] and painted_files(tmp_path / "two") == alone[2]
    with pytest.raises(ParameterError, match="^Give at least one object to paint"):
        core.paint_objects([])
    with pytest.raises(ParameterError, match="^The number of processes must be a whole number from 1, got 0.$"):
        core.paint_objects(good, processes=0)


def test_a_second_call_keeps_every_painting_and_a_change_paints_that_object_only(tmp_path, own_temp, monkeypatch):
    jobs = scene_jobs(tmp_path)
    first = core.paint_objects(jobs, processes=2)
    before = [stamps(job["output_dir"]) for job in jobs]
    started = []
    monkeypatch.setattr(side_by_side, "Worker", lambda *a: started.append(a) or pytest.fail("a worker started"))
    again = core.paint_objects(scene_jobs(tmp_path), processes=2)
    assert [outcome.report["batch"] for outcome in again] == ["kept"] * 3 and started == []
    assert [stamps(job["output_dir"]) for job in jobs] == before
    for kept, painted in zip(again, first, strict=True):
        assert kept.report["files"] == painted.report["files"] and kept.report["output_dir"] == painted.report[
            "output_dir"]
    monkeypatch.undo()
    monkeypatch.setattr(tempfile, "tempdir", str(own_temp))
    texture = tmp_path / "texture.png"
    shutil.copyfile(SAMPLES / "chelsea.png", texture)
    changed = scene_jobs(tmp_path)
    changed[0]["params"] = Params(seed=7)                                   # another seed: painted again
    changed[1]["texture_path"] = texture                                    # the same picture's bytes elsewhere:
    second = core.paint_objects(changed, processes=2)                       # the same inputs, kept
    assert [outcome.report["batch"] for outcome in second] == ["painted", "kept", "kept"]
    assert stamps(jobs[1]["output_dir"]) == before[1] and stamps(jobs[2]["output_dir"]) == before[2]
    assert second[0].report["params"]["seed"] == 7
    write_png(texture, np.full((32, 32, 3), 0.5, np.float32))              # other bytes and a mesh moved, another
    changed[1]["mesh"] = SurfaceMesh(cube().uv, cube().position * 1.01)     # extension: each painted again
    changed[2]["extensions"] = "REPEAT"
    third = core.paint_objects(changed, processes=1)
    assert [outcome.report["batch"] for outcome in third] == ["kept", "painted", "painted"]
    assert third[1].report["inputs_sha256"] != first[1].report["inputs_sha256"]


def test_a_folder_whose_painting_was_changed_since_is_painted_again(tmp_path, own_temp):
    jobs = scene_jobs(tmp_path)[:2]
    core.paint_objects(jobs, processes=1)
    with open(Path(jobs[1]["output_dir"]) / "height.exr", "ab") as stream:
        stream.write(b"\0")
    assert [o.report["batch"] for o in core.paint_objects(jobs, processes=1)] == ["kept", "painted"]


@pytest.mark.parametrize("processes", [2, 1])
def test_cancel_stops_every_worker_and_leaves_every_unfinished_folder_as_it_was(tmp_path, own_temp, processes):
    jobs = scene_jobs(tmp_path)
    core.paint_object(**dict(jobs[1], params=Params(seed=9)))              # an earlier painting in one folder
    (Path(jobs[1]["output_dir"]) / "notes.txt").write_text("the user's own")
    before = folder_bytes(jobs[1]["output_dir"])
    heard = []

    def cancel():
        return any("Island" in message for _, message in heard)
    with pytest.raises(Cancelled) as stopped:
        core.paint_objects(jobs, progress=lambda f, m: heard.append((f, m)), cancel=cancel, processes=processes)
    assert str(stopped.value) == ("Painting the objects was cancelled; the 0 painted stay in their folders and the "
                                  "others are as they were.")
    assert folder_bytes(jobs[1]["output_dir"]) == before
    assert not Path(jobs[0]["output_dir"]).exists() and not Path(jobs[2]["output_dir"]).exists()
    assert list(own_temp.iterdir()) == []


def test_one_process_paints_in_this_process_with_the_same_bytes(tmp_path, alone, own_temp, monkeypatch):
    monkeypatch.setattr(side_by_side, "Worker", lambda *a: pytest.fail("a worker started"))
    outcomes = core.paint_objects(scene_jobs(tmp_path), processes=1)
    assert [painted_files(o.report["output_dir"]) for o in outcomes] == alone
    one = core.paint_objects(scene_jobs(tmp_path / "one")[:1])              # one job: no worker either
    assert painted_files(one[0].report["output_dir"]) == alone[0]


def test_a_worker_that_ends_without_a_result_is_one_sentence_and_no_python_paints_here(tmp_path, alone, own_temp,
                                                                                      monkeypatch):
    crashing = tmp_path / "crashing"
    crashing.write_text("#!/bin/sh\necho 'Segmentation fault.' >&2\nexit 139\n")
    crashing.chmod(0o755)
    monkeypatch.setattr(side_by_side, "python_program", lambda: str(crashing))
    jobs = scene_jobs(tmp_path)[:2]
    outcomes = core.paint_objects(jobs, processes=2)
    assert [str(o.error) for o in outcomes] == [
        f"Painting object {k + 1} into {job['output_dir']} ended without a result, its last words: Segmentation "
        f"fault." for k, job in enumerate(jobs)]
    assert not any(Path(job["output_dir"]).exists() for job in jobs)
    monkeypatch.setattr(side_by_side, "python_program", lambda: None)
    heard = []
    outcomes = core.paint_objects(jobs, processes=2, notice=heard.append)
    assert [painted_files(o.report["output_dir"]) for o in outcomes] == alone[:2]
    assert len(heard) == 1 and heard[0].startswith("The objects are painted one after another: ")


HELD_SCRIPT = '''
import json, sys, types
import numpy as np
sys.modules["only_in_blender"] = types.ModuleType("only_in_blender")      # what the extension's package needs
from bl_ext.user_default.paint_relief import core
from bl_ext.user_default.paint_relief.core.params import Params
from bl_ext.user_default.paint_relief.core.surface.mesh import SurfaceMesh
jobs = json.loads(sys.argv[1])
for job in jobs:
    with np.load(job.pop("arrays")) as arrays:
        job["mesh"] = SurfaceMesh(arrays["uv"], arrays["position"])
    job["params"] = Params(seed=job.pop("seed"))
outcomes = core.paint_objects(jobs, processes=2)
print(json.dumps([[o.report and o.report["batch"], o.error and str(o.error)] for o in outcomes]))
'''


def held_in_an_extension(tmp_path: Path, script: str) -> list:
    """As inside Blender: core copied into ``tmp_path``/bl_ext/user_default/paint_relief, whose __init__ imports
    what only the program holds, and ``script`` as held.py; returns the first two ``scene_jobs`` as plain values
    (each mesh's arrays in an .npz, "arrays", and the seed, "seed"), painted under ``tmp_path``/out."""
    extension = tmp_path / "bl_ext" / "user_default" / "paint_relief"
    shutil.copytree(Path(core.__file__).parent, extension / "core", ignore=shutil.ignore_patterns("__pycache__"))
    for package in (tmp_path / "bl_ext", tmp_path / "bl_ext" / "user_default"):
        (package / "__init__.py").write_text("")
    (extension / "__init__.py").write_text("import only_in_blender\n")
    jobs = []
    for k, job in enumerate(scene_jobs(tmp_path / "out")[:2]):
        np.savez(tmp_path / f"mesh{k}.npz", uv=job["mesh"].uv, position=job["mesh"].position)
        jobs.append({name: str(value) if isinstance(value, Path) else value for name, value in job.items()
                     if name not in ("mesh", "params")} | {"arrays": str(tmp_path / f"mesh{k}.npz"),
                                                             "seed": job["params"].seed})
    (tmp_path / "held.py").write_text(script)
    return jobs


def test_inside_an_extension_s_package_the_workers_import_core_from_its_folder(tmp_path, alone):
    """As inside Blender: core is a subpackage of bl_ext.user_default.paint_relief, whose __init__ imports what
    only the program holds; the workers import core on its own from the extension's folder."""
    jobs = held_in_an_extension(tmp_path, HELD_SCRIPT)
    environment = {name: value for name, value in os.environ.items() if name != "PYTHONPATH"}
    done = subprocess.run([sys.executable, str(tmp_path / "held.py"), json.dumps(jobs)], cwd=tmp_path,
                          env=environment, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout.splitlines()[-1]) == [["painted", None], ["painted", None]]
    assert [painted_files(tmp_path / "out" / name) for name in ("sphere", "cube")] == alone[:2]
