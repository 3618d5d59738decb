"""A mesh's UV islands, rasterised into a texture, their texel densities and the bleed (ALGORITHM §10), on meshes
worked out by hand."""

import numpy as np

from core.surface.islands import NO_ISLAND, bled, bleed_texels, island_map, texel_density, uv_islands


def quad(uv_low, uv_high, world_size=1.0, world_origin=(0.0, 0.0)):
    """Two triangles of a UV rectangle ``uv_low`` .. ``uv_high``, mapped to a flat square of ``world_size`` m:
    (uv (2, 3, 2), position (2, 3, 3))."""
    (u0, v0), (u1, v1) = uv_low, uv_high
    uv = np.array([[[u0, v0], [u1, v0], [u1, v1]], [[u0, v0], [u1, v1], [u0, v1]]], float)
    x0, y0 = world_origin
    s = world_size
    corners = {(u0, v0): (x0, y0), (u1, v0): (x0 + s, y0), (u1, v1): (x0 + s, y0 + s), (u0, v1): (x0, y0 + s)}
    position = np.array([[[*corners[tuple(p)], 0.0] for p in triangle] for triangle in uv])
    return uv, position


def test_triangles_sharing_a_uv_edge_are_one_island_and_a_seam_parts_them():
    one_uv, _ = quad((0.0, 0.0), (0.5, 0.5))
    other_uv, _ = quad((0.5, 0.0), (1.0, 0.5))              # shares the edge u = 0.5, v in [0, 0.5]
    apart_uv, _ = quad((0.0, 0.6), (0.4, 1.0))              # touches nothing
    uv = np.concatenate([apart_uv, one_uv, other_uv])
    assert uv_islands(uv).tolist() == [1, 1, 2, 2, 2, 2]
    # the same two quads, the second moved off the first in UV (a seam: the edge meets in 3-D, not in UV)
    seam_uv, _ = quad((0.55, 0.0), (1.0, 0.5))
    assert uv_islands(np.concatenate([one_uv, seam_uv])).tolist() == [1, 1, 2, 2]
    assert uv_islands(np.zeros((0, 3, 2))).tolist() == []


def test_the_island_map_covers_exactly_the_texel_centres_inside_the_triangles():
    size = 16
    uv, _ = quad((0.25, 0.5), (0.75, 1.0))                  # texels with columns 4..11 and rows 0..7
    islands = island_map(uv, uv_islands(uv), size)
    expected = np.zeros((size, size), np.int32)
    expected[0:8, 4:12] = 1
    assert np.array_equal(islands, expected)                # the diagonal shared by the two triangles leaves no gap
    far_uv, _ = quad((0.0, 0.0), (0.125, 0.125))
    both = np.concatenate([uv, far_uv])
    islands = island_map(both, uv_islands(both), size)
    assert np.count_nonzero(islands == 2) == 4 and islands[15, 0] == 2 and islands[14, 1] == 2
    assert island_map(both, uv_islands(both), size).tobytes() == islands.tobytes()


def test_a_triangle_covers_the_centres_on_its_edges_and_none_beyond_them():
    size = 8
    uv = np.array([[[0.0, 1.0], [1.0, 1.0], [0.0, 0.0]]])   # the upper left half: centres with x + y <= 7
    islands = island_map(uv, np.array([1], np.int32), size)
    rows, cols = np.mgrid[0:size, 0:size]
    assert np.array_equal(islands == 1, rows + cols <= size - 1)


def test_texel_density_is_the_square_root_of_world_area_over_uv_area_per_island():
    small_uv, small_world = quad((0.0, 0.0), (0.5, 0.5), world_size=1.0)                    # 1 m over 0.5 UV
    large_uv, large_world = quad((0.6, 0.6), (0.85, 0.85), world_size=2.0, world_origin=(5, 0))  # 2 m over 0.25
    uv, position = np.concatenate([small_uv, large_uv]), np.concatenate([small_world, large_world])
    density = texel_density(uv, position, uv_islands(uv))
    assert np.allclose(density.island, [2.0, 8.0])         # the second island's texels span 4x as much surface
    assert np.allclose(density.face, [2.0, 2.0, 8.0, 8.0]) and np.allclose(density.stray, 0.0)
    stretched = position.copy()
    stretched[0, :, 0] *= 2.0                               # one triangle's world x doubled: area 1 m2, not 0.5
    density = texel_density(uv, stretched, uv_islands(uv))
    island = np.sqrt(1.5 / 0.25)
    assert np.isclose(density.island[0], island)
    assert np.allclose(density.face[:2], [np.sqrt(1.0 / 0.125), np.sqrt(0.5 / 0.125)])
    assert np.isclose(density.stray[0], 1.0 - 2.0 / island)        # the unstretched face strays most


def test_paint_bleeds_the_nearest_island_texel_within_the_bleed_and_no_further():
    islands = np.zeros((20, 20), np.int32)
    islands[5:10, 5:10] = 1
    islands[12:15, 12:15] = 2
    values = np.zeros((20, 20, 3), np.float32)
    values[islands == 1] = (1.0, 0.0, 0.0)
    values[islands == 2] = (0.0, 0.0, 1.0)
    out = bled(values, islands, 2.0)
    assert np.array_equal(out[islands != NO_ISLAND], values[islands != NO_ISLAND])
    assert out[7, 3].tolist() == [1.0, 0.0, 0.0] and out[7, 2].tolist() == [0.0, 0.0, 0.0]     # 2 texels, not 3
    assert out[16, 13].tolist() == [0.0, 0.0, 1.0] and out[11, 11].tolist() == [0.0, 0.0, 1.0]
    assert out[4, 4].tolist() == [1.0, 0.0, 0.0]                                             # sqrt(2) <= 2
    assert np.array_equal(out[0], values[0])
    assert bleed_texels(2048) == 8.0 and bleed_texels(4096) == 16.0 and bleed_texels(256) == 2.0
