"""Memory budgets: sizes, the estimate against a measured run, available memory, the bomb check."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from core.errors import InputError, ParameterError
from core.files import budget, writing

REPO = Path(__file__).resolve().parent.parent


@pytest.mark.parametrize("text, expected", [("512M", 512 * 2**20), ("2G", 2 * 2**30), ("1.5g", int(1.5 * 2**30)),
                                            ("800", 800 * 2**20), ("64k", 64 * 1024), ("4GB", 4 * 2**30)])
def test_parse_size(text, expected):
    assert budget.parse_size(text) == expected


@pytest.mark.parametrize("text", ["", "lots", "-1G", "0", "nan", "inf", "1e999G", "4X"])
def test_parse_size_refuses(text):
    with pytest.raises(ParameterError, match="--max-memory"):
        budget.parse_size(text)


def test_estimate_grows_with_pixels_and_mask():
    small, large = budget.estimate_bytes(100, 100), budget.estimate_bytes(1000, 1000)
    assert large - small == (1000 * 1000 - 100 * 100) * budget.BYTES_PER_PIXEL
    assert budget.estimate_bytes(1000, 1000, mask=True) > large


def test_available_memory_is_known_on_linux():
    if not os.path.exists("/proc/meminfo"):
        pytest.skip("no /proc/meminfo")
    assert budget.available_bytes() > 0


def test_check_refuses_above_the_limit(tmp_path):
    with pytest.raises(InputError, match="7000 x 7000 pixels"):
        budget.check(tmp_path / "x.png", 7000, 7000, max_memory=2**30)
    assert budget.check(tmp_path / "x.png", 100, 100, max_memory=2**30) == budget.estimate_bytes(100, 100)


def test_bomb_check(tmp_path):
    path = tmp_path / "small.png"
    path.write_bytes(b"x" * 5000)
    with pytest.raises(InputError, match="decompression bomb"):
        budget.check_bomb(path, 7000, 7000)
    budget.check_bomb(path, 2000, 2000)  # below BOMB_MIN_PIXELS: allowed
    path.write_bytes(b"x" * 60_000)                      # 817 pixels per byte: a flat colour at zlib's best
    with pytest.raises(InputError, match="decompression bomb"):
        budget.check_bomb(path, 7000, 7000)
    path.write_bytes(b"x" * 200_000)
    budget.check_bomb(path, 7000, 7000)  # under 500 pixels per byte: allowed


def test_estimate_bounds_a_measured_run(tmp_path):
    """The estimate is above the peak resident memory of a real `core paint`, and not wildly above it."""
    rng = np.random.default_rng(1)
    h, w = 600, 800
    image = np.clip(np.cumsum(rng.normal(0, 0.02, (h, w, 3)), axis=1) + 0.5, 0, 1).astype(np.float32)
    writing.write_png(tmp_path / "p.png", image)
    env = dict(os.environ, PYTHONPATH=str(REPO))
    proc = subprocess.Popen([sys.executable, "-m", "core", "paint", str(tmp_path / "p.png"), "-o",
                             str(tmp_path / "o"), "-q"], env=env, cwd=REPO)
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    assert proc.returncode == 0
    peak = usage.ru_maxrss * 1024
    estimate = budget.estimate_bytes(w, h)
    assert peak < estimate < 3 * peak, (peak, estimate)


def test_sizes_and_pixel_counts_are_never_shown_as_zero():
    assert budget.format_bytes(1024) == "1 KB" and budget.format_bytes(512) == "512 bytes"
    assert budget.format_bytes(5 * 2**20) == "5 MB" and budget.format_bytes(3 * 2**30) == "3.0 GB"
    assert budget.format_megapixels(96 * 72) == "0.0069 megapixels"
    assert budget.format_megapixels(12_000_000) == "12.0 megapixels"
