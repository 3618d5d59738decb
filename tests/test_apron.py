"""Strokes across UV seams (ALGORITHM §10, strokes across seams): the chart maps and aprons as data, worked out by
hand on two squares of a plane, and textures painted across the seams of a cube and a UV sphere whose sources run
on over the surface."""

import numpy as np
import pytest
from seam_meshes import baked, cube, uv_sphere
from test_seams import two_squares

from core.params import Params
from core.surface.apron import island_apron, island_bilinear, seam_charts
from core.surface.islands import NO_ISLAND, bleed_texels, island_map, uv_islands
from core.surface.mesh import SurfaceMesh
from core.surface.seams import edge_samples, texture_steps
from core.surface.texture import island_box, padded, paint_texture, surface_layout

SIZE = 64


def test_a_seam_in_a_plane_unfolds_the_neighbour_island_beside_the_island_as_on_the_surface():
    """The split squares: island 1 over u 0.05..0.45 (x 0..1 m), island 2 over u 0.55..0.95 (x 1..2 m), 0.4 UV a
    metre both. Across the middle edge, island 2's frame lies beside island 1's shifted by 0.1 UV, and back."""
    uv, position = two_squares(split=True)
    islands = uv_islands(uv)
    charts = seam_charts(uv, position, islands, SIZE)
    seams = np.flatnonzero(charts.neighbour != NO_ISLAND)
    assert len(seams) == 2 and sorted(charts.island[seams]) == [1, 2]
    for edge in seams:
        shift = -0.1 * SIZE if charts.island[edge] == 1 else 0.1 * SIZE
        assert np.allclose(charts.chart[edge], [[1, 0, shift], [0, 1, 0]], atol=1e-9)
        assert charts.partner[charts.partner[edge]] == edge
    assert charts.leads[seams].tolist() == [charts.island[e] == 2 for e in seams]    # the later island leads


def test_an_island_s_apron_reads_the_neighbour_where_the_surface_runs_on_and_nothing_past_a_border():
    uv, position = two_squares(split=True)
    islands = uv_islands(uv)
    charts = seam_charts(uv, position, islands, SIZE)
    texel_islands = island_map(uv, islands, SIZE)
    rows, cols = island_box(texel_islands == 1, 6, clipped=False)
    box = padded(texel_islands, rows, cols, NO_ISLAND)
    apron = island_apron(charts, texel_islands, 1, (rows.start, cols.start), box, 6.0)
    x, y = apron.cols + cols.start, apron.rows + rows.start
    assert len(x) and np.all(x > 0.45 * SIZE - 0.5)                   # beyond the seam only, not past the borders
    assert np.all(apron.neighbour == 2)
    assert np.allclose(apron.source, np.stack([x + 0.1 * SIZE, y], axis=1))
    assert np.all(apron.feather[x - (0.45 * SIZE - 0.5) <= 4.0] == 1.0) and np.all(apron.feather[x - (0.45 * SIZE - 0.5) > 5.5] < 1.0)


def test_a_cube_s_aprons_read_its_surface_as_it_runs_on_over_each_edge():
    """Each island's apron reads only islands it shares a seam with, and beside the island it reads the colour the
    island's own border texels show, as the source runs on over the cube's edges (the colour's slope over a
    texel and a half at most)."""
    from scipy import ndimage

    from core.surface.texture import extended

    mesh, size = cube(), 128
    source = baked(mesh, size)
    layout = surface_layout(mesh, size)
    for island in range(1, 7):
        rows, cols = island_box(layout.islands == island, 8, clipped=False)
        box = padded(layout.islands, rows, cols, NO_ISLAND)
        apron = island_apron(layout.charts, layout.islands, island, (rows.start, cols.start), box, 8.0)
        assert len(apron.rows) > 0 and set(apron.neighbour) <= set(range(1, 7)) - {island}
        read, weight = island_bilinear(source, layout.islands, apron.neighbour, apron.source)
        assert np.all(weight > 0)
        beside = ndimage.binary_dilation(box == island, np.ones((3, 3), bool))[apron.rows, apron.cols]
        border = extended(padded(source, rows, cols, 0.0), box == island)[apron.rows, apron.cols]
        assert beside.sum() > 50
        assert np.abs(read - border)[beside].mean() < 0.03


