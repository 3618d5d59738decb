"""Shared by the shipped-package tests: the zip under test and a runner for Blender scripts in a subprocess."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent


@pytest.fixture(scope="session")
def package_zip():
    path = Path(os.environ["PAINT_RELIEF_ZIP"])
    assert path.is_file(), "PAINT_RELIEF_ZIP={} is not a file: run `make extension` first".format(path)
    return path


def run_script(script, *args, user_dir, cwd, timeout=900):
    """Run tests/shipped/<script> with this Python and BLENDER_USER_RESOURCES=user_dir; return (run, RESULTS dict)."""
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(user_dir))
    env.pop("PYTHONPATH", None)  # nothing from the checkout: the extension comes from the zip only
    run = subprocess.run([sys.executable, str(HERE / script), *map(str, args)], capture_output=True, text=True,
                         timeout=timeout, env=env, cwd=str(cwd))
    lines = [line for line in run.stdout.splitlines() if line.startswith("RESULTS ")]
    results = json.loads(lines[-1][len("RESULTS "):]) if lines else {}
    return run, results


def script_results(script, package_zip, work):
    """Run tests/shipped/<script> on the zip with its work and user folders in ``work``; return its RESULTS dict
    (fails when it printed none)."""
    run, results = run_script(script, package_zip, work, user_dir=work / "blender_user", cwd=work)
    assert results, "{} printed no results:\n{}\n{}".format(script, run.stdout[-3000:], run.stderr[-3000:])
    return results


def step(results, name):
    """The findings of the step ``name``; fails with its traceback when it raised."""
    found = results[name]
    assert "exception" not in found, found.get("exception")
    return found
