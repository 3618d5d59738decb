"""Where a sequence's motion comes from (ALGORITHM §9, "Motion"): one rule for the painter, the relit film and
the benches.

Blender's Vector pass when every frame carries one (exact), else optical
flow on the pictures, found both ways. A motion is float32 (H, W, 2) in
pixels, image axes ([..., 0] = x right, [..., 1] = y down).
"""

from __future__ import annotations

from pathlib import Path
from typing import Sequence, Tuple

import numpy as np

from ..files.frames import carry_vector_passes
from ..files.timelapse import STILL_MOTION
from .optical_flow import SEQUENCE_MEGAPIXELS, optical_flow
from .vector_pass import motion_pair

VECTOR_PASS_MOTION = "vector pass"
"""The motion source of frames that all carry Blender's Vector pass (report.json's "motion")."""

OPTICAL_FLOW_MOTION = "optical flow"
"""The motion source of frames without a Vector pass: optical flow on the pictures (report.json's "motion")."""


def motion_source(paths: Sequence[Path]) -> str:
    """``VECTOR_PASS_MOTION`` when every frame file in ``paths`` holds a Vector pass, else ``OPTICAL_FLOW_MOTION``,
    from the headers alone; InputError naming a frame when only some hold one (``carry_vector_passes``)."""
    return VECTOR_PASS_MOTION if carry_vector_passes(paths) else OPTICAL_FLOW_MOTION


def two_way_motion(before: np.ndarray, after: np.ndarray, source: str,
                   max_megapixels: float = SEQUENCE_MEGAPIXELS) -> Tuple[np.ndarray, np.ndarray]:
    """(forward, backward) motion between two consecutive frames, each float32 (H, W, 2) px.

    ``source`` is ``VECTOR_PASS_MOTION``, with ``before`` and ``after`` the
    frames' Vector passes (float32 (H, W, 4) as stored, ``read_vector_pass``),
    or ``OPTICAL_FLOW_MOTION``, with the frames' sRGB [0, 1] pictures
    (float32 (H, W, 3)): flow forward and backward refined up to
    ``max_megapixels`` (the painter's ``SEQUENCE_MEGAPIXELS``; inf: at the
    frames' own size), or ``STILL_MOTION``: none, zeros of the pictures' (H, W).
    """
    if source == STILL_MOTION:
        still = np.zeros(before.shape[:2] + (2,), np.float32)
        return still, still.copy()
    if source == VECTOR_PASS_MOTION:
        return motion_pair(before, after)
    return optical_flow(before, after, max_megapixels), optical_flow(after, before, max_megapixels)