def painted_pair(mesh: SurfaceMesh, size: int, seed: int = 0):
    """(source, layout across seams, painting across seams, layout apart, painting apart)."""
    source = baked(mesh, size)
    across, apart = surface_layout(mesh, size), surface_layout(mesh, size, across_seams=False)
    return (source, across, paint_texture(source, across, Params(seed=seed)), apart,
            paint_texture(source, apart, Params(seed=seed)))


def ratio(steps: dict) -> float:
    """The seam step over the inner step."""
    return steps["seam"] / steps["inner"]


@pytest.fixture(scope="module")
def painted_cube():
    return painted_pair(cube(), 256)


def test_a_cube_painted_across_its_seams_steps_there_as_its_source_does(painted_cube):
    source, layout, across, _, apart = painted_cube
    own = ratio(texture_steps(source, layout.edges))
    assert ratio(texture_steps(across.colour, layout.edges)) < 1.2 * own
    assert ratio(texture_steps(apart.colour, layout.edges)) > 1.3 * own          # painted apart it steps more


def test_the_two_sides_of_every_seam_agree_at_matched_points_as_an_inner_edge_s_do(painted_cube):
    """Points half a texel from each edge, facing each other on the surface: across a seam they differ at most 1.6
    times as much as across an inner edge (resampling the carried paint softens it a little), and far less than
    where the islands are painted apart."""
    source, layout, across, _, apart = painted_cube
    mesh = cube()
    close = edge_samples(mesh.uv, mesh.position, 0.5 * float(layout.density.island.max()) / 256)
    assert close.seam.any()
    assert ratio(texture_steps(across.colour, close)) < 1.6 * max(1.0, ratio(texture_steps(source, close)))
    assert ratio(texture_steps(across.colour, close)) < 0.75 * ratio(texture_steps(apart.colour, close))


def test_no_paint_lands_outside_the_islands_past_the_bleed_across_seams(painted_cube):
    _, layout, across, _, _ = painted_cube
    from scipy import ndimage
    distance = ndimage.distance_transform_edt(layout.islands == NO_ISLAND)
    beyond = distance > bleed_texels(256)
    assert beyond.any() and np.all(across.opacity[beyond] == 0) and np.all(across.height[beyond] == 0)
    assert np.all(across.colour[beyond] == np.asarray(Params().canvas_colour, np.float32))


def test_a_uv_sphere_painted_across_its_meridian_steps_there_about_as_across_an_inner_edge():
    """The painting steps across the meridian about as across an inner edge (1.05), its source a little less
    (0.85: where its samples fall); painted apart it steps 1.66 times as much as across an inner edge."""
    source, layout, across, _, apart = painted_pair(uv_sphere(48, 24), 512)
    own = ratio(texture_steps(source, layout.edges))
    assert ratio(texture_steps(across.colour, layout.edges)) < 1.25 * own
    assert ratio(texture_steps(across.colour, layout.edges)) < 0.7 * ratio(texture_steps(apart.colour, layout.edges))


def test_painting_across_seams_gives_the_same_bytes_for_the_same_input():
    mesh, size = cube(cells=2), 128
    source = baked(mesh, size)
    first = paint_texture(source, surface_layout(mesh, size), Params(seed=3))
    second = paint_texture(source, surface_layout(mesh, size), Params(seed=3))
    for a, b in ((first.colour, second.colour), (first.height, second.height), (first.opacity, second.opacity)):
        assert a.tobytes() == b.tobytes()


def test_a_mesh_without_seams_is_painted_as_its_islands_apart_byte_for_byte():
    from test_surface_texture import photograph_on_two_squares

    picture, layout = photograph_on_two_squares(128)
    assert not layout.charts.leads.any()
    across = paint_texture(picture, layout, Params(seed=1))
    apart = paint_texture(picture, layout._replace(charts=None), Params(seed=1))
    assert across.colour.tobytes() == apart.colour.tobytes() and across.height.tobytes() == apart.height.tobytes()
