# SPDX-License-Identifier: GPL-3.0-or-later
"""Lights for the canvas: a raking key Sun, an optional soft fill Sun, and a dim world when the scene has none.

The lights are new objects in the active collection (found again by their
role, so adding lights again updates them). A world is made only for a
scene without one: a world the user set up is never replaced.

Angles follow :func:`values.light_direction`, the painter's convention:
azimuth in the canvas plane from the painting's right edge towards its bottom
edge (0 right, 90 bottom, 180 left, 270 top); elevation above the canvas. Objects are found again by their role, so
adding lights again updates the same lights.
"""

import math

import bpy
from mathutils import Vector

from .. import values
from .canvas_plane import ROLE_KEY, find_role, link_new_object

KEY_NAME = "Paint Relief Key"
FILL_NAME = "Paint Relief Fill"
WORLD_NAME = "Paint Relief World"
# Angular diameter of the key Sun: small, for crisp shadows of the paint ridges.
KEY_ANGLE = math.radians(1.0)
# The fill comes from the opposite side, high, wide and weak.
FILL_ELEVATION = math.radians(60.0)
FILL_ANGLE = math.radians(30.0)
FILL_FRACTION = 0.2
# Background of the world: a dim grey.
WORLD_COLOUR = (0.05, 0.05, 0.05)
# Lower bound on sin(elevation) when the key's strength is scaled for a flat canvas.
MIN_SINE = 0.05


def _sun(context, role, name):
    """The scene's Sun with ``role``, created (and linked into the active collection) when missing."""
    obj = find_role(context.scene, role)
    if obj is None or obj.type != "LIGHT" or obj.data.type != "SUN":
        if obj is not None:
            bpy.data.objects.remove(obj)
        obj = bpy.data.objects.new(name, bpy.data.lights.new(name, "SUN"))
        obj[ROLE_KEY] = role
        link_new_object(context, obj)
    return obj


def aim_sun(obj, azimuth, elevation, distance=1.0):
    """Point a Sun (which shines along its local -z) from direction (azimuth, elevation) onto the origin."""
    direction = Vector(values.light_direction(azimuth, elevation))
    obj.rotation_mode = "QUATERNION"
    obj.rotation_quaternion = direction.to_track_quat("Z", "Y")
    obj.location = direction * distance


def sun_strength(brightness, elevation):
    """Sun strength (irradiance, W/m^2) at which white paint on a flat canvas renders at ``brightness``.

    Cycles gives a Lambertian surface of albedo a under irradiance E the
    radiance a E / pi; the Sun stands ``elevation`` (radians) above the canvas.
    """
    return math.pi * brightness / max(math.sin(elevation), MIN_SINE)


def add_lights(context, azimuth, elevation, brightness, fill):
    """Create or update the key (and fill) lights, and a world if the scene has none; return (key, fill or None).

    azimuth, elevation: radians (the painter's convention); brightness: the
    key's brightness on white paint of a flat canvas; fill: add (True) or
    remove (False) the fill light.
    """
    scene = context.scene
    key = _sun(context, "key_light", KEY_NAME)
    key.data.angle = KEY_ANGLE
    fill_obj = find_role(scene, "fill_light")
    if fill:
        fill_obj = _sun(context, "fill_light", FILL_NAME)
        fill_obj.data.angle = FILL_ANGLE
    elif fill_obj is not None:
        light = fill_obj.data
        bpy.data.objects.remove(fill_obj)
        if light.users == 0:
            bpy.data.lights.remove(light)
        fill_obj = None
    aim_lights(scene, azimuth, elevation, brightness)

    if scene.world is None:
        set_world(scene)
    return key, fill_obj


def aim_lights(scene, azimuth, elevation, brightness):
    """Turn the scene's key (and fill, if any) light to ``azimuth``/``elevation`` radians at ``brightness``."""
    canvas = find_role(scene, "canvas")
    distance = max(canvas.dimensions[:2]) if canvas is not None else 1.0
    key = find_role(scene, "key_light")
    if key is not None and key.type == "LIGHT":
        aim_sun(key, azimuth, elevation, distance)
        key.data.energy = sun_strength(brightness, elevation)
    fill = find_role(scene, "fill_light")
    if fill is not None and fill.type == "LIGHT":
        aim_sun(fill, azimuth + math.pi, FILL_ELEVATION, distance)
        fill.data.energy = FILL_FRACTION * sun_strength(brightness, FILL_ELEVATION)


def set_world(scene):
    """Give the scene a new dim uniform world; return it."""
    world = bpy.data.worlds.new(WORLD_NAME)
    if world.node_tree is None:  # Blender 4.2 creates the tree only with use_nodes
        world.use_nodes = True
    background = next((n for n in world.node_tree.nodes if n.type == "BACKGROUND"), None)
    if background is None:
        background = world.node_tree.nodes.new("ShaderNodeBackground")
        output = next((n for n in world.node_tree.nodes if n.type == "OUTPUT_WORLD"), None)
        if output is None:
            output = world.node_tree.nodes.new("ShaderNodeOutputWorld")
        world.node_tree.links.new(background.outputs["Background"], output.inputs["Surface"])
    background.inputs["Color"].default_value = (*WORLD_COLOUR, 1.0)
    background.inputs["Strength"].default_value = 1.0
    world.color = WORLD_COLOUR
    scene.world = world
    return world
