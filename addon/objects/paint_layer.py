# SPDX-License-Identifier: GPL-3.0-or-later
"""A painted object's material as a coat of paint over the user's own: a copy of the material the slot had, in
which only what the paint covers changes.

In the copy, every Principled BSDF and Diffuse BSDF that reaches the active
Material Output's Surface (directly, or through Mix Shader, Add Shader and
Reroute nodes) gets:

- **colour**: the painted colour map over the colour it had, mixed by the
  paint's opacity (bare where no stroke lies, the original shows);
- **roughness** (Principled): the paint's PAINT_ROUGHNESS over the roughness
  it had (its own map or value), mixed by the opacity;
- **normal**: a Bump node adding the paint's height, ``thickness`` metres per
  unit, on top of the normal it had (its Normal Map node, or the mesh's own
  custom split normals when nothing is linked): the user's normal map keeps
  shading under the paint.

Everything else stays as the user made it: emission (a glowing part still
glows), metallic (metal under the paint stays metal: the paint takes the
metal's look, so a painted chrome cap keeps the brightness of chrome),
alpha, transmission, coat, the images a second UV map feeds, and the
material output's own Displacement. The paint's maps are read through the
UV map the source was painted in, with the source image's extension, so a
face whose UVs lie in another unit square shows the painting Blender samples
there.

The nodes added carry material.OWN_NODE_KEY (set_thickness and the map
reloads find them) and are named material.NODE_PREFIX + role; the copy
holds its original under LAYER_OF_KEY.
"""

import bpy

from .. import values
from ..scene.material import (
    FINE_BUMP_STRENGTH,
    NODE_PREFIX,
    OWN_NODE_KEY,
    PAINT_ROUGHNESS,
    normal_strength,
    own_nodes,
    set_material_displacement,
)

LAYER_OF_KEY = "paint_relief_layer_of"
SHADER_COLOUR = {"ShaderNodeBsdfPrincipled": "Base Color", "ShaderNodeBsdfDiffuse": "Color"}
PASS_THROUGH = ("ShaderNodeMixShader", "ShaderNodeAddShader", "NodeReroute")


def active_output(tree):
    """The Material Output node Blender renders with (the active one, else the first), or None."""
    outputs = [node for node in tree.nodes if node.bl_idname == "ShaderNodeOutputMaterial"]
    return next((node for node in outputs if node.is_active_output), outputs[0] if outputs else None)


def surface_shaders(tree):
    """The Principled and Diffuse BSDF nodes of ``tree`` whose shading reaches the active output's Surface, in the
    order they are met (each once)."""
    output = active_output(tree)
    found, seen = [], set()
    stack = [link.from_node for link in output.inputs["Surface"].links] if output is not None else []
    while stack:
        node = stack.pop(0)
        if node.name in seen:
            continue
        seen.add(node.name)
        if node.bl_idname in SHADER_COLOUR:
            found.append(node)
        elif node.bl_idname in PASS_THROUGH:
            stack.extend(link.from_node for socket in node.inputs if socket.type == "SHADER" or
                         node.bl_idname == "NodeReroute" for link in socket.links if not link.is_muted)
    return found


def can_layer(material):
    """Whether ``material`` has nodes whose surface a coat of paint can go on (surface_shaders finds one)."""
    return (material is not None and material.use_nodes and material.node_tree is not None
            and bool(surface_shaders(material.node_tree)))


