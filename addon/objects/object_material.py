# SPDX-License-Identifier: GPL-3.0-or-later
"""A painted object's look: its own material showing the painted texture, the relief on the object itself, and
the way back to the material it had.

The painted material is the canvas's shader (``scene.material``) reading the
maps through the UV map Blender renders with. The relief either displaces
the object along its normals by thickness x height, keeping its shape and
shading (the modifiers of ``relief``); with ``CYCLES_ADAPTIVE``, the
material's Displacement moves it at render time over a Subdivision Surface
that Cycles dices adaptively, as a canvas's can; with ``NORMAL_MAP``, the
painter's normal map shades it and its geometry stays.

A texture set painted from several sources (material slots with images
of their own, UDIM tiles: ``sources``) gives one painted material per
source, each reading its own maps (``color.s<k>.exr``, or the UDIM tiles
``color.s<k>.<UDIM>.exr``) through the object's UV map, and each slot shows
its source's; the relief's Displace modifier reads the whole set's height
map (the atlas) through a UV map of its own, ATLAS_UV_MAP.

The materials the object had and its painted materials are held on the
object by ID properties that point at them (ORIGINALS_KEY: {"slots": the
number of material slots, "materials": {slot index: material}}, empty slots
left out; PAINTED_KEY: the painted material of the first source;
PAINTED_SLOTS_KEY, for several sources: the painted material of each slot,
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
from . import texture_set
from .relief import add_relief, mark_relief, relief_modifiers, remove_relief
from .surface import uv_map_name

ORIGINALS_KEY = "paint_relief_originals"
LEGACY_ORIGINALS_KEY = "paint_relief_original_materials"
PAINTED_KEY = values.PAINTED_MATERIAL_KEY
PAINTED_SLOTS_KEY = "paint_relief_painted_slots"
ATLAS_UV_MAP = "Paint Relief Atlas"


def paint_object_look(scene, obj, folder, thickness, relief, texture_size, slot_source=None):
    """Give ``obj`` of ``scene`` the painting in ``folder``: its painted materials (made, or updated when it has
    them; one per source of a texture set, ``slot_source`` giving each slot's source, default all the first)
    and the relief
    (``relief``: 'DISPLACE', 'CYCLES_ADAPTIVE' or 'NORMAL_MAP'); the materials it shows are kept as its
    originals unless it shows its painting (those it had before stay kept then). Returns the first source's
    material. Raises maps.CanvasError (before changing anything) when a map cannot be used."""
    normal_map, adaptive = relief == "NORMAL_MAP", relief == "CYCLES_ADAPTIVE"
    roles = values.CANVAS_MAPS + ((values.NORMAL_MAP,) if normal_map else ())
    images = maps.load_maps(folder, roles)
    atlas = texture_set.read_atlas(folder)
    several = texture_set.is_set(atlas)
    slot_source = list(slot_source) if slot_source is not None else [0] * max(1, len(obj.material_slots))
    sets = texture_set.source_images(folder, atlas, roles) if several else [images]
    uv_map = uv_map_name(obj)
    made = []
    for source, source_images in enumerate(sets):
        name = "Paint Relief " + obj.name + ("" if source == 0 else " {}".format(source + 1))
        material = (painted_material(obj) if source == 0 else painted_slot_material(obj, source)) or \
            bpy.data.materials.new(name)
        canvas_material.build_material(material, source_images, thickness, adaptive, normal_map, uv_map)
        canvas_material.set_material_displacement(material, "DISPLACEMENT" if adaptive else "BUMP")
        made.append(material)
    keep_originals(obj, (original_materials(obj) or []) if shows_painting(obj) else
                   [slot.material for slot in obj.material_slots])
    if obj.get(PAINTED_KEY) is None:
        mark_relief(obj, [])        # painted now, not before: no modifier of the user's is taken for the relief
    obj[PAINTED_KEY] = made[0]
    if len(made) > 1:
        obj[PAINTED_SLOTS_KEY] = {"slots": len(slot_source), "sources": {str(k): m for k, m in enumerate(made)},
                                  "materials": {str(slot): made[min(k, len(made) - 1)]
                                                for slot, k in enumerate(slot_source)}}
    elif PAINTED_SLOTS_KEY in obj:
        del obj[PAINTED_SLOTS_KEY]
    remove_relief(obj)
    if not several:
        texture_set.remove_atlas_uv(obj, ATLAS_UV_MAP)
    if adaptive:
        mark_relief(obj, [canvas_plane.add_adaptive_subdivision(
            scene, obj, obj.modifiers.new(canvas_plane.SUBDIVISION_MODIFIER, "SUBSURF"))])
    elif not normal_map:
        relief_uv = texture_set.write_atlas_uv(obj, atlas, slot_source, uv_map, ATLAS_UV_MAP) if several else uv_map
        add_relief(obj, images[values.HEIGHT_MAP], thickness, texture_size, relief_uv)
    show_painting(obj, True)
    return made[0]


def painted_slot_material(obj, source):
    """The painted material of a texture set's ``source`` (> 0) that ``obj`` holds (PAINTED_SLOTS_KEY), or None."""
    kept = obj.get(PAINTED_SLOTS_KEY)
    return None if kept is None else kept.get("sources", {}).get(str(source))


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
