"""What every frame of a shot is painted with, as one value that travels with each piece of a frame's work."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Tuple

from ..motion.source import VECTOR_PASS_MOTION
from ..params import Params


@dataclass(frozen=True)
class ShotSettings:
    """A shot's settings.

    params: the painter's parameters (the paper's layout). fade_frames: K, 1 to 100, frames a stroke fades in
    and out over. normal_map: each frame also gets its normal map. motion: the motion's source,
    ``core.motion.source.VECTOR_PASS_MOTION`` or ``OPTICAL_FLOW_MOTION``. shape: (H, W) px of every frame.
    measures: each frame's maps are written with the steadiness of the pair it ends (``frame_work.pair_measures``).
    """

    params: Params
    fade_frames: int
    normal_map: bool
    motion: str
    shape: Tuple[int, int]
    measures: bool = False

    @property
    def vector_pass(self) -> bool:
        """Whether the frames carry Blender's Vector pass, which is then read with each frame."""
        return self.motion == VECTOR_PASS_MOTION