def layered_material(original, images, thickness, uv_map, extension, name, connect_displacement=False,
                     normal_map=False, vector_feed=None):
    """A copy of ``original`` named ``name`` wearing the paint of ``images`` ({role: image}: colour, height,
    opacity, and normal with ``normal_map``) as the module docstring says; ``thickness``: metres of paint of
    height 1; ``uv_map``: the UV map the maps are read through; ``extension``: the Image Texture extension
    ('REPEAT', 'EXTEND', 'CLIP', 'MIRROR'); ``connect_displacement``: the paint's height drives the output's
    Displacement (Cycles displacement at render time); ``normal_map``: the painter's tangent-space normal map
    shades the paint's relief where a shader has no normal of its own (over a normal of its own, the Bump of
    the paint's height at full strength does); ``vector_feed``: (node name, output identifier) of the nodes
    that fed the source image's Vector (a Mapping, a mirroring chain), whose output then reads the maps too,
    else None. Requires ``can_layer(original)``."""
    material = original.copy()
    material.name = name
    if material.use_fake_user:
        material.use_fake_user = False
    material[LAYER_OF_KEY] = original
    tree = material.node_tree
    before = set(tree.nodes)
    uv = tree.nodes.new("ShaderNodeUVMap")
    uv.uv_map = uv_map
    colour, height, opacity = (_image(tree, uv, images[role], label, interpolation, extension)
                               for role, label, interpolation in ((values.COLOR_MAP, "Colour", "Linear"),
                                                                  (values.HEIGHT_MAP, "Height", "Cubic"),
                                                                  (values.OPACITY_MAP, "Opacity", "Linear")))
    painter_normal = _painter_normal(tree, uv, images, thickness, uv_map, extension) if normal_map else None
    bumps = {}
    for shader in surface_shaders(tree):
        mix = _coat(tree, shader.inputs[SHADER_COLOUR[shader.bl_idname]], colour.outputs["Color"],
                    opacity.outputs["Color"], "RGBA")
        mix.label = "Paint over colour"
        if "Roughness" in shader.inputs:
            roughness = shader.inputs["Roughness"]
            mix = _coat(tree, roughness, None, opacity.outputs["Color"], "FLOAT")
            _socket(mix.inputs, "B_Float").default_value = PAINT_ROUGHNESS
            mix.label = "Paint over roughness"
        _bump_under(tree, shader.inputs["Normal"], height, thickness, bumps, painter_normal)
    displacement = tree.nodes.new("ShaderNodeDisplacement")
    displacement.space = "OBJECT"
    displacement.inputs["Midlevel"].default_value = 0.0
    displacement.inputs["Scale"].default_value = thickness
    tree.links.new(height.outputs["Color"], displacement.inputs["Height"])
    if connect_displacement:
        tree.links.new(displacement.outputs["Displacement"], active_output(tree).inputs["Displacement"])
        set_material_displacement(material, "DISPLACEMENT")
    else:
        set_material_displacement(material, "BUMP")
    for node, role in ((colour, "Colour"), (height, "Height"), (opacity, "Opacity"), (displacement, "Displacement"),
                       (uv, "UV")):
        node.name = NODE_PREFIX + role
    for node in set(tree.nodes) - before:
        node[OWN_NODE_KEY] = True
        node.location = (node.location[0] - 600, node.location[1])
    _read_through(tree, uv, vector_feed)
    return material


def update_layer(material, images, thickness, uv_map, extension, connect_displacement=False, normal_map=False,
                 vector_feed=None):
    """Point the coat of paint of ``material`` (made by ``layered_material``, with the same arguments) at new maps,
    thickness, UV map and extension, in place; True when it could (every node of the coat is there and it has
    the same kind of relief), else False, changing nothing. Nodes and links the user added stay."""
    tree = material.node_tree
    nodes = own_nodes(tree) if tree is not None else {}
    roles = ("Colour", "Height", "Opacity", "UV", "Displacement")
    if not all(NODE_PREFIX + role in nodes for role in roles) or \
            (NODE_PREFIX + "Normal Map" in nodes) != normal_map or \
            not any(node.bl_idname == "ShaderNodeBump" for node in nodes.values()):
        return False
    nodes[NODE_PREFIX + "UV"].uv_map = uv_map
    _read_through(tree, nodes[NODE_PREFIX + "UV"], vector_feed)
    for node in nodes.values():
        if node.bl_idname == "ShaderNodeTexImage":
            node.image = images[{"Colour": values.COLOR_MAP, "Height": values.HEIGHT_MAP,
                                 "Opacity": values.OPACITY_MAP, "Normal": values.NORMAL_MAP}[node.label]]
            node.extension = extension
        elif node.bl_idname == "ShaderNodeBump":
            node.inputs["Distance"].default_value = thickness
        elif node.bl_idname == "ShaderNodeNormalMap":
            node.uv_map = uv_map
            node.inputs["Strength"].default_value = normal_strength(thickness)
    displacement, output = nodes[NODE_PREFIX + "Displacement"], active_output(tree)
    displacement.inputs["Scale"].default_value = thickness
    linked = [link for link in output.inputs["Displacement"].links if link.from_node == displacement]
    if connect_displacement and not linked:
        tree.links.new(displacement.outputs["Displacement"], output.inputs["Displacement"])
    for link in linked if not connect_displacement else ():
        tree.links.remove(link)
    set_material_displacement(material, "DISPLACEMENT" if connect_displacement else "BUMP")
    return True


