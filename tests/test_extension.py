# SPDX-License-Identifier: GPL-3.0-or-later
"""The extension package: `make extension` builds a small, valid zip that
Blender installs, enables, disables and enables again.

The build runs the Makefile's own `extension` target on a copy of the
repository (so the repository's dist/ is never touched), with decoy files in
the folders the manifest must leave out. Blender runs in a subprocess: `bpy`
can be imported once per process and BLENDER_USER_RESOURCES must be set first.
"""

import importlib.util
import os
import runpy
import shutil
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import pytest

pytestmark = pytest.mark.blender

REPO = Path(__file__).resolve().parent.parent
HELPER = REPO / "tests" / "blender" / "install_enable_disable.py"
OK_LINE = "paint_relief extension: install, enable, disable, enable OK"
MAX_ZIP_BYTES = 2 * 1024 * 1024

# Files planted in the copy that must not reach the package.
DECOYS = (
    ".venv/lib/python3.11/site-packages/decoy/__init__.py",
    ".ci/decoy",
    ".hypothesis/decoy",
    "dist/decoy.txt",
    "build/decoy.py",
    "out/decoy.exr",
    "wheels/decoy-1.0-py3-none-any.whl",
    "core/__pycache__/decoy.cpython-311.pyc",
    "scene.blend1",
)
# Top-level entries of the repository that belong in the package.
PACKAGE_ROOTS = {"blender_manifest.toml", "__init__.py", "addon", "core", "README.md", "LICENSE"}


def _bpy_dir():
    spec = importlib.util.find_spec("bpy")  # Locates bpy without importing it.
    if spec is None or not spec.submodule_search_locations:
        pytest.skip("the bpy module (Blender as a Python module) is not installed")
    return Path(list(spec.submodule_search_locations)[0])


def _scripts_file(relative):
    found = sorted(_bpy_dir().glob("*/scripts/" + relative))
    assert found, "no {} inside the bpy package at {}".format(relative, _bpy_dir())
    return found[-1]


@pytest.fixture(scope="module")
def built_zip(tmp_path_factory):
    """Run `make extension` on a copy of the repository; return the zip path."""
    make = shutil.which("make")
    if make is None:
        pytest.skip("GNU make is not installed")
    blender_ext = _scripts_file("addons_core/bl_pkg/cli/blender_ext.py")

    src = tmp_path_factory.mktemp("extension") / "src"
    shutil.copytree(REPO, src, ignore=shutil.ignore_patterns(
        ".git", ".venv", ".pytest_cache", ".hypothesis", "__pycache__",
        "dist", "build", "out", "wheels", "*.zip"))
    for decoy in DECOYS:
        path = src / decoy
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("decoy: must not be packaged\n")

    # PY and BLENDER_EXT point at this environment (the copy has no real venv);
    # `-o` keeps make from reinstalling the requirements for the setup stamp.
    command = [make, "--no-print-directory", "-C", str(src),
               "-o", ".venv/.installed",
               "PY=" + sys.executable, "BLENDER_EXT=" + str(blender_ext),
               "extension"]
    run = subprocess.run(command, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, "make extension failed:\n{}\n{}".format(run.stdout, run.stderr)

    zips = sorted((src / "dist").glob("paint_relief-*.zip"))
    assert len(zips) == 1, "expected one package in dist/, found {}".format([z.name for z in zips])
    return zips[0]


def test_manifest_tags_are_blenders():
    manifest = tomllib.loads((REPO / "blender_manifest.toml").read_text(encoding="utf-8"))
    valid = runpy.run_path(str(_scripts_file("modules/_bpy_internal/extensions/tags.py")))["addons"]
    unknown = sorted(set(manifest["tags"]) - valid)
    assert not unknown, "tags not in Blender's list: {}".format(unknown)
    assert manifest["id"] == "paint_relief" and manifest["type"] == "add-on"


def test_package_holds_the_extension_and_nothing_else(built_zip):
    size = built_zip.stat().st_size
    assert size < MAX_ZIP_BYTES, "{} is {} bytes".format(built_zip.name, size)

    with zipfile.ZipFile(built_zip) as archive:
        names = set(archive.namelist())
    for required in ("blender_manifest.toml", "__init__.py",
                     "addon/__init__.py", "addon/properties.py", "addon/panels.py"):
        assert required in names, "{} is missing from {}".format(required, built_zip.name)
    core_files = sorted(p.relative_to(REPO).as_posix() for p in (REPO / "core").glob("*.py"))
    assert core_files, "core/ has no Python files"
    missing = [name for name in core_files if name not in names]
    assert not missing, "core files missing from the package: {}".format(missing)

    stray = sorted(name for name in names
                   if name.split("/")[0] not in PACKAGE_ROOTS
                   or any(part.startswith(".") or part == "__pycache__" for part in name.split("/"))
                   or name.endswith((".pyc", ".blend1")))
    assert not stray, "files that must stay out of the package: {}".format(stray)


def test_install_enable_disable_enable(built_zip, tmp_path):
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "blender_user"))
    run = subprocess.run([sys.executable, str(HELPER), str(built_zip)],
                         capture_output=True, text=True, timeout=300, env=env, cwd=tmp_path)
    output = "stdout:\n{}\nstderr:\n{}".format(run.stdout, run.stderr)
    assert run.returncode == 0, output
    lines = run.stdout.strip().splitlines()
    assert lines and lines[-1] == OK_LINE, output
