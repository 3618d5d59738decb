"""Test collection: the shipped-package tests run only when given a built package (make test-shipped); fixtures
that several test files share."""

import os

import numpy as np
import pytest

# tests/shipped/ drives the extension installed from a zip (PAINT_RELIEF_ZIP) in bpy-only environments.
collect_ignore = [] if os.environ.get("PAINT_RELIEF_ZIP") else ["shipped"]


def half_textured_photo(height: int = 32, width: int = 40, seed: int = 5) -> np.ndarray:
    """A small photograph-like float32 (H, W, 3) sRGB image: a red gradient under flat green on the left half,
    random colours (``seed``) on the right half."""
    rng = np.random.default_rng(seed)
    image = np.zeros((height, width, 3), np.float32)
    image[..., 0] = np.linspace(0.1, 0.9, width)[None, :]
    image[..., 1] = 0.4
    image[:, width // 2:] = rng.random((height, width - width // 2, 3))
    return image


@pytest.fixture(scope="session")
def half_textured():
    """``half_textured(height=32, width=40, seed=5)``: the photograph-like image the command-line tests paint."""
    return half_textured_photo