def _read_through(tree, uv, vector_feed):
    """Link the Vector of every image node the UV Map node ``uv`` feeds (or the feed fed) to ``vector_feed``'s
    output when ``tree`` holds that node, else to ``uv``."""
    feed = tree.nodes.get(vector_feed[0]) if vector_feed else None
    output = next((socket for socket in feed.outputs if socket.identifier == vector_feed[1]), None) if feed else None
    for node in own_nodes(tree).values():
        if node.bl_idname == "ShaderNodeTexImage":
            tree.links.new(output or uv.outputs["UV"], node.inputs["Vector"])


def _image(tree, uv, image, label, interpolation, extension):
    """An Image Texture node showing ``image`` through the UV Map node ``uv``."""
    node = tree.nodes.new("ShaderNodeTexImage")
    node.image, node.label, node.interpolation, node.extension = image, label, interpolation, extension
    tree.links.new(uv.outputs["UV"], node.inputs["Vector"])
    return node


def _coat(tree, socket, paint, opacity, data_type):
    """Put a Mix node (``data_type`` 'RGBA' or 'FLOAT') before ``socket``: A what fed it (its link, else its
    value), B ``paint`` (an output socket, or None to set later), factor ``opacity``. Returns the Mix node."""
    mix = tree.nodes.new("ShaderNodeMix")
    mix.data_type = data_type
    mix.clamp_factor = True
    kind = "Color" if data_type == "RGBA" else "Float"
    a, b = _socket(mix.inputs, "A_" + kind), _socket(mix.inputs, "B_" + kind)
    if socket.links:
        tree.links.new(socket.links[0].from_socket, a)
    else:
        a.default_value = socket.default_value
    if paint is not None:
        tree.links.new(paint, b)
    tree.links.new(opacity, _socket(mix.inputs, "Factor_Float"))
    tree.links.new(_socket(mix.outputs, "Result_" + kind), socket)
    return mix


def _socket(sockets, identifier):
    """The socket of ``sockets`` whose identifier is ``identifier`` (a Mix node's sockets share names)."""
    return next(socket for socket in sockets if socket.identifier == identifier)


def _painter_normal(tree, uv, images, thickness, uv_map, extension):
    """The Normal Map node of the painter's normal map (``images``' normal.exr), ``thickness`` setting its
    strength as the canvas's does."""
    image = _image(tree, uv, images[values.NORMAL_MAP], "Normal", "Linear", extension)
    normal = tree.nodes.new("ShaderNodeNormalMap")
    normal.space, normal.uv_map = "TANGENT", uv_map
    normal.inputs["Strength"].default_value = normal_strength(thickness)
    normal.name = NODE_PREFIX + "Normal Map"
    tree.links.new(image.outputs["Color"], normal.inputs["Color"])
    return normal


def _bump_under(tree, normal, height, thickness, bumps, painter_normal=None):
    """Link a Bump node of the paint's ``height`` to the shader input ``normal``, over the normal it had (one Bump
    per distinct normal fed, kept in ``bumps``); where it had none and ``painter_normal`` (a Normal Map node) is
    given, over that, and at full strength over a normal of its own then."""
    fed = normal.links[0].from_socket if normal.links else None
    key = None if fed is None else (fed.node.name, fed.identifier)
    if key not in bumps:
        bump = tree.nodes.new("ShaderNodeBump")
        bump.inputs["Strength"].default_value = (1.0 if painter_normal is not None and fed is not None
                                                 else FINE_BUMP_STRENGTH)
        if fed is None and painter_normal is not None:
            fed = painter_normal.outputs["Normal"]
        bump.inputs["Distance"].default_value = thickness
        tree.links.new(height.outputs["Color"], bump.inputs["Height"])
        if fed is not None:
            tree.links.new(fed, bump.inputs["Normal"])
        bump.name = NODE_PREFIX + "Bump" + ("" if not bumps else " {}".format(len(bumps) + 1))
        bumps[key] = bump
    tree.links.new(bumps[key].outputs["Normal"], normal)


def layer_origin(material):
    """The material ``material`` is a coat of paint over (LAYER_OF_KEY), or None."""
    origin = material.get(LAYER_OF_KEY) if material is not None else None
    return origin if isinstance(origin, bpy.types.Material) else None
