"""Several objects painted on a Dask cluster (core.paint_objects with a farm): the bytes of paint_object alone, one
sentence for a bad job while the others are painted, a kept job never sent, and cancel leaving the folders
painted whole and the others as they were."""

import json
import os
import pickle
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("distributed")

from dask_cluster import hang_guard  # noqa: E402
from oracles import folder_bytes  # noqa: E402
from test_paint_objects import held_in_an_extension, scene_jobs  # noqa: E402

import core  # noqa: E402
from core.errors import Cancelled, InputError  # noqa: E402
from core.farm import objects as farm_objects  # noqa: E402
from core.farm.cluster import Farm  # noqa: E402
from core.objects import side_by_side  # noqa: E402
from core.params import Params  # noqa: E402
from core.surface.mesh import SurfaceMesh  # noqa: E402

pytestmark = pytest.mark.cluster

FARM = Farm(workers=2)


@pytest.fixture(autouse=True)
def time_limit():
    """A farm test that hangs fails instead."""
    with hang_guard():
        yield


def painted_bytes(folder: Path, root: Path) -> dict:
    """{name: bytes} of every file of the painting in ``folder`` under ``root``, its report.json as JSON without
    the seconds taken, the paths in it written relative to ``root``."""
    files = folder_bytes(folder, leave_out=())
    report = json.loads(files.pop("report.json").decode().replace(str(root), "ROOT"))
    report.pop("seconds")
    return dict(files, **{"report.json": json.dumps(report, sort_keys=True).encode()})


def farm_jobs(root: Path) -> list:
    """``scene_jobs`` and the sphere at 256 texels, whose bytes the number of BLAS threads once changed."""
    jobs = scene_jobs(root)
    return jobs + [dict(jobs[0], output_dir=root / "big", texture_size=256)]


@pytest.fixture(scope="module")
def alone(tmp_path_factory):
    """Each job of ``farm_jobs`` painted by paint_object alone: [painted_bytes of its folder]."""
    root = tmp_path_factory.mktemp("alone")
    return [painted_bytes(Path(core.paint_object(**job)["output_dir"]), root) for job in farm_jobs(root)]


def test_each_object_is_one_task_on_the_farm_with_the_bytes_paint_object_writes_alone(tmp_path, alone):
    jobs = farm_jobs(tmp_path)
    for job in jobs:                                            # the meshes travel to the workers as they are
        mesh = pickle.loads(pickle.dumps(job["mesh"]))
        assert isinstance(mesh, SurfaceMesh) and all(
            (a is None and b is None) or (np.array_equal(a, b) and a.dtype == b.dtype)
            for a, b in zip(mesh, job["mesh"], strict=True))
    heard, environment = [], dict(os.environ)
    outcomes = core.paint_objects(jobs, progress=lambda f, m: heard.append((f, m)), farm=FARM)
    assert dict(os.environ) == environment       # no Dask setting left for the processes started after
    assert [outcome.error for outcome in outcomes] == [None] * 4
    for outcome, job, files in zip(outcomes, jobs, alone, strict=True):
        assert outcome.report["batch"] == "painted"
        assert outcome.report["output_dir"] == str(Path(job["output_dir"]).resolve())
        assert painted_bytes(Path(job["output_dir"]), tmp_path) == files
    assert sorted(m for _, m in heard) == [f"Object {k}/4: painted (2 workers)" for k in (1, 2, 3, 4)]
    assert [f for f, _ in heard] == sorted(f for f, _ in heard) and heard[-1][0] == 1.0


def test_a_bad_job_is_its_one_sentence_and_the_others_are_painted(tmp_path, alone):
    good = scene_jobs(tmp_path)
    jobs = [good[0],
            dict(good[1], texture_path=tmp_path / "missing.png", output_dir=tmp_path / "missing"),
            dict(good[1], mesh=SurfaceMesh(np.zeros((0, 3, 2)), np.zeros((0, 3, 3)))),
            good[2]]
    outcomes = core.paint_objects(jobs, farm=FARM)
    assert [outcome.ok for outcome in outcomes] == [True, False, False, True]
    assert [type(outcome.error) for outcome in outcomes[1:3]] == [InputError, InputError]
    assert str(outcomes[1].error) == f"The input file {tmp_path / 'missing.png'} does not exist."
    assert str(outcomes[2].error) == "The mesh given has no faces to paint."
    assert not (tmp_path / "missing").exists() and not (tmp_path / "cube").exists()
    assert painted_bytes(tmp_path / "sphere", tmp_path) == alone[0]
    assert painted_bytes(tmp_path / "two", tmp_path) == alone[2]


