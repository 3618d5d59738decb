# SPDX-License-Identifier: GPL-3.0-or-later
"""The extension package: `make extension` builds one valid zip per platform
(the extension plus that platform's SciPy wheels for Python 3.11 and 3.13, its OpenImageIO wheel for
Blender 4.2's Python 3.11 and the pure-Python threadpoolctl wheel) that Blender installs,
enables, disables and enables again.

The build runs the Makefile's own `extension` target on a copy of the
repository (so the repository's dist/ is never touched), with decoy files in
the folders the manifest must leave out. Wheels already downloaded into the
repository's wheels/ are copied along, so only missing ones are downloaded. Blender runs in a subprocess: `bpy`
can be imported once per process and BLENDER_USER_RESOURCES must be set first.
"""

import importlib.util
import os
import platform
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
    "paint_relief.egg-info/PKG-INFO",
)
# The wheels each Python needs: SciPy everywhere; OpenImageIO only on Python 3.11, for Blender 4.2 LTS, which
# has no OpenImageIO binding of its own (4.4 and later bundle one).
PYTHON_TAGS = {"cp311": ("openimageio", "scipy"), "cp313": ("scipy",)}
# The pure-Python wheel every package holds, whatever its platform.
PURE_WHEEL = "./wheels/threadpoolctl-3.7.0-py3-none-any.whl"
# Platforms where no Blender runs that Python: Blender 4.5 LTS is the last for Intel Macs.
NO_BLENDER = {("macos-x64", "cp313")}
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
def built_zips(tmp_path_factory):
    """Run `make extension` on a copy of the repository; return {zip name: path}."""
    make = shutil.which("make")
    if make is None:
        pytest.skip("GNU make is not installed")
    blender_ext = _scripts_file("addons_core/bl_pkg/cli/blender_ext.py")

    src = tmp_path_factory.mktemp("extension") / "src"
    shutil.copytree(REPO, src, ignore=shutil.ignore_patterns(
        ".git", ".venv", ".pytest_cache", ".hypothesis", "__pycache__",
        "dist", "build", "out", "wheels", "*.zip", ".venv-shipped-*"))
    wheels = _manifest().get("wheels", [])
    for wheel in wheels:
        cached = REPO / wheel
        if cached.is_file():
            (src / wheel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(cached, src / wheel)
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
    run = subprocess.run(command, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, "make extension failed:\n{}\n{}".format(run.stdout, run.stderr)

    zips = {z.name: z for z in (src / "dist").glob("paint_relief-*.zip")}
    version = _manifest()["version"]
    expected = {"paint_relief-{}-{}.zip".format(version, p.replace("-", "_")) for p in _manifest()["platforms"]}
    assert set(zips) == expected, "expected {} in dist/, found {}".format(sorted(expected), sorted(zips))
    return zips


def _manifest():
    return tomllib.loads((REPO / "blender_manifest.toml").read_text(encoding="utf-8"))


def _this_platform():
    """Blender's name of this machine's platform, e.g. 'linux-x64'."""
    system = {"Linux": "linux", "Darwin": "macos", "Windows": "windows"}[platform.system()]
    machine = {"x86_64": "x64", "AMD64": "x64", "arm64": "arm64", "aarch64": "arm64"}[platform.machine()]
    return "{}-{}".format(system, machine)


@pytest.fixture(scope="module")
def this_platforms_zip(built_zips):
    name = "paint_relief-{}-{}.zip".format(_manifest()["version"], _this_platform().replace("-", "_"))
    if name not in built_zips:
        pytest.skip("no package is built for {}".format(_this_platform()))
    return built_zips[name]


def test_manifest_tags_are_blenders():
    manifest = _manifest()
    valid = runpy.run_path(str(_scripts_file("modules/_bpy_internal/extensions/tags.py")))["addons"]
    unknown = sorted(set(manifest["tags"]) - valid)
    assert not unknown, "tags not in Blender's list: {}".format(unknown)
    assert manifest["id"] == "paint_relief" and manifest["type"] == "add-on"


def test_manifest_is_complete():
    manifest = _manifest()
    assert len(manifest["tagline"]) < 64 and not manifest["tagline"].endswith(".")
    assert manifest["permissions"]["files"] and not manifest["permissions"]["files"].endswith(".")
    wheels = manifest["wheels"]
    assert all(w.startswith(("./wheels/scipy-", "./wheels/openimageio-", "./wheels/threadpoolctl-"))
               and w.endswith(".whl") for w in wheels), wheels
    assert [w for w in wheels if w.endswith("-none-any.whl")] == [PURE_WHEEL], "one pure-Python wheel for every Blender"
    assert not any("numpy" in w for w in wheels), "numpy comes with Blender and must not be bundled"
    assert set(PYTHON_TAGS) == {"cp311", "cp313"}, "Blender 4.2 to 5.0 ship Python 3.11, 5.1 and later 3.13"
    for platform_name in manifest["platforms"]:
        for tag, versions in PYTHON_TAGS.items():
            if (platform_name, tag) in NO_BLENDER:
                continue
            own = [w for w in wheels if "-{}-".format(tag) in w and _for_platform(w, platform_name)]
            assert sorted(w.split("/")[-1].split("-")[0] for w in own) == sorted(versions), (platform_name, tag, own)
    for name in ("scipy", "openimageio"):
        for tag in PYTHON_TAGS:
            own = {w.split("-")[1] for w in wheels if w.startswith("./wheels/{}-".format(name)) and "-{}-".format(tag) in w}
            assert len(own) <= 1, "every platform gets the same {} version for {}: {}".format(name, tag, own)


def _for_platform(wheel, platform_name):
    """True when the wheel file is for Blender's platform name, e.g. 'linux-x64' (a pure-Python wheel is for all)."""
    system, machine = platform_name.split("-")
    tag = wheel.rsplit("-", 1)[-1]
    if tag == "any.whl":
        return True
    arch = {"x64": ("x86_64", "amd64"), "arm64": ("arm64", "aarch64")}[machine]
    prefix = {"linux": "manylinux", "macos": "macosx", "windows": "win"}[system]
    return tag.startswith(prefix) and tag[:-len(".whl")].endswith(arch)


def test_packages_hold_the_extension_and_nothing_else(built_zips):
    manifest = _manifest()
    core_files = sorted(p.relative_to(REPO).as_posix() for p in (REPO / "core").glob("*.py"))
    assert core_files, "core/ has no Python files"
    addon_files = sorted(p.relative_to(REPO).as_posix() for p in (REPO / "addon").rglob("*.py"))
    for zip_path in built_zips.values():
        with zipfile.ZipFile(zip_path) as archive:
            infos = archive.infolist()
        names = {info.filename for info in infos}
        own = sum(info.compress_size for info in infos if not info.filename.startswith("wheels/"))
        assert own < MAX_ZIP_BYTES, "{} holds {} bytes besides its wheels".format(zip_path.name, own)
        for required in ("blender_manifest.toml", "__init__.py", "addon/__init__.py",
                         "addon/settings/properties.py", "addon/panels.py", "addon/painting/ops_paint.py",
                         "addon/scene/ops_scene.py", "addon/scene/canvas_plane.py", "addon/comparison/compare.py"):
            assert required in names, "{} is missing from {}".format(required, zip_path.name)
        missing = [name for name in core_files if name not in names]
        assert not missing, "core files missing from {}: {}".format(zip_path.name, missing)
        missing = [name for name in addon_files if name not in names]
        assert not missing, "addon files missing from {}: {}".format(zip_path.name, missing)

        wheels = sorted(name for name in names if name.startswith("wheels/"))
        platform_name = zip_path.stem.rsplit("-", 1)[-1].replace("_", "-")
        assert wheels == sorted(w[2:] for w in manifest["wheels"] if _for_platform(w, platform_name)), wheels
        for tag, versions in PYTHON_TAGS.items():
            if (platform_name, tag) not in NO_BLENDER:
                own = sorted(w.split("/")[1].split("-")[0] for w in wheels if "-{}-".format(tag) in w)
                assert own == sorted(versions), (zip_path.name, tag, own)
        stray = sorted(name for name in names
                       if name.split("/")[0] not in PACKAGE_ROOTS | {"wheels"}
                       or any(part.startswith(".") or part == "__pycache__" for part in name.split("/"))
                       or name.endswith((".pyc", ".blend1")))
        assert not stray, "files that must stay out of {}: {}".format(zip_path.name, stray)


def test_the_extension_carries_no_dask(built_zips):
    """Dask is for the painter on a cluster (pyproject.toml's `farm` extra), never inside Blender."""
    farm = ("dask", "distributed")
    listed = [w for w in _manifest()["wheels"] if w.split("/")[-1].split("-")[0].lower() in farm]
    assert not listed, "the manifest lists Dask wheels: {}".format(listed)
    for zip_path in built_zips.values():
        with zipfile.ZipFile(zip_path) as archive:
            names = archive.namelist()
        carried = [n for n in names if any(part.lower() == name or part.lower().startswith(name + "-")
                                          for part in n.split("/") for name in farm)]
        assert not carried, "{} carries Dask: {}".format(zip_path.name, carried[:5])


def test_install_enable_disable_enable(this_platforms_zip, tmp_path):
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "blender_user"))
    run = subprocess.run([sys.executable, str(HELPER), str(this_platforms_zip)],
                         capture_output=True, text=True, timeout=600, env=env, cwd=tmp_path)
    output = "stdout:\n{}\nstderr:\n{}".format(run.stdout, run.stderr)
    assert run.returncode == 0, output
    lines = run.stdout.strip().splitlines()
    assert lines and lines[-1] == OK_LINE, output
