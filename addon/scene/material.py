# SPDX-License-Identifier: GPL-3.0-or-later
"""The canvas's material: the node tree that shades the painted maps.

Colour from the colour map; roughness from glossy paint to matte bare
canvas with the opacity; a Bump node adding paint detail finer than the
geometry and a canvas weave where the paint is thin (over the painter's
tangent-space normals for a *Normal Map* canvas); a Displacement node
reading the height map, linked to the output only when Cycles displaces the
surface at render time (``CYCLES_ADAPTIVE``; a ``MESH`` canvas carries the
relief in its geometry, and a linked output would add the same slopes again
as bump).

The nodes made here carry OWN_NODE_KEY, and the ones a rebuild updates are
named NODE_PREFIX + role; a rebuild changes only these and leaves the nodes
a user added, and their links, as they are.
"""

import bpy

from .. import values

MATERIAL_NAME = "Paint Relief Canvas"
# Node names of the canvas material's own nodes; a rebuild updates these and leaves every other node alone.
NODE_PREFIX = "Paint Relief "
OWN_NODE_KEY = "paint_relief_node"

# Paint thickness (metres) at which the Normal Map node's strength is 1 (the normal map's own relief).
NORMAL_MAP_THICKNESS = 0.002
# Roughness of fully covering paint and of bare canvas.
PAINT_ROUGHNESS = 0.35
CANVAS_ROUGHNESS = 0.8
# Strength of the Bump node that adds detail finer than the displaced geometry.
FINE_BUMP_STRENGTH = 0.3
# Canvas weave: thread period (metres) and its height relative to the paint thickness.
WEAVE_PERIOD = 0.0008
WEAVE_HEIGHT = 0.05


def own_nodes(tree):
    """{name: node} of the Paint Relief nodes of ``tree`` (marked by OWN_NODE_KEY)."""
    return {node.name: node for node in tree.nodes if node.get(OWN_NODE_KEY)}


def own_images(material):
    """The images the Paint Relief image nodes of ``material`` show (a set; empty without a node tree)."""
    if not material or material.node_tree is None:
        return set()
    return {node.image for node in own_nodes(material.node_tree).values()
            if node.bl_idname == "ShaderNodeTexImage" and node.image is not None}


def normal_strength(thickness):
    """Strength of the Normal Map node for paint ``thickness`` metres thick (1 at NORMAL_MAP_THICKNESS)."""
    return max(0.0, thickness / NORMAL_MAP_THICKNESS)


def set_material_displacement(material, method):
    """Set the material's displacement method ('BUMP', 'DISPLACEMENT', 'BOTH') where this Blender keeps it."""
    if hasattr(material, "displacement_method"):
        material.displacement_method = method
    if hasattr(material, "cycles") and hasattr(material.cycles, "displacement_method"):
        material.cycles.displacement_method = method


def canvas_material(material, images, thickness, connect_displacement, normal_map):
    """The canvas material for ``images`` ({file name: image}) and paint ``thickness`` metres thick.

    ``material`` (a canvas's present material, or None) is updated in place
    when it is Paint Relief's with all its own nodes and the same kind of
    relief (normal map or not); its own nodes are built again when some are
    gone or the kind changed; a new material is made when there is none or
    it is not Paint Relief's.
    """
    if material is None or not material.get(OWN_NODE_KEY):
        material = bpy.data.materials.new(MATERIAL_NAME)
        build_material(material, images, thickness, connect_displacement, normal_map)
        return material
    has_normal = material.node_tree is not None and (NODE_PREFIX + "Normal Map") in material.node_tree.nodes
    if has_normal != normal_map or not update_material(material, images, thickness, connect_displacement):
        build_material(material, images, thickness, connect_displacement, normal_map)
    elif normal_map:
        nodes = material.node_tree.nodes
        nodes[NODE_PREFIX + "Normal Map"].inputs["Strength"].default_value = normal_strength(thickness)
        for node in nodes:
            if node.bl_idname == "ShaderNodeTexImage" and node.get(OWN_NODE_KEY) and node.label == "Normal":
                node.image = images[values.NORMAL_MAP]
    return material


def update_material(material, images, thickness, connect_displacement):
    """Point an existing canvas material at new maps and thickness; True when its own nodes are all there.

    User nodes and links are untouched. Returns False (changing nothing)
    when some of the Paint Relief nodes are gone, so the caller builds them again.
    """
    tree = material.node_tree
    nodes = own_nodes(tree) if tree is not None else {}
    names = [NODE_PREFIX + name for name in ("Colour", "Height", "Opacity", "Bump", "Displacement", "Output")]
    if not all(name in nodes for name in names):
        return False
    for name, key in (("Colour", values.COLOR_MAP), ("Height", values.HEIGHT_MAP), ("Opacity", values.OPACITY_MAP)):
        nodes[NODE_PREFIX + name].image = images[key]
    nodes[NODE_PREFIX + "Bump"].inputs["Distance"].default_value = thickness
    displacement, output = nodes[NODE_PREFIX + "Displacement"], nodes[NODE_PREFIX + "Output"]
    displacement.inputs["Scale"].default_value = thickness
    linked = [l for l in output.inputs["Displacement"].links if l.from_node == displacement]
    if connect_displacement and not linked:
        tree.links.new(displacement.outputs["Displacement"], output.inputs["Displacement"])
    elif not connect_displacement:
        for link in linked:
            tree.links.remove(link)
    return True


