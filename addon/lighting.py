# SPDX-License-Identifier: GPL-3.0-or-later
"""Lights for the canvas: a raking key Sun, an optional soft fill Sun and a dim world.

Angles follow :func:`values.light_direction`, the painter's convention:
azimuth in the canvas plane from the painting's right edge towards its bottom
edge (0 right, 90 bottom, 180 left, 270 top); elevation above the canvas. Objects are found again by their role, so
adding lights again updates the same lights.
"""

import math

import bpy
from mathutils import Vector

from . import values
from .canvas import ROLE_KEY, find_role

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


def _sun(scene, role, name):
    """The scene's Sun with ``role``, created (and linked) when missing."""
    obj = find_role(scene, role)
    if obj is None or obj.type != "LIGHT" or obj.data.type != "SUN":
        if obj is not None:
            bpy.data.objects.remove(obj)
        obj = bpy.data.objects.new(name, bpy.data.lights.new(name, "SUN"))
        obj[ROLE_KEY] = role
        scene.collection.objects.link(obj)
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
    """Create or update the key (and fill) lights and the world; return (key, fill or None)."""
    scene = context.scene
    canvas = find_role(scene, "canvas")
    distance = max(canvas.dimensions[:2]) if canvas is not None else 1.0

    key = _sun(scene, "key_light", KEY_NAME)
    aim_sun(key, azimuth, elevation, distance)
    key.data.energy = sun_strength(brightness, elevation)
    key.data.angle = KEY_ANGLE

    fill_obj = find_role(scene, "fill_light")
    if fill:
        fill_obj = _sun(scene, "fill_light", FILL_NAME)
        aim_sun(fill_obj, azimuth + math.pi, FILL_ELEVATION, distance)
        fill_obj.data.energy = FILL_FRACTION * sun_strength(brightness, FILL_ELEVATION)
        fill_obj.data.angle = FILL_ANGLE
    elif fill_obj is not None:
        light = fill_obj.data
        bpy.data.objects.remove(fill_obj)
        if light.users == 0:
            bpy.data.lights.remove(light)
        fill_obj = None

    set_world(scene)
    return key, fill_obj


def set_world(scene):
    """Give the scene a dim uniform world (created once, then reused)."""
    world = bpy.data.worlds.get(WORLD_NAME) or bpy.data.worlds.new(WORLD_NAME)
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
