"""Blender-side fault cases: Build Canvas meets truncated, NaN, infinite and mismatched maps.

tests/blender/map_checks.py runs the operator on each broken folder inside
the bpy module (one subprocess) and reports; Blender must report one
sentence naming the file, add nothing to the scene, and never crash.
"""

import importlib.util
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from core.cli import main
from core.files import reading, writing

REPO = Path(__file__).resolve().parent.parent
HELPER = REPO / "tests" / "blender" / "map_checks.py"
FAULTS = ("truncated_height", "truncated_color", "nan_height", "inf_color", "small_opacity")


def _broken(folder: Path, fault: str) -> None:
    kind, name = fault.split("_")
    path = folder / f"{name}.exr"
    data, channels, attributes = reading.read_exr(path)
    keep = {k: v for k, v in attributes.items() if k in ("paint_relief:seed", "paint_relief:params")}
    if kind == "truncated":
        raw = path.read_bytes()
        path.write_bytes(raw[: len(raw) // 2])
    elif kind in ("nan", "inf"):
        data[1, 2, 0] = np.nan if kind == "nan" else np.inf
        writing.write_exr(path, data, channels=channels, attributes=keep)
    elif kind == "small":
        writing.write_exr(path, data[:-2, :-2], channels=channels, attributes=keep)


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    if importlib.util.find_spec("bpy") is None:
        pytest.skip("the bpy module (Blender as a Python module) is not installed")
    work = tmp_path_factory.mktemp("maps")
    rng = np.random.default_rng(2)
    photo = work.parent / "maps_photo.png"
    writing.write_png(photo, rng.random((24, 32, 3)).astype(np.float32))
    assert main(["paint", str(photo), "-o", str(work / "good"), "-q"]) == 0
    for fault in FAULTS:
        shutil.copytree(work / "good", work / fault)
        _broken(work / fault, fault)
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(work.parent / "blender_user"))
    run = subprocess.run([sys.executable, str(HELPER), str(work)], capture_output=True, text=True, timeout=600,
                         env=env, cwd=work.parent)
    lines = [line for line in run.stdout.splitlines() if line.startswith("RESULTS ")]
    assert run.returncode == 0 and lines, f"map_checks.py failed:\n{run.stdout[-3000:]}\n{run.stderr[-3000:]}"
    found = json.loads(lines[-1][len("RESULTS "):])
    found["work"] = str(work)
    return found


@pytest.mark.blender
def test_good_maps_build_a_canvas(results):
    assert results["good"]["result"] == ["FINISHED"], results["good"]["error"]


@pytest.mark.blender
@pytest.mark.parametrize("fault", FAULTS)
def test_bad_map_is_reported_and_never_reaches_blender(results, fault):
    step = results[fault]
    name = fault.split("_")[1] + ".exr"
    assert step["result"] is None and not step["changed"]
    assert name in step["error"] and "Traceback" not in step["error"]
