# SPDX-License-Identifier: GPL-3.0-or-later
"""A painted object's look: its own material showing the painted texture, the relief on the object itself, and
the way back to the material it had.

Each slot's painted material is a coat of paint over the material the slot
had (``paint_layer``: a copy of it whose base colour, roughness and normal
take the paint by its opacity, everything else, normal maps, emission and
metal among them, as the user made it); a slot without a material, or one
whose material has no Principled or Diffuse BSDF reaching its output, gets
the canvas's shader (``scene.material``) instead. The maps are read through
the UV map each source was painted in. The relief either displaces
the object along its normals by thickness x height, keeping its shape and
shading (the modifiers of ``relief``); with ``CYCLES_ADAPTIVE``, the
material's Displacement moves it at render time over a Subdivision Surface
that Cycles dices adaptively, as a canvas's can; with ``NORMAL_MAP``, the
painter's normal map shades it and its geometry stays.

A texture set painted from several sources (material slots with images
of their own, UDIM tiles: ``sources``) gives each slot's painted material
its source's maps (``color.s<k>.exr``, or the UDIM tiles
``color.s<k>.<UDIM>.exr``); the relief's Displace modifier reads the whole
set's height map (the atlas) through a UV map of its own, ATLAS_UV_MAP.

The materials the object had and its painted materials are held on the
object by ID properties that point at them (ORIGINALS_KEY: {"slots": the
number of material slots, "materials": {slot index: material}}, empty slots
left out; PAINTED_KEY: the painted material of the first slot;
PAINTED_SLOTS_KEY, when slots differ: the painted material of each slot,
as ORIGINALS_KEY holds the originals). Such a pointer is a user of
the material, so Blender writes it into the file whichever of the two the
object shows, keeps it through undo and object duplication, and keeps it
with the extension disabled (ID properties need no registration). One
toggle shows the originals again and another the painting. Files painted
before kept the originals by name (LEGACY_ORIGINALS_KEY, a list of names)
and the painted material by name: a material of that name that still exists
is adopted the next time the object is painted or toggled.
"""

import contextlib

import bpy

from .. import values
from ..scene import canvas_plane, maps
from ..scene import material as canvas_material
from . import paint_layer, texture_set
from .relief import add_relief, mark_relief, relief_modifiers, remove_relief
from .surface import uv_map_name

ORIGINALS_KEY = "paint_relief_originals"
LEGACY_ORIGINALS_KEY = "paint_relief_original_materials"
PAINTED_KEY = values.PAINTED_MATERIAL_KEY
PAINTED_SLOTS_KEY = "paint_relief_painted_slots"
ATLAS_UV_MAP = "Paint Relief Atlas"


