# SPDX-License-Identifier: GPL-3.0-or-later
"""A texture set painted from several sources in Blender: each source's maps as images, and the atlas UV map.

The painter paints every source (a material slot's image, each UDIM tile of
a tiled one) as a cell of one square texture, the atlas, and writes besides
the atlas's maps each cell's (report.json "atlas": its cells, each with its
source, tile and files). A source's maps are read through the object's own
UV map: a plain source's as one image, a tiled source's tiles as one UDIM
image. The relief's Displace modifier reads the atlas's height map, which
needs the atlas's UV coordinates on the mesh (``write_atlas_uv``).
"""

import json
import os

import numpy as np

from .. import values
from ..scene import maps

ROLES = {values.COLOR_MAP: "color", values.HEIGHT_MAP: "height", values.OPACITY_MAP: "opacity",
         values.NORMAL_MAP: "normal"}
"""The files of a cell by the role of the atlas's map."""


def read_atlas(folder):
    """The "atlas" of the painting in ``folder`` (report.json), or None for a painting without one."""
    try:
        with open(os.path.join(folder, "report.json"), encoding="utf-8") as report:
            return json.load(report).get("atlas")
    except (OSError, ValueError):
        return None


def is_set(atlas):
    """Whether ``atlas`` holds more than one cell (a texture set of several sources or tiles)."""
    return bool(atlas) and len(atlas.get("cells", ())) > 1


def source_images(folder, atlas, roles):
    """[{role: image}] for each source of ``atlas`` in order: its cells' maps of ``roles`` loaded from ``folder``,
    a tiled source's as UDIM images. Raises maps.CanvasError naming a file that cannot be used."""
    sources = {}
    for cell in atlas["cells"]:
        sources.setdefault(int(cell["source"]), []).append(cell)
    found = []
    for source in sorted(sources):
        cells = sorted(sources[source], key=lambda cell: cell["tile"] or 0)
        paths = {role: os.path.join(folder, cells[0]["files"][ROLES[role]]) for role in roles}
        images = maps.load_images(paths)
        if cells[0]["tile"] is not None:
            for image in images.values():
                as_udim(image, [int(cell["tile"]) for cell in cells])
        found.append(images)
    return found


def as_udim(image, tiles):
    """Make ``image``, loaded from the file of its first tile, the UDIM image of ``tiles`` (numbers, 1001...)."""
    image.source = "TILED"          # Blender finds the tiles beside the file and puts <UDIM> in the path
    known = {tile.number for tile in image.tiles}
    for tile in tiles:
        if tile not in known:
            image.tiles.new(tile_number=tile)
    image.reload()


def write_atlas_uv(obj, atlas, slot_source, uv_map, name, slot_uv_maps=None, transforms=None):
    """Write where each corner of ``obj``'s own mesh (before modifiers, which carry it on) lies in ``atlas``
    (report.json's, each source wrapped by its cells' "extension") into its UV map ``name`` (made when missing;
    the maps Blender shows and renders with stay as they were), from its UV map ``uv_map`` and each face's source
    (``slot_source``: one per material slot); with ``slot_uv_maps`` (one UV map name or None per slot,
    ``sources.SourceSet.slot_uv_maps()``) a face's corners are read from its slot's map (``uv_map`` where None),
    and moved where its source's image is read by ``transforms`` (``sources.SourceSet.transforms``); a
    painting of one cell writes those UVs as they are; returns ``name``."""
    from ...core.surface.atlas import triangle_atlas_uv
    from .sources import read_where_sampled, triangle_sources
    from .surface import triangle_uv

    mesh = obj.data
    mesh.calc_loop_triangles()
    loops = np.empty(len(mesh.loop_triangles) * 3, np.int32)
    mesh.loop_triangles.foreach_get("loops", loops)
    slots = np.empty(len(mesh.loop_triangles), np.int32)
    mesh.loop_triangles.foreach_get("material_index", slots)
    names = [named or uv_map for named in (slot_uv_maps or [None])]
    sources = triangle_sources(slots, slot_source)
    triangles = read_where_sampled(triangle_uv(mesh, loops, slots, names, obj), sources, transforms or [])
    atlas_uv = triangle_atlas_uv(triangles, sources, None, atlas) if is_set(atlas) else triangles
    layers = mesh.uv_layers
    active, rendered = layers.active_index, next((k for k, layer in enumerate(layers) if layer.active_render), 0)
    layer = layers.get(name) or layers.new(name=name, do_init=False)
    layers.active_index = active
    layers[rendered].active_render = True
    uv = np.zeros((len(mesh.loops), 2), np.float32)
    uv[loops] = atlas_uv.astype(np.float32).reshape(-1, 2)
    layer.data.foreach_set("uv", uv.ravel())
    return name


def remove_atlas_uv(obj, name):
    """Remove ``obj``'s UV map ``name`` when it has one."""
    layer = obj.data.uv_layers.get(name)
    if layer is not None:
        obj.data.uv_layers.remove(layer)
