"""``python -m core analyze``: outputs, progress, bad input."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import OpenImageIO as oiio
import pytest
from oracles import folder_bytes, one_sentence, one_sentence_run, same_bytes

from core.cli import main
from core.files import reading, writing
from core.params import Params

ROOT = Path(__file__).resolve().parent.parent
OUTPUTS = {"reference.png", "importance.exr", "importance.png", "partition.png", "orientation.png", "analysis.json"}


@pytest.fixture
def photo(tmp_path):
    """A small textured photograph: half smooth gradient, half noise."""
    rng = np.random.default_rng(1)
    image = np.zeros((60, 90, 3), np.float32)
    image[:, :45] = np.linspace(0.2, 0.6, 45)[None, :, None]
    image[:, 45:] = rng.random((60, 45, 3))
    path = tmp_path / "photo.png"
    writing.write_png(path, image)
    return path


def test_analyze_writes_every_output(photo, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["analyze", str(photo), "-o", str(out)]) == 0
    assert {p.name for p in out.iterdir()} == OUTPUTS
    report = json.loads((out / "analysis.json").read_text())
    assert report["width"] == 90 and report["height"] == 60
    assert report["grids"] == sum(report["grids_per_stroke_size"].values())
    assert set(report["seconds"]) >= {"reference", "importance", "partition", "orientation"}
    importance, channels, attributes = reading.read_exr(out / "importance.exr")
    assert importance.shape == (60, 90, 1) and channels == ["Y"]
    assert 0.0 <= importance.min() and importance.max() <= 1.0
    assert json.loads(attributes["paint_relief:params"])["detail"] == Params().detail
    assert "Analysis done" in capsys.readouterr().err


def test_quiet_silences_progress(photo, tmp_path, capsys):
    assert main(["analyze", str(photo), "-o", str(tmp_path / "out"), "--quiet"]) == 0
    assert capsys.readouterr().err == ""


def test_same_seed_gives_same_bytes(photo, tmp_path):
    for name in ("a", "b"):
        assert main(["analyze", str(photo), "-o", str(tmp_path / name), "-q"]) == 0
    # analysis.json holds the seconds each stage took
    assert set(same_bytes(tmp_path / "a", tmp_path / "b", leave_out=("analysis.json",))) == OUTPUTS - {"analysis.json"}


def test_help_documents_every_option_with_its_default():
    result = subprocess.run([sys.executable, "-m", "core", "analyze", "--help"], cwd=ROOT,
                            capture_output=True, text=True)
    assert result.returncode == 0
    for option in ("--sizes", "--detail", "--mask", "--mask-strength", "--seed", "--max-megapixels", "--quiet"):
        assert option in result.stdout
    assert result.stdout.count("default") >= 6


def _nan_exr(path, photo=None):
    data = np.full((8, 8, 3), 0.5, np.float32)
    data[2, 3, 1] = np.nan
    out = oiio.ImageOutput.create(str(path))
    out.open(str(path), oiio.ImageSpec(8, 8, 3, oiio.FLOAT))
    out.write_image(data)
    out.close()


def _truncated_png(path, photo):
    data = photo.read_bytes()
    path.write_bytes(data[: len(data) // 2])


BAD_INPUTS = {
    "missing": lambda p, photo: None,
    "empty": lambda p, photo: p.write_bytes(b""),
    "text": lambda p, photo: p.write_text("not an image"),
    "truncated": _truncated_png,
    "nan": _nan_exr,
}


@pytest.mark.parametrize("kind", sorted(BAD_INPUTS))
def test_bad_input_fails_with_one_sentence_and_no_output(kind, photo, tmp_path):
    bad = tmp_path / (f"bad_{kind}.exr" if kind == "nan" else f"bad_{kind}.png")
    BAD_INPUTS[kind](bad, photo)
    out = tmp_path / "out"
    result = subprocess.run([sys.executable, "-m", "core", "analyze", str(bad), "-o", str(out)],
                            cwd=ROOT, capture_output=True, text=True)
    assert bad.name in one_sentence_run(result)
    assert not out.exists() or list(out.iterdir()) == []


def test_pixel_limit_is_enforced(photo, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["analyze", str(photo), "-o", str(out), "--max-megapixels", "0.001", "-q"]) != 0
    assert "megapixels" in capsys.readouterr().err
    assert not out.exists()


def test_unwritable_output_folder(photo, tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    assert main(["analyze", str(photo), "-o", str(blocker / "out"), "-q"]) != 0
    assert "out" in one_sentence(capsys.readouterr().err)


def test_invalid_parameters(photo, tmp_path, capsys):
    assert main(["analyze", str(photo), "-o", str(tmp_path / "o"), "--detail", "2", "-q"]) != 0
    assert "Detail must be between 0 and 1" in capsys.readouterr().err
    assert main(["analyze", str(photo), "-o", str(tmp_path / "o"), "--sizes", "8,-4", "-q"]) != 0
    assert "positive" in capsys.readouterr().err


def test_failed_run_keeps_earlier_outputs(photo, tmp_path):
    out = tmp_path / "out"
    assert main(["analyze", str(photo), "-o", str(out), "-q"]) == 0
    before = folder_bytes(out, leave_out=())
    assert main(["analyze", str(tmp_path / "missing.png"), "-o", str(out), "-q"]) != 0
    assert folder_bytes(out, leave_out=()) == before and set(before) == OUTPUTS


def test_cancel_stops_cleanly(photo):
    from core import Cancelled, Params, analyze
    image = reading.read_image(photo)
    with pytest.raises(Cancelled):
        analyze(image, Params(), cancel=lambda: True)
