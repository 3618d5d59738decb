# SPDX-License-Identifier: GPL-3.0-or-later
"""A painted object's look: its own material showing the painted texture, the relief on the object itself, and
the way back to the material it had.

The painted material is the canvas's shader (``scene.material``) reading the
maps through the UV map Blender renders with. The relief either displaces
the object along its normals by thickness x height, keeping its shape and
shading (the modifiers of ``relief``); with ``CYCLES_ADAPTIVE``, the
material's Displacement moves it at render time over a Subdivision Surface
that Cycles dices adaptively, as a canvas's can; with ``NORMAL_MAP``, the
painter's normal map shades it and its geometry stays. The
materials the object had are remembered on the object (ORIGINALS_KEY, by
name), so one toggle shows them again and another the painting.
"""

import bpy

from .. import values
from ..scene import canvas_plane, maps
from ..scene import material as canvas_material
from .relief import add_relief, relief_modifiers, remove_relief
from .surface import uv_map_name

ORIGINALS_KEY = "paint_relief_original_materials"
PAINTED_KEY = values.PAINTED_MATERIAL_KEY


def paint_object_look(scene, obj, folder, thickness, relief, texture_size):
    """Give ``obj`` of ``scene`` the painting in ``folder``: its painted material in every slot (made, or updated
    when it has one) and the relief (``relief``: 'DISPLACE', 'CYCLES_ADAPTIVE' or 'NORMAL_MAP'); the materials it
    had are remembered the first time. Returns the material. Raises maps.CanvasError (before changing anything)
    when a map cannot be used."""
    normal_map, adaptive = relief == "NORMAL_MAP", relief == "CYCLES_ADAPTIVE"
    images = maps.load_maps(folder, values.CANVAS_MAPS + ((values.NORMAL_MAP,) if normal_map else ()))
    painted = bpy.data.materials.get(obj.get(PAINTED_KEY, "")) if obj.get(PAINTED_KEY) else None
    if painted is None:
        painted = bpy.data.materials.new("Paint Relief " + obj.name)
    canvas_material.build_material(painted, images, thickness, adaptive, normal_map, uv_map_name(obj))
    canvas_material.set_material_displacement(painted, "DISPLACEMENT" if adaptive else "BUMP")
    if ORIGINALS_KEY not in obj:
        obj[ORIGINALS_KEY] = [slot.material.name if slot.material else "" for slot in obj.material_slots]
    obj[PAINTED_KEY] = painted.name
    remove_relief(obj)
    if adaptive:
        canvas_plane.add_adaptive_subdivision(scene, obj)
    elif not normal_map:
        add_relief(obj, images[values.HEIGHT_MAP], thickness, texture_size)
    show_painting(obj, True)
    return painted


def shows_painting(obj):
    """Whether ``obj`` shows its painted material now."""
    painted = obj.get(PAINTED_KEY)
    return bool(painted) and any(slot.material is not None and slot.material.name == painted
                                 for slot in obj.material_slots)


def show_painting(obj, painted):
    """Show ``obj``'s painted material and relief (``painted``), or the materials it had before Paint Object and
    no relief."""
    material = bpy.data.materials.get(obj.get(PAINTED_KEY, ""))
    if painted and material is not None:
        if not obj.material_slots:
            obj.data.materials.append(material)
        for slot in obj.material_slots:
            slot.material = material
    elif not painted:
        originals = list(obj.get(ORIGINALS_KEY, []))
        for slot, name in zip(obj.material_slots, originals, strict=False):   # slots added since keep theirs
            slot.material = bpy.data.materials.get(name) if name else None
        if not originals:
            obj.data.materials.clear()
    for modifier in relief_modifiers(obj):
        modifier.show_viewport = modifier.show_render = bool(painted)