def paint_object_look(scene, obj, folder, thickness, relief, texture_size, slot_source=None, extensions=None,
                      uv_maps=None, feeds=None, transforms=None):
    """Give ``obj`` of ``scene`` the painting in ``folder``: its painted materials and the relief (``relief``:
    'DISPLACE', 'CYCLES_ADAPTIVE' or 'NORMAL_MAP'); returns the first slot's painted material.

    Each slot's painted material is a coat of paint over the material the slot had (``paint_layer``: a copy,
    so its normal map, emission, metal and every other input stay), reading its source's maps
    (``slot_source``: each slot's source, default all the first) through that source's UV map (``uv_maps``, None
    for the map Blender renders with) with its image's extension (``extensions``, default REPEAT), or by the
    output of the nodes that fed the source image's Vector (``feeds``: (node name, output identifier) or None,
    one per source, for a slot whose original holds that node; ``transforms``, the sources' functions of UVs
    to where they are read, give the relief's UV map then); a slot
    without a material, or whose material has no shader a coat can go on, gets the canvas's shader. Slots of
    one material and source share one painted material. An earlier painting's materials are replaced by the
    new ones wherever they were used. The materials the object shows are kept as its originals unless it shows
    its painting (those it had before stay kept then). Raises maps.CanvasError (before changing anything) when
    a map cannot be used."""
    normal_map, adaptive = relief == "NORMAL_MAP", relief == "CYCLES_ADAPTIVE"
    roles = values.CANVAS_MAPS + ((values.NORMAL_MAP,) if normal_map else ())
    images = maps.load_maps(folder, roles)
    atlas = texture_set.read_atlas(folder)
    several = texture_set.is_set(atlas)
    slot_source = list(slot_source) if slot_source is not None else [0] * max(1, len(obj.material_slots))
    sets = texture_set.source_images(folder, atlas, roles) if several else [images]
    render_uv = uv_map_name(obj)
    originals = (original_materials(obj) or []) if shows_painting(obj) else \
        [slot.material for slot in obj.material_slots]
    earlier = _earlier_per_slot(obj, len(slot_source), originals)
    made, per_slot = {}, []
    for slot, source in enumerate(slot_source):
        original = originals[slot] if slot < len(originals) else None
        key = (original.name if paint_layer.can_layer(original) else None, source)
        if key not in made:
            name = "Paint Relief " + obj.name + ("" if not made else " {}".format(len(made) + 1))
            uv_map = (uv_maps[source] if uv_maps and uv_maps[source] else None) or render_uv
            extension = extensions[source] if extensions else "REPEAT"
            before = earlier[slot] if earlier[slot] not in made.values() else None
            feed = feeds[source] if feeds else None
            material = _painted(original if key[0] is not None else None, before, name,
                                (sets[source], thickness, uv_map, extension, adaptive, normal_map, feed))
            made[key] = material
        per_slot.append(made[key])
    keep_originals(obj, originals)
    _replace(earlier, per_slot)
    if obj.get(PAINTED_KEY) is None:
        mark_relief(obj, [])        # painted now, not before: no modifier of the user's is taken for the relief
    obj[PAINTED_KEY] = per_slot[0]
    if len(set(per_slot)) > 1:
        obj[PAINTED_SLOTS_KEY] = {"slots": len(per_slot),
                                  "materials": {str(slot): material for slot, material in enumerate(per_slot)}}
    elif PAINTED_SLOTS_KEY in obj:
        del obj[PAINTED_SLOTS_KEY]
    remove_relief(obj)
    moved = any(transform is not None for transform in transforms or ())
    if not several and not moved:
        texture_set.remove_atlas_uv(obj, ATLAS_UV_MAP)
    if adaptive:
        mark_relief(obj, [canvas_plane.add_adaptive_subdivision(
            scene, obj, obj.modifiers.new(canvas_plane.SUBDIVISION_MODIFIER, "SUBSURF"))])
    elif not normal_map:
        source_uv = [uv_maps[source] if uv_maps else None for source in slot_source]
        relief_uv = texture_set.write_atlas_uv(obj, atlas, slot_source, render_uv, ATLAS_UV_MAP, source_uv,
                                               transforms) if several or moved else source_uv[0] or render_uv
        add_relief(obj, images[values.HEIGHT_MAP], thickness, texture_size, relief_uv)
    show_painting(obj, True)
    return per_slot[0]


def _painted(original, before, name, paint):
    """A slot's painted material: a coat of ``paint`` (paint_layer.layered_material's arguments from images on)
    over ``original``, or the canvas's shader of it when ``original`` is None; the slot's earlier painted
    material ``before`` (or None) updated in place when it is of the same kind (over the same original), else
    a new material named ``name``."""
    if original is not None:
        if paint_layer.layer_origin(before) == original and paint_layer.update_layer(before, *paint):
            return before                                   # the same coat, new paint: the user's edits stay
        return paint_layer.layered_material(original, *paint[:4], name, *paint[4:])
    images, thickness, uv_map, extension, adaptive, normal_map, _ = paint
    material = before if before is not None and before.get(canvas_material.OWN_NODE_KEY) and \
        paint_layer.layer_origin(before) is None else bpy.data.materials.new(name)
    canvas_material.build_material(material, images, thickness, adaptive, normal_map, uv_map, extension)
    canvas_material.set_material_displacement(material, "DISPLACEMENT" if adaptive else "BUMP")
    return material


def _earlier_per_slot(obj, slots, originals):
    """The painted material of an earlier painting on each of ``slots`` slots of ``obj`` (None where it had none;
    never one of the ``originals``)."""
    first, per_slot = painted_material(obj), painted_slot_materials(obj)
    earlier = [per_slot.get(slot, first) for slot in range(slots)]
    return [None if material in originals else material for material in earlier]


def _replace(earlier, painted):
    """Put the new ``painted`` materials (one per slot) where an earlier painting's (``earlier``, one per slot)
    were used, and remove the earlier ones."""
    names = [None if material is None or material in painted else material.name for material in earlier]
    for slot, name in enumerate(names):
        material = bpy.data.materials.get(name) if name else None
        if material is not None:                            # a material on several slots goes at its first
            material.user_remap(painted[slot])
            bpy.data.materials.remove(material)
            if painted[slot].name.startswith(name + "."):  # made while the earlier one held the name
                painted[slot].name = name


