# SPDX-License-Identifier: GPL-3.0-or-later
"""A painted object's relief on the object itself: the modifiers Paint Object adds last on the object's stack.

A Subdivision Surface of simple subdivision, which keeps the object's shape,
then a Displace modifier reading the height map through the UV map moves the
surface along its normals by thickness x height.
"""

from .. import values
from ..scene import canvas_plane
from .surface import uv_map_name


def relief_modifiers(obj):
    """The object's relief modifiers that Paint Object added (Subdivision, Displace), those present."""
    names = (canvas_plane.SUBDIVISION_MODIFIER, canvas_plane.DISPLACE_MODIFIER)
    return [m for m in (obj.modifiers.get(name) for name in names) if m is not None]


def add_relief(obj, height_image, thickness, texture_size):
    """Displace ``obj`` by ``thickness`` metres x the height map: a simple Subdivision Surface fine enough for the
    texture (``values.relief_levels``) and a Displace modifier along the normals through the UV map."""
    levels = values.relief_levels(len(obj.data.polygons), texture_size)
    subdivision = obj.modifiers.get(canvas_plane.SUBDIVISION_MODIFIER)
    if subdivision is None or subdivision.type != "SUBSURF":
        if subdivision is not None:
            obj.modifiers.remove(subdivision)
        subdivision = obj.modifiers.new(canvas_plane.SUBDIVISION_MODIFIER, "SUBSURF")
    subdivision.subdivision_type = "SIMPLE"
    subdivision.levels = max(0, levels - 2)
    subdivision.render_levels = levels
    displace = canvas_plane.add_displace(obj, height_image, thickness)
    displace.uv_layer = uv_map_name(obj)
    for modifier in (subdivision, displace):
        modifier.show_viewport = modifier.show_render = True
    return subdivision, displace


def remove_relief(obj):
    """Remove the relief modifiers Paint Object added (and Blender 4.2's adaptive subdivision flag)."""
    for modifier in relief_modifiers(obj):
        obj.modifiers.remove(modifier)
    canvas_plane.set_object_adaptive(None, obj, False)
