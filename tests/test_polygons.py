"""A polygon cut into triangles that stay inside it (core/surface/polygons.py)."""

import numpy as np
import pytest

from core.surface.polygons import polygon_plane, triangles


def area(flat, corners):
    """The signed area of the triangle ``corners`` of 2-D points ``flat``."""
    (ax, ay), (bx, by), (cx, cy) = flat[list(corners)]
    return 0.5 * ((bx - ax) * (cy - ay) - (by - ay) * (cx - ax))


def shoelace(flat):
    """The signed area of the 2-D polygon ``flat``."""
    x, y = flat[:, 0], flat[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def test_a_convex_polygon_is_cut_as_a_fan_from_its_first_corner():
    hexagon = np.array([[np.cos(a), np.sin(a), 0.0] for a in np.linspace(0, 2 * np.pi, 6, endpoint=False)])
    assert triangles(hexagon) == [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5)]
    assert triangles(hexagon[:3]) == [(0, 1, 2)]


@pytest.mark.parametrize("turn", [1, -1])
def test_a_concave_polygon_is_cut_into_triangles_inside_it_that_add_up_to_its_area(turn):
    # an arrow-shaped octagon with a deep notch, tilted in space, both ways round
    flat = np.array([[0, 0], [4, 0], [4, 3], [2, 1], [0, 3], [-1, 2], [-1, 1], [0.5, 1.5]], float)[::turn]
    tilt = np.array([[1, 0, 0], [0, 0.6, 0.8], [0, -0.8, 0.6]])
    points = np.c_[flat, np.zeros(len(flat))] @ tilt.T + [3.0, -2.0, 7.0]
    cut = triangles(points)
    assert len(cut) == len(points) - 2 and sorted({k for t in cut for k in t}) == list(range(len(points)))
    plane = polygon_plane(points)
    assert shoelace(plane) > 0                                   # counter-clockwise in its own frame
    areas = [area(plane, t) for t in cut]
    assert min(areas) > 0 and np.isclose(sum(areas), shoelace(plane))
    fan = [(0, k, k + 1) for k in range(1, len(points) - 1)]
    assert not np.isclose(sum(abs(area(plane, t)) for t in fan), shoelace(plane))   # the fan reaches past the notch