def build_material(material, images, thickness, connect_displacement, normal_map=False, uv_map="UVMap",
                   extension="EXTEND"):
    """Fill ``material``'s node tree with the canvas shader; return the tree.

    thickness: metres of paint of height 1. connect_displacement: link the
    Displacement node to the material output (CYCLES_ADAPTIVE) or leave it
    unconnected (MESH, where the geometry is displaced already). normal_map:
    shade with the painter's normal map (``images`` holds it then), whose tangents follow the UV map ``uv_map``
    (the one the maps are read through: Blender renders with it). ``extension``: how the maps are read beyond
    0..1 (the Image Texture extension; an object's UVs may lie in other unit squares). Earlier
    Paint Relief nodes and Blender's default nodes are replaced; nodes the
    user added stay. The nodes made here carry OWN_NODE_KEY, and the ones
    :func:`update_material` needs are named NODE_PREFIX + role.
    """
    tree = _cleared_tree(material)
    before = set(tree.nodes)
    uv, colour, height, opacity = _map_nodes(tree, images, extension)
    bsdf, output = _surface(tree, colour)
    _roughness_from_opacity(tree, opacity, bsdf)
    bump = _fine_bump(tree, _paint_and_weave_height(tree, uv, height, opacity), thickness)
    if normal_map:
        _normal_map(tree, uv, images[values.NORMAL_MAP], bump, thickness, uv_map, extension)
    _link(tree, bump.outputs["Normal"], bsdf.inputs["Normal"])
    displacement = _displacement(tree, height, output, thickness, connect_displacement)
    for node, name in ((colour, "Colour"), (height, "Height"), (opacity, "Opacity"), (bump, "Bump"),
                       (displacement, "Displacement"), (output, "Output"), (bsdf, "BSDF")):
        node.name = NODE_PREFIX + name
    for node in set(tree.nodes) - before:
        node[OWN_NODE_KEY] = True
    output.is_active_output = True
    return tree


# ---------------------------------------------------------------------------
# the parts of the node tree, in the order build_material makes them


def _link(tree, from_socket, to_socket):
    tree.links.new(from_socket, to_socket)


def _image_node(nodes, image, label, interpolation, location, extension="EXTEND"):
    node = nodes.new("ShaderNodeTexImage")
    node.image = image
    node.label = label
    node.interpolation = interpolation
    node.extension = extension
    node.location = location
    return node


def _math_node(nodes, operation, location, label=""):
    """A Math node doing ``operation`` at ``location``, with an optional label."""
    node = nodes.new("ShaderNodeMath")
    node.operation = operation
    node.location = location
    if label:
        node.label = label
    return node


def _cleared_tree(material):
    """``material``'s node tree without its earlier Paint Relief nodes (and, the first time, without Blender's
    default Principled BSDF and Material Output); marks the material as Paint Relief's."""
    if material.node_tree is None:  # Blender 4.2 creates the tree only with use_nodes
        material.use_nodes = True
    tree = material.node_tree
    nodes = tree.nodes
    for node in list(nodes):
        if node.get(OWN_NODE_KEY) or node.bl_idname in ("ShaderNodeBsdfPrincipled", "ShaderNodeOutputMaterial") \
                and not material.get(OWN_NODE_KEY):
            nodes.remove(node)
    material[OWN_NODE_KEY] = True
    return tree


def _map_nodes(tree, images, extension):
    """The texture coordinates and the colour, height and opacity image nodes reading them by UV."""
    nodes = tree.nodes
    uv = nodes.new("ShaderNodeTexCoord")
    uv.location = (-1300, 0)
    colour = _image_node(nodes, images[values.COLOR_MAP], "Colour", "Linear", (-1000, 400), extension)
    height = _image_node(nodes, images[values.HEIGHT_MAP], "Height", "Cubic", (-1000, -300), extension)
    opacity = _image_node(nodes, images[values.OPACITY_MAP], "Opacity", "Linear", (-1000, 50), extension)
    for node in (colour, height, opacity):
        _link(tree, uv.outputs["UV"], node.inputs["Vector"])
    return uv, colour, height, opacity


def _surface(tree, colour):
    """A Principled BSDF of the colour map's colour, linked to a new Material Output: (bsdf, output)."""
    bsdf = tree.nodes.new("ShaderNodeBsdfPrincipled")
    bsdf.location = (-100, 300)
    output = tree.nodes.new("ShaderNodeOutputMaterial")
    output.location = (300, 200)
    _link(tree, bsdf.outputs["BSDF"], output.inputs["Surface"])
    _link(tree, colour.outputs["Color"], bsdf.inputs["Base Color"])
    return bsdf, output