def test_a_kept_job_is_not_sent_and_no_cluster_is_reached_when_every_job_is_kept(tmp_path, monkeypatch):
    jobs = scene_jobs(tmp_path)
    core.paint_object(**jobs[1])
    sent = []
    paint_objects_on = farm_objects.paint_objects_on
    monkeypatch.setattr(farm_objects, "paint_objects_on",
                        lambda client, paint, given, *rest: sent.append(sorted(given)) or paint_objects_on(
                            client, paint, given, *rest))
    outcomes = core.paint_objects(jobs, farm=FARM)
    assert sent == [[0, 2]]
    assert [outcome.report["batch"] for outcome in outcomes] == ["painted", "kept", "painted"]
    monkeypatch.setattr(side_by_side, "on_farm", lambda *a: pytest.fail("a cluster was reached"))
    again = core.paint_objects(jobs, farm=FARM)
    assert [outcome.report["batch"] for outcome in again] == ["kept"] * 3


def test_cancel_stops_the_farm_and_leaves_the_folders_painted_whole_and_the_others_as_they_were(tmp_path, alone):
    jobs = scene_jobs(tmp_path)
    jobs += [dict(job, output_dir=tmp_path / f"again{k}", params=Params(seed=10 + k)) for k, job in enumerate(jobs)]
    heard = []

    def cancel():
        return any("painted" in message for _, message in heard)
    with pytest.raises(Cancelled) as stopped:
        core.paint_objects(jobs, progress=lambda f, m: heard.append((f, m)), cancel=cancel, farm=FARM)
    painted = [k for k, job in enumerate(jobs) if Path(job["output_dir"]).exists()]
    assert str(stopped.value) == (f"Painting the objects was cancelled; the {len(painted)} painted stay in their "
                                  f"folders and the others are as they were.")
    assert 1 <= len(painted) < len(jobs)
    for k in painted:                                           # each folder painted whole, or not at all
        assert side_by_side.kept_report(jobs[k]) is not None
        if k < 3:
            assert painted_bytes(Path(jobs[k]["output_dir"]), tmp_path) == alone[k]
    assert not [p for p in tmp_path.rglob(".staging-*")]


HELD_SCRIPT = '''
import json, sys, types
import numpy as np
sys.modules["only_in_blender"] = types.ModuleType("only_in_blender")      # what the extension's package needs
from bl_ext.user_default.paint_relief import core
from bl_ext.user_default.paint_relief.core.farm.cluster import Farm
from bl_ext.user_default.paint_relief.core.params import Params
from bl_ext.user_default.paint_relief.core.surface.mesh import SurfaceMesh


def main():
    jobs = json.loads(sys.argv[1])
    for job in jobs:
        with np.load(job.pop("arrays")) as arrays:
            job["mesh"] = SurfaceMesh(arrays["uv"], arrays["position"])
        job["params"] = Params(seed=job.pop("seed"))
    outcomes = core.paint_objects(jobs, farm=Farm(workers=2))
    print(json.dumps([[o.report and o.report["batch"], o.error and type(o.error).__module__] for o in outcomes]))


if __name__ == "__main__":
    main()
'''


def test_inside_an_extension_s_package_the_tasks_name_core_as_the_workers_import_it(tmp_path, alone):
    """As inside Blender: core is a subpackage of bl_ext.user_default.paint_relief, a name no worker imports; the
    tasks are sent by core imported on its own from the extension's folder, and the errors come back as the
    extension's."""
    jobs = held_in_an_extension(tmp_path, HELD_SCRIPT)
    jobs[1]["texture_path"] = str(tmp_path / "missing.png")
    environment = {name: value for name, value in os.environ.items() if name != "PYTHONPATH"}
    done = subprocess.run([sys.executable, str(tmp_path / "held.py"), json.dumps(jobs)], cwd=tmp_path,
                          env=environment, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout.splitlines()[-1]) == [
        ["painted", None], [None, "bl_ext.user_default.paint_relief.core.errors"]]
    assert painted_bytes(tmp_path / "out" / "sphere", tmp_path) == alone[0]
