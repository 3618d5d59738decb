"""The texture's step across a mesh's UV seams against the step across its inner edges (ALGORITHM §10, seams),
worked out by hand on two squares of a plane."""

import numpy as np
import pytest

from core.surface.seams import edge_samples, seam_figures, shared_edges

SIZE = 64


def two_squares(split: bool):
    """Two 1 m squares side by side in the plane z = 0 (x 0..1 and 1..2), two triangles each, as (uv, position).
    Split: each square its own UV island (left over u 0.05..0.45, right over u 0.55..0.95); else one island over
    u 0.05..0.85, continuous across x = 1."""
    squares = []
    for left in (0.0, 1.0):
        corners = np.array([[left, 0, 0], [left + 1, 0, 0], [left + 1, 1, 0], [left, 1, 0]], float)
        u0 = (0.05 if left == 0 else 0.55) if split else 0.05 + 0.4 * left
        uv = np.array([[u0, 0.05], [u0 + 0.4, 0.05], [u0 + 0.4, 0.45], [u0, 0.45]])
        squares += [(uv[[0, 1, 2]], corners[[0, 1, 2]]), (uv[[0, 2, 3]], corners[[0, 2, 3]])]
    return np.array([s[0] for s in squares]), np.array([s[1] for s in squares])


def test_the_edges_two_triangles_share_in_3d_are_found_with_each_end_s_corner():
    _, position = two_squares(split=True)
    triangles, first, second = shared_edges(position)
    assert len(triangles) == 3                                    # two diagonals and the middle edge
    ends = [{tuple(position[t, f]), tuple(position[t, s])} for t, f, s in zip(triangles[:, 0], first[:, 0],
                                                                               second[:, 0], strict=True)]
    assert {(1.0, 0.0, 0.0), (1.0, 1.0, 0.0)} in [set(e) for e in ends]
    for k in (0, 1):                                             # both triangles name the same ends in the same order
        assert np.array_equal(position[triangles[:, k], first[:, k]], position[triangles[:, 0], first[:, 0]])


def test_a_seam_between_two_flat_islands_steps_by_their_colours_difference_and_inner_edges_not_at_all():
    uv, position = two_squares(split=True)
    samples = edge_samples(uv, position, 0.05)
    assert list(samples.edges) == [1, 2]
    assert samples.seam.sum() == 18              # one every 5 cm of the 0.9 m where both points lie in their triangles
    texture = np.zeros((SIZE, SIZE, 3))
    texture[:, : SIZE // 2] = 0.2
    texture[:, SIZE // 2:] = 0.6
    figures = seam_figures(samples, texture, texture)
    assert figures["source"] == {"seam": pytest.approx(0.4), "inner": 0.0}
    assert figures["offset_mm"] == 50.0 and figures["edges"] == {"seam": 1, "inner": 2}


def test_a_ramp_continuous_on_the_surface_steps_alike_across_a_seam_and_inside_an_island():
    """A texture whose value is the surface's x, on either layout: across the middle edge (along y) the two points
    are 2 d apart in x; across a diagonal, 2 d / sqrt 2; with no seam the middle edge is an inner edge."""
    d, pooled = 0.05, {}
    for split in (True, False):
        uv, position = two_squares(split)
        u = (np.arange(SIZE) + 0.5) / SIZE
        x = np.where(u < 0.5, (u - 0.05) / 0.4, 1 + (u - 0.55) / 0.4) if split else (u - 0.05) / 0.4
        texture = np.broadcast_to(x[None, :, None] / 10, (SIZE, SIZE, 1))      # 0.1 a metre
        samples = edge_samples(uv, position, d)
        steps = seam_figures(samples, texture, texture)["source"]
        if split:
            assert steps == {"seam": pytest.approx(2 * d / 10, abs=1e-5),                    # rounded to 1e-5
                             "inner": pytest.approx(2 * d / np.sqrt(2) / 10, abs=1e-5)}
            pooled[split] = (samples.seam.sum() * steps["seam"] + (~samples.seam).sum() * steps["inner"]) / len(
                samples.seam)
        else:
            assert steps["seam"] is None and list(samples.edges) == [0, 3]
            pooled[split] = steps["inner"]
    assert pooled[True] == pytest.approx(pooled[False], abs=1e-5)


def test_an_edge_where_no_two_points_offset_that_far_face_each_other_inside_their_triangles_is_left_out():
    """The middle edge's triangles have their right angles at opposite ends: points d across it stay inside both
    where d < s < 1 - d, for d < 0.5. A diagonal's triangles rise to 0.71 m at its middle: d < 0.71."""
    uv, position = two_squares(split=True)
    assert list(edge_samples(uv, position, 0.45).edges) == [1, 2]
    assert list(edge_samples(uv, position, 0.55).edges) == [0, 2]
    assert list(edge_samples(uv, position, 0.75).edges) == [0, 0]