def painted_slot_materials(obj):
    """{slot index: painted material} for an object painted from several sources, else {}."""
    kept = obj.get(PAINTED_SLOTS_KEY)
    if kept is None:
        return {}
    materials = kept.get("materials", {})
    return {int(index): material for index, material in materials.items()}


def painted_material(obj):
    """``obj``'s painted material (PAINTED_KEY: the material, or its name in a file painted before), or None."""
    painted = obj.get(PAINTED_KEY)
    if isinstance(painted, str):
        return bpy.data.materials.get(painted) if painted else None
    return painted if isinstance(painted, bpy.types.Material) else None


def original_materials(obj):
    """The materials ``obj`` had in its slots before Paint Object, one per slot (None for an empty one or one
    whose material no longer exists), or None when none are kept. Read only (a panel may call it)."""
    kept = obj.get(ORIGINALS_KEY)
    if kept is not None:
        materials = kept.get("materials", {})
        return [materials.get(str(index)) for index in range(int(kept.get("slots", 0)))]
    names = obj.get(LEGACY_ORIGINALS_KEY)
    if names is None:
        return None
    return [bpy.data.materials.get(name) if name else None for name in names]


def keep_originals(obj, materials):
    """Hold ``materials`` (one per slot, None for an empty slot) on ``obj`` as its originals, by reference (they
    have a user then); the by-name list of a file painted before goes."""
    obj[ORIGINALS_KEY] = {"slots": len(materials),
                          "materials": {str(index): material for index, material in enumerate(materials)
                                        if material is not None}}
    if LEGACY_ORIGINALS_KEY in obj:
        del obj[LEGACY_ORIGINALS_KEY]


def source_materials(obj):
    """The materials the texture of ``obj`` is painted from: its originals while it shows its painting, else
    those it shows (never the painting itself)."""
    if shows_painting(obj):
        return [material for material in original_materials(obj) or [] if material is not None]
    return [slot.material for slot in obj.material_slots if slot.material is not None]


def shows_painting(obj):
    """Whether ``obj`` shows its painted material now."""
    painted = {painted_material(obj)} | set(painted_slot_materials(obj).values())
    painted.discard(None)
    return any(slot.material in painted for slot in obj.material_slots)


def _adopt(obj):
    """Hold a file painted before's painted material and originals by reference (those that still exist)."""
    painted = obj.get(PAINTED_KEY)
    if isinstance(painted, str):
        material = painted_material(obj)
        if material is not None:
            obj[PAINTED_KEY] = material
    if ORIGINALS_KEY not in obj and LEGACY_ORIGINALS_KEY in obj:
        keep_originals(obj, original_materials(obj))


def show_painting(obj, painted):
    """Show ``obj``'s painted material and relief (``painted``), or the materials it had before Paint Object and
    no relief."""
    _adopt(obj)
    _show(obj, painted)


def _show(obj, painted):
    """``show_painting`` without adopting what a file painted before names."""
    material, per_slot = painted_material(obj), painted_slot_materials(obj)
    if painted and material is not None:
        if not obj.material_slots:
            obj.data.materials.append(material)
        for index, slot in enumerate(obj.material_slots):
            slot.material = per_slot.get(index) or material
    elif not painted:
        originals = original_materials(obj) or []
        for slot, original in zip(obj.material_slots, originals, strict=False):   # slots added since keep theirs
            slot.material = original
        if not originals:
            obj.data.materials.clear()
    for modifier in relief_modifiers(obj):
        modifier.show_viewport = modifier.show_render = bool(painted)


@contextlib.contextmanager
def original_shown(obj):
    """For the block, ``obj`` shows the materials it had before Paint Object and no relief when it shows its
    painting now (to read or bake its source); afterwards its slots and relief modifiers are exactly as before."""
    if not shows_painting(obj):
        yield
        return
    slots = [slot.material for slot in obj.material_slots]
    shown = [(modifier, modifier.show_viewport, modifier.show_render) for modifier in relief_modifiers(obj)]
    _show(obj, False)
    try:
        yield
    finally:
        while len(obj.material_slots) < len(slots):
            obj.data.materials.append(None)
        for slot, material in zip(obj.material_slots, slots, strict=False):
            slot.material = material
        for modifier, viewport, render in shown:
            modifier.show_viewport, modifier.show_render = viewport, render
