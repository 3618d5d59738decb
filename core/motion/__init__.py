"""Motion: how frames of a sequence move (ALGORITHM §9).

Blender's Vector pass as forward and backward motion in image axes
(``vector_pass``), bilinear sampling and warping frame t+1 back onto frame t
(``warp``), the forward-backward check of which pixels are visible in both
frames (``visibility``) and the measures of a sequence's steadiness
(``measures``: warping error, stillness), and optical flow for frames
without a Vector pass (``optical_flow``, TV-L1). A motion is float32 (H, W, 2) in
pixels, [..., 0] = x (right), [..., 1] = y (down).
"""

from .measures import mean_over_pairs, normalise, still_pixels, stillness, value_range, warping_error
from .optical_flow import optical_flow
from .vector_pass import backward_motion, forward_motion, motion_pair
from .visibility import comes_back, motion_boundary, round_trip_consistent, visible_in_both
from .warp import bilinear, inside_frame, pixel_positions, warp_back

__all__ = ["backward_motion", "bilinear", "comes_back", "forward_motion", "inside_frame", "mean_over_pairs", "motion_boundary",
           "motion_pair", "normalise", "optical_flow", "pixel_positions", "round_trip_consistent", "still_pixels", "stillness",
           "value_range", "visible_in_both", "warp_back", "warping_error"]
