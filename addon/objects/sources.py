# SPDX-License-Identifier: GPL-3.0-or-later
"""The pictures an object's texture set is painted from: one per material slot, shared where slots share one.

Each slot's source is, in this order: the image feeding the Base Color of
its material's Principled BSDF (a UDIM tiled image as its path with
``<UDIM>``, every tile on disk; an image Blender holds only in memory
written out as a PNG), else the texture file the user names, else a Cycles
bake of that material's diffuse colour (``surface.bake_diffuse_colours``;
a material without nodes renders its one colour, which is its source).
Slots with the same image or the same file share a source, so the painter
paints it once (the same image read through another UV map or with another
extension is a source of its own); every baked material has its own. Each
triangle of the mesh is painted from its slot's source
(``triangle_sources``).

An image source keeps how Blender reads it: its Image Texture node's
``extension`` (REPEAT, EXTEND, CLIP or MIRROR; the painter paints UVs beyond
0..1 by it), the UV map its Vector input starts from, and the nodes between
(``uv_chain``: a Mapping node, a glTF importer's mirroring Math nodes), as a
function of the UVs the painter paints through and whose output the painted
material reads its maps by; an image read through nodes not followed there
is baked. A file, a bake or a flat colour repeats and is read through the
object's render UV map.
"""

import os
from typing import Callable, List, NamedTuple, Optional

import bpy
import numpy as np

from .surface import (
    bake_diffuse_colours,
    base_color_node,
    image_extension,
    image_on_disk,
    missing_file,
    write_image,
)
from .uv_chain import vector_chain

UDIM_TOKEN = "<UDIM>"


class SourceSet(NamedTuple):
    """The sources of one object's texture set."""

    paths: List[str]            # one per source: an image file, or a UDIM path holding UDIM_TOKEN
    kinds: List[str]            # one per source: "base color", "udim", "file" or "bake"
    slot_source: List[int]      # one per material slot (one for an object without slots): its source's index
    extensions: List[str]       # one per source: "REPEAT", "EXTEND", "CLIP" or "MIRROR", how UVs beyond 0..1 read it
    uv_maps: List[Optional[str]]    # one per source: the UV map its image is read through; None: the render map
    transforms: List[Optional[Callable]]    # one per source: (N, 2) UVs -> where its image is read; None: as is
    feeds: List[Optional[tuple]]    # one per source with a transform: (node name, output) feeding its image's Vector

    def slot_uv_maps(self):
        """One per material slot: the UV map its source is read through (None: the render map), for
        ``surface.mesh_triangles``."""
        return [self.uv_maps[k] for k in self.slot_source]


def tiled_path(image):
    """The ``<UDIM>`` path of the tiled ``image`` whose every tile is a file on disk; ValueError (one sentence
    naming the image and the file) when it is packed, generated or a tile's file is missing."""
    path = os.path.normpath(bpy.path.abspath(image.filepath, library=image.library))
    if image.packed_file is not None or UDIM_TOKEN not in path:
        raise ValueError("UDIM image {} has no tiles on disk: save its tiles (Image > Save) and paint "
                         "again.".format(image.name))
    for tile in image.tiles:
        tile_file = path.replace(UDIM_TOKEN, str(tile.number))
        if not os.path.isfile(tile_file):
            raise ValueError("Tile {} of UDIM image {} is missing: {} does not exist.".format(
                tile.number, image.name, tile_file))
    return path


def image_source(image, scratch, index):
    """(path, kind) of the painter's picture of ``image``: its file, its UDIM path, or its pixels written to
    ``scratch``/source.``index``.png when Blender has it only in memory."""
    if image.source == "TILED":
        return tiled_path(image), "udim"
    missing = missing_file(image)
    if missing is not None:
        raise ValueError("Image {}'s file {} does not exist: find it (File > External Data > Find Missing Files) or "
                         "choose another image, then paint.".format(image.name, missing))
    on_disk = image_on_disk(image)
    if on_disk is not None:
        return on_disk, "base color"
    return write_image(image, os.path.join(scratch, "source.{}.png".format(index))), "base color"


def flat_colour(material, scratch, index):
    """The path of a small PNG of the one colour ``material`` (without nodes) renders, written to
    ``scratch``/source.``index``.png."""
    from ...core.colour import linear_to_srgb
    from ...core.files.writing import write_png

    colour = linear_to_srgb(np.clip(np.array(material.diffuse_color[:3], np.float32), 0.0, 1.0))
    path = os.path.join(scratch, "source.{}.png".format(index))
    write_png(path, np.broadcast_to(colour, (8, 8, 3)).copy(), bits=16)
    return path


