"""A check script of tests/blender/ run in a process of its own (``bpy`` is imported once per process) with a
throw-away Blender user folder, and its findings read back (the last ``RESULTS <json>`` line it prints)."""

import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest


def need_bpy():
    """Skip the test when the bpy module (Blender as a Python module) is not installed."""
    if importlib.util.find_spec("bpy") is None:
        pytest.skip("the bpy module (Blender as a Python module) is not installed")


def user_env(work):
    """The environment of a Blender process whose user folder is ``work/blender_user``."""
    return dict(os.environ, BLENDER_USER_RESOURCES=str(Path(work) / "blender_user"))


def run_script(script, args, work, timeout=600):
    """Run the Python ``script`` with ``args`` in the folder ``work`` with a Blender user folder of its own there;
    return the finished process (text output captured)."""
    return subprocess.run([sys.executable, str(script), *map(str, args)], capture_output=True, text=True,
                          timeout=timeout, env=user_env(work), cwd=work)


def run_checks(script, work, *args, timeout=600):
    """Run ``script`` with ``args`` in the folder ``work``; return its findings (a dict)."""
    run = run_script(script, args, work, timeout)
    lines = [line for line in run.stdout.splitlines() if line.startswith("RESULTS ")]
    assert run.returncode == 0 and lines, "{} failed:\n{}\n{}".format(Path(script).name, run.stdout[-4000:],
                                                                    run.stderr[-4000:])
    return json.loads(lines[-1][len("RESULTS "):])


def step(results, name):
    """The findings of the check ``name``; fails with its traceback when it raised."""
    found = results[name]
    assert "exception" not in found, found.get("exception")
    return found
