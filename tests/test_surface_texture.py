"""A texture painted in a mesh's UV space, island by island (ALGORITHM §10): no paint crosses islands, the strokes
are one size in the world, the bleed and the bytes."""

import numpy as np
import pytest
from test_islands import quad

from core.errors import InputError
from core.params import Params
from core.surface.islands import NO_ISLAND, bleed_texels, island_map, texel_density, uv_islands
from core.surface.texture import SurfaceLayout, island_sizes, paint_texture, texel_mm

SIZE = 128


def two_islands(size: int = SIZE) -> SurfaceLayout:
    """Island 1: UV [0.05, 0.55]^2 over a 1 m square (2 m per UV unit); island 2: UV [0.6, 0.95]^2 over a 1.4 m
    square (4 m per UV unit): its texels span twice as much surface."""
    a_uv, a_xyz = quad((0.05, 0.05), (0.55, 0.55), world_size=1.0)
    b_uv, b_xyz = quad((0.6, 0.6), (0.95, 0.95), world_size=1.4, world_origin=(3.0, 0.0))
    uv, xyz = np.concatenate([a_uv, b_uv]), np.concatenate([a_xyz, b_xyz])
    islands = uv_islands(uv)
    return SurfaceLayout(island_map(uv, islands, size), texel_density(uv, xyz, islands))


def texture(seed: int, size: int = SIZE) -> np.ndarray:
    """A smooth random (size, size, 3) sRGB picture with some edges."""
    rng = np.random.default_rng(seed)
    coarse = rng.random((8, 8, 3)).astype(np.float32)
    return np.repeat(np.repeat(coarse, size // 8, axis=0), size // 8, axis=1)


def test_an_island_twice_as_coarse_gets_strokes_half_as_many_texels_wide():
    layout = two_islands()
    assert np.allclose(layout.density.island, [2.0, 4.0])
    assert np.allclose(texel_mm(layout), [1000 * 2.0 / SIZE, 1000 * 4.0 / SIZE])
    assert island_sizes((64.0, 32.0, 16.0), 2.0) == (32, 16, 8)
    assert island_sizes((64.0, 32.0, 16.0), 4.0) == (16, 8, 4)
    assert island_sizes((64.0, 32.0, 4.0, 2.0), 4.0) == (16, 8, 2)       # at least 2 texels, each width once


def test_each_island_is_painted_from_its_own_texels_alone_and_its_strokes_are_anchored_on_it():
    """Changing the picture on island 2 (and outside every island) changes nothing of island 1's paint."""
    layout = two_islands()
    params = Params(seed=2)
    picture = texture(1)
    painted = paint_texture(picture, layout, params)
    other = picture.copy()
    other[layout.islands != 1] = texture(7)[layout.islands != 1]
    again = paint_texture(other, layout, params)
    one = layout.islands == 1
    for name in ("colour", "height", "opacity", "orientation"):
        assert getattr(painted, name)[one].tobytes() == getattr(again, name)[one].tobytes(), name
        assert getattr(painted, name)[layout.islands == 2].tobytes() != getattr(again, name)[
            layout.islands == 2].tobytes() or name == "orientation"
    anchors = np.array([stroke.anchor for stroke in painted.strokes])
    assert np.all(layout.islands[anchors[:, 1], anchors[:, 0]] != NO_ISLAND)
    per_island = painted.statistics["islands"]
    assert [entry["island"] for entry in per_island] == [1, 2]
    assert sum(entry["strokes"] for entry in per_island) == len(painted.strokes) == painted.statistics["strokes"]


def test_paint_bleeds_past_the_islands_and_beyond_the_bleed_the_texture_is_bare():
    layout = two_islands()
    painted = paint_texture(texture(3), layout, Params(seed=1))
    from scipy import ndimage
    distance = ndimage.distance_transform_edt(layout.islands == NO_ISLAND)
    reach = bleed_texels(SIZE)
    assert np.all(painted.opacity[distance > reach] == 0) and np.all(painted.height[distance > reach] == 0)
    assert np.all(painted.colour[distance > reach] == np.asarray(Params().canvas_colour, np.float32))
    edge = (distance > 0) & (distance <= 1)
    assert np.all(painted.opacity[edge] > 0)
    assert np.all(painted.opacity[layout.islands != NO_ISLAND] > 0)       # the islands are covered


def test_the_same_texture_layout_and_seed_give_the_same_bytes():
    layout = two_islands()
    first, second = (paint_texture(texture(4), layout, Params(seed=9)) for _ in range(2))
    for name in ("colour", "height", "opacity", "orientation"):
        assert getattr(first, name).tobytes() == getattr(second, name).tobytes()


def test_a_texture_and_an_island_map_that_do_not_fit_are_one_sentence():
    layout = two_islands()
    with pytest.raises(InputError, match=r"^The texture is 64 x 64 texels and its island map 128 x 128: both must "
                                         r"be the same square\.$"):
        paint_texture(texture(1, 64), layout, Params())
    empty = SurfaceLayout(np.zeros((SIZE, SIZE), np.int32), layout.density)
    with pytest.raises(InputError, match="No face of the mesh covers a texel"):
        paint_texture(texture(1), empty, Params())


def photograph_on_two_squares(size: int):
    """A photograph laid on the surface at one scale (1 m across) and a texture of two islands showing it: island
    1 a 0.6 m square over UV 0.02..0.62, island 2 a 1.2 m square over UV 0.66..0.96, whose texels span 4x as much
    surface. Returns (texture, layout)."""
    from pathlib import Path

    from scipy import ndimage
    from test_islands import quad

    from core.files.reading import read_image
    from core.surface.mesh import SurfaceMesh
    from core.surface.texture import surface_layout

    photo = read_image(Path(__file__).resolve().parents[1] / "sample_scenes" / "chelsea.png")
    per_metre = photo.shape[1]
    rows, cols = np.mgrid[0:size, 0:size]
    u, v = (cols + 0.5) / size, 1.0 - (rows + 0.5) / size
    picture = np.zeros((size, size, 3), np.float32)
    uvs, positions = [], []
    for low, high, metres in ((0.02, 0.62, 0.6), (0.66, 0.96, 1.2)):
        uv, position = quad((low, low), (high, high), world_size=metres)
        uvs.append(uv)
        positions.append(position)
        inside = (u >= low) & (u <= high) & (v >= low) & (v <= high)
        x, y = (u[inside] - low) / (high - low) * metres, (v[inside] - low) / (high - low) * metres
        for channel in range(3):
            picture[..., channel][inside] = ndimage.map_coordinates(photo[..., channel],
                                                                    [(1.0 - y) * per_metre, x * per_metre],
                                                                    order=1, mode="reflect")
    return picture, surface_layout(SurfaceMesh(np.concatenate(uvs), np.concatenate(positions)), size)


def test_islands_whose_texels_differ_4x_paint_each_layer_at_one_median_width_in_millimetres():
    """At 2048 texels the coarse island's texels are 1.95 mm, fine enough for the still's widths (docs/objects.md:
    at 1024 its finest strokes, 2 texels, are twice the dense island's)."""
    picture, layout = photograph_on_two_squares(2048)
    assert np.allclose(texel_mm(layout)[1] / texel_mm(layout)[0], 4.0)
    first, second = paint_texture(picture, layout, Params(seed=3)).statistics["islands"]
    for dense, coarse in zip(first["stroke_mm_median_per_layer"][:4], second["stroke_mm_median_per_layer"][:4],
                             strict=True):
        assert abs(coarse / dense - 1.0) <= 0.25, (first, second)
