"""What every frame of a shot is painted with, as one value that travels with each piece of a frame's work."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Tuple

from ..motion.source import VECTOR_PASS_MOTION
from ..params import Params
from ..version import __version__


def shot_key(params: Params, fade_frames: int, normal_map: bool, motion: Optional[str]) -> dict:
    """What makes a shot's frames, as plain data: the painter's version, the parameters (seed included), the fade,
    the normal-map setting and the motion's source (None where the frames are not read yet: it comes from their
    headers). A shot's fingerprint (``shot_resume.fingerprint``) and the add-on's key of a run
    (``addon.painting.shot_source.source_key``) are made of it."""
    return {"version": __version__, "params": params.to_dict(), "fade_frames": fade_frames,
            "normal_map": normal_map, "motion": motion}


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
    def key(self) -> dict:
        """What makes this shot's frames (``shot_key``)."""
        return shot_key(self.params, self.fade_frames, self.normal_map, self.motion)

    @property
    def vector_pass(self) -> bool:
        """Whether the frames carry Blender's Vector pass, which is then read with each frame."""
        return self.motion == VECTOR_PASS_MOTION