def texture_sources(context, obj, file_path, size, scratch):
    """The ``SourceSet`` of ``obj`` (module docstring); baked and in-memory pictures are written to ``scratch``,
    bakes ``size`` texels square. ValueError (one sentence naming the object, image or file) when a slot has no
    source to be had."""
    materials = [slot.material for slot in obj.material_slots] or [None]
    paths, kinds, slot_source, known, baked, extensions, uv_maps, transforms, feeds = [], [], [], {}, {}, [], [], [], []

    def source_of(key, make, extension="REPEAT", chain=None):
        if key not in known:
            path, kind = make(len(paths))
            known[key] = len(paths)
            paths.append(path)
            kinds.append(kind)
            extensions.append(extension)
            uv_maps.append(chain.uv_map if chain is not None else None)
            transforms.append(chain.transform if chain is not None else None)
            feeds.append(chain.feed if chain is not None and chain.transform is not None else None)
        return known[key]

    if not any(material is not None for material in materials) and not file_path:
        raise ValueError("Object {} has no material, so there is no colour to bake: give it a material or "
                         "choose a texture file.".format(obj.name))
    chosen = os.path.normpath(bpy.path.abspath(file_path)) if file_path else None
    used = used_slots(obj)
    for slot, material in enumerate(materials):
        if material is None and slot not in used and len(materials) > 1:
            slot_source.append(0)           # no face shows it: any source will do
            continue
        node = base_color_node(obj, [material]) if material is not None else None
        chain = vector_chain(node) if node is not None else None
        if chain is not None:
            image, extension, uv_map = node.image, image_extension(node), chain.uv_map
            if uv_map is not None and obj.data.uv_layers.get(uv_map) is None:
                raise ValueError("Material {}'s Base Color image {} is read through UV map {}, which object {} does "
                                 "not have: choose one of its UV maps in the UV Map node, then paint.".format(
                                     material.name, image.name, uv_map, obj.name))
            read_by = (material.name, chain.feed) if chain.transform is not None else None
            slot_source.append(source_of(("image", image.name, extension, uv_map, read_by),
                                         lambda k, image=image: image_source(image, scratch, k), extension, chain))
        elif chosen is not None:
            if not os.path.isfile(chosen):
                raise ValueError("Texture {} does not exist.".format(chosen))
            slot_source.append(source_of(("file", chosen), lambda k: (chosen, "file")))
        elif material is not None and (material.node_tree is None or not material.use_nodes):
            slot_source.append(source_of(("colour", material.name),
                                         lambda k, material=material: (flat_colour(material, scratch, k), "colour")))
        elif material is None:
            raise ValueError("Object {}'s material slot {} holds no material, so its faces have no colour to "
                             "paint: give it a material or choose a texture file.".format(obj.name, slot + 1))
        else:
            slot_source.append(source_of(("bake", material.name),
                                         lambda k, material=material: (baked.setdefault(
                                             material, os.path.join(scratch, "bake.{}.png".format(k))), "bake")))
    if baked:
        bake_diffuse_colours(context, obj, size, baked)
    return SourceSet(paths, kinds, slot_source, extensions, uv_maps, transforms, feeds)


def used_slots(obj):
    """The set of material slot indices some face of ``obj``'s mesh uses."""
    polygons = obj.data.polygons
    index = np.empty(len(polygons), np.int32)
    polygons.foreach_get("material_index", index)
    return set(np.unique(index).tolist())


def triangle_sources(material_index, slot_source):
    """(T,) int: the source of each triangle, from its (T,) material slot index ``material_index`` (an index past
    the slots, as Blender allows, counts as the last slot)."""
    slots = np.asarray(slot_source, np.int64)
    return slots[np.clip(np.asarray(material_index, np.int64), 0, len(slots) - 1)]


def read_where_sampled(uv, triangle_source, transforms):
    """(T, 3, 2) float64: the corners ``uv`` (T, 3, 2) of each triangle moved to where its source's image is read
    (``transforms``, one per source: a function of (N, 2) UVs, or None for as they are), by ``triangle_source``
    (T,)."""
    moved = np.array(uv, np.float64)
    for source, transform in enumerate(transforms):
        chosen = np.asarray(triangle_source) == source
        if transform is not None and chosen.any():
            moved[chosen] = transform(moved[chosen].reshape(-1, 2)).reshape(-1, 3, 2)
    return moved