def _roughness_from_opacity(tree, opacity, bsdf):
    """Glossy where the paint covers, matte bare canvas where it does not: opacity 0..1 maps to roughness
    CANVAS_ROUGHNESS..PAINT_ROUGHNESS."""
    roughness = tree.nodes.new("ShaderNodeMapRange")
    roughness.label = "Roughness from opacity"
    roughness.location = (-600, 150)
    roughness.inputs["To Min"].default_value = CANVAS_ROUGHNESS
    roughness.inputs["To Max"].default_value = PAINT_ROUGHNESS
    roughness.clamp = True
    _link(tree, opacity.outputs["Color"], roughness.inputs["Value"])
    _link(tree, roughness.outputs["Result"], bsdf.inputs["Roughness"])


def _paint_and_weave_height(tree, uv, height, opacity):
    """The bumped surface's height: paint height + WEAVE_HEIGHT x weave x (1 - opacity), the canvas weave (two
    perpendicular sine bands of WEAVE_PERIOD, multiplied) showing where the paint is thin. Returns its Math node."""
    nodes = tree.nodes
    weave_x = nodes.new("ShaderNodeTexWave")
    weave_y = nodes.new("ShaderNodeTexWave")
    for node, axis, y in ((weave_x, "X", -600), (weave_y, "Y", -800)):
        node.wave_type = "BANDS"
        node.bands_direction = axis
        node.wave_profile = "SIN"
        node.inputs["Scale"].default_value = values.wave_scale_for_period(WEAVE_PERIOD)
        node.inputs["Distortion"].default_value = 0.0
        node.location = (-1000, y)
        _link(tree, uv.outputs["Object"], node.inputs["Vector"])
    weave = _math_node(nodes, "MULTIPLY", (-750, -650), "Weave")
    _link(tree, weave_x.outputs["Fac"], weave.inputs[0])
    _link(tree, weave_y.outputs["Fac"], weave.inputs[1])
    bare = _math_node(nodes, "SUBTRACT", (-750, -450), "Bare canvas (1 - opacity)")
    bare.inputs[0].default_value = 1.0
    _link(tree, opacity.outputs["Color"], bare.inputs[1])
    weave_bare = _math_node(nodes, "MULTIPLY", (-550, -550))
    _link(tree, weave.outputs["Value"], weave_bare.inputs[0])
    _link(tree, bare.outputs["Value"], weave_bare.inputs[1])
    surface = _math_node(nodes, "MULTIPLY_ADD", (-350, -400), "Paint + weave height")
    surface.inputs[1].default_value = WEAVE_HEIGHT
    _link(tree, weave_bare.outputs["Value"], surface.inputs[0])
    _link(tree, height.outputs["Color"], surface.inputs[2])
    return surface


def _fine_bump(tree, surface, thickness):
    """The Bump node shading ``surface``'s height, ``thickness`` metres per unit, at FINE_BUMP_STRENGTH."""
    bump = tree.nodes.new("ShaderNodeBump")
    bump.location = (-350, -150)
    bump.inputs["Strength"].default_value = FINE_BUMP_STRENGTH
    bump.inputs["Distance"].default_value = thickness
    _link(tree, surface.outputs["Value"], bump.inputs["Height"])
    return bump


def _normal_map(tree, uv, image, bump, thickness, uv_map, extension):
    """The painter's tangent-space normals (normal.exr ``image``) under ``bump``: they shade a flat plane and
    the weave bump stacks on top (switched off for paint of no thickness)."""
    normal_image = _image_node(tree.nodes, image, "Normal", "Linear", (-1000, -1050), extension)
    _link(tree, uv.outputs["UV"], normal_image.inputs["Vector"])
    normal = tree.nodes.new("ShaderNodeNormalMap")
    normal.location = (-600, -1000)
    normal.space = "TANGENT"
    normal.uv_map = uv_map
    normal.inputs["Strength"].default_value = normal_strength(thickness)
    normal.name = NODE_PREFIX + "Normal Map"
    _link(tree, normal_image.outputs["Color"], normal.inputs["Color"])
    _link(tree, normal.outputs["Normal"], bump.inputs["Normal"])
    bump.inputs["Strength"].default_value = 0.0 if thickness <= 0 else FINE_BUMP_STRENGTH


def _displacement(tree, height, output, thickness, connect):
    """The Displacement node: the height map, ``thickness`` metres per unit, along the object's normal;
    linked to ``output`` when ``connect``."""
    displacement = tree.nodes.new("ShaderNodeDisplacement")
    displacement.location = (0, -250)
    displacement.space = "OBJECT"
    displacement.inputs["Midlevel"].default_value = 0.0
    displacement.inputs["Scale"].default_value = thickness
    _link(tree, height.outputs["Color"], displacement.inputs["Height"])
    if connect:
        _link(tree, displacement.outputs["Displacement"], output.inputs["Displacement"])
    return displacement
