"""The painter as a Python package (pyproject.toml): `pip install .` gives `import core` and `python -m core`
anywhere, as Dask's workers on other machines import it, and `pip install ".[farm]"` adds Dask.

The wheel is built with pip from a copy of the repository's packaging files and core/, with decoy addon/ and
tests/ beside them, using the setuptools of this environment (--no-build-isolation --no-index: no network).
"""

import email.parser
import os
import shutil
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import pytest
from oracles import same_bytes

from core.api import paint_file
from core.files import writing
from core.params import Params
from core.version import __version__

REPO = Path(__file__).resolve().parent.parent
# Files the extension holds beside core/ that the wheel must leave out.
DECOYS = ("__init__.py", "addon/__init__.py", "addon/values.py", "tests/test_decoy.py", "bench/decoy.py")


def _pyproject():
    return tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))


def _core_files():
    """Every file of core/ a wheel must carry, as 'core/...' paths (no bytecode)."""
    return {p.relative_to(REPO).as_posix() for p in (REPO / "core").rglob("*")
            if p.is_file() and "__pycache__" not in p.parts and p.suffix != ".pyc"}


@pytest.fixture(scope="module")
def wheel(tmp_path_factory):
    """The project's wheel, built from a copy of the repository: its path."""
    pytest.importorskip("setuptools", reason="the build backend (requirements.txt pins setuptools)")
    src = tmp_path_factory.mktemp("packaging") / "src"
    src.mkdir()
    for name in ("pyproject.toml", "README.md", "LICENSE", "blender_manifest.toml"):
        shutil.copyfile(REPO / name, src / name)
    shutil.copytree(REPO / "core", src / "core", ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    for decoy in DECOYS:
        (src / decoy).parent.mkdir(parents=True, exist_ok=True)
        (src / decoy).write_text("raise ImportError('decoy: must not be packaged')\n")
    out = src.parent / "wheels"
    run = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "--no-index",
                          "--disable-pip-version-check", "--quiet", "--wheel-dir", str(out), str(src)],
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, "pip wheel failed:\n{}\n{}".format(run.stdout, run.stderr)
    built = sorted(out.glob("*.whl"))
    assert len(built) == 1, built
    return built[0]


def _metadata(wheel_path):
    with zipfile.ZipFile(wheel_path) as archive:
        name = next(n for n in archive.namelist() if n.endswith(".dist-info/METADATA"))
        return email.parser.Parser().parsestr(archive.read(name).decode("utf-8"))


def test_versions_agree():
    manifest = tomllib.loads((REPO / "blender_manifest.toml").read_text(encoding="utf-8"))
    assert _pyproject()["project"]["version"] == manifest["version"] == __version__


def test_wheel_holds_core_and_nothing_else(wheel):
    assert wheel.name == "paint_relief-{}-py3-none-any.whl".format(__version__)
    with zipfile.ZipFile(wheel) as archive:
        names = set(archive.namelist())
    own = {n for n in names if not n.startswith("paint_relief-{}.dist-info/".format(__version__))}
    expected = _core_files()
    assert {"core/__main__.py", "core/files/folders.py", "core/sequence/__init__.py",
            "core/figures/font.npz"} <= expected
    assert own == expected, "missing: {}; not core: {}".format(sorted(expected - own), sorted(own - expected))


def test_wheel_declares_the_painters_dependencies_and_the_farm_extra(wheel):
    metadata = _metadata(wheel)
    assert metadata["Name"] == "paint-relief" and metadata["Version"] == __version__
    assert metadata["Requires-Python"] == ">=3.11"
    assert metadata["License-Expression"] == "GPL-3.0-or-later"
    requires = metadata.get_all("Requires-Dist")
    plain = {r.split(">")[0].split("=")[0].strip().lower() for r in requires if "extra ==" not in r}
    assert plain == {"numpy", "scipy", "openimageio", "threadpoolctl"}, requires
    assert metadata.get_all("Provides-Extra") == ["farm"]
    farm = [r for r in requires if r.replace(" ", "").endswith('extra=="farm"')]
    assert len(farm) == 1 and farm[0].startswith("dask[diagnostics,distributed]>="), requires


def test_installed_wheel_runs_outside_the_repository_and_paints_the_repositorys_bytes(wheel, tmp_path,
                                                                                      half_textured):
    site = tmp_path / "site"
    run = subprocess.run([sys.executable, "-m", "pip", "install", "--no-deps", "--no-index", "--quiet",
                          "--disable-pip-version-check", "--target", str(site), str(wheel)],
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    env = dict(os.environ, PYTHONPATH=str(site))
    code = "import core, core.figures.text as t, os; print(core.__file__); print(os.path.isfile(t.FONT_FILE))"
    found = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path, env=env,
                           timeout=600)
    assert found.returncode == 0, found.stderr
    where, font = found.stdout.split()
    assert Path(where).is_relative_to(site) and font == "True"
    helped = subprocess.run([sys.executable, "-m", "core", "--help"], capture_output=True, text=True, cwd=tmp_path,
                            env=env, timeout=600)
    assert helped.returncode == 0 and "paint" in helped.stdout, helped.stderr
    # a machine of a farm paints with the installed painter: the same files, byte for byte, as this source tree's
    photo = tmp_path / "photo.png"
    writing.write_png(photo, half_textured())
    painted = subprocess.run([sys.executable, "-m", "core", "paint", str(photo), "-o", str(tmp_path / "installed"),
                              "-q", "--seed", "2"], capture_output=True, text=True, cwd=tmp_path, env=env, timeout=600)
    assert painted.returncode == 0, painted.stderr
    paint_file(photo, tmp_path / "here", Params(seed=2))
    same_bytes(tmp_path / "installed", tmp_path / "here")
