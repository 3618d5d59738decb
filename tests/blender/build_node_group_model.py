# SPDX-License-Identifier: GPL-3.0-or-later
"""Build tests/models/knight_node_group/knight_node_group.blend: the knight of tests/models/knight imported with
Blender's glTF importer, its base colour (the image times the vertex colour) moved into a node group whose
output feeds the Principled BSDF's Base Color, as older glTF importers built their materials around group nodes.

    python tests/blender/build_node_group_model.py

The image stays a file beside the glTF (tests/models/knight/knight.png), named by a relative path.
"""

import os

import bpy

MODELS = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "models")
SOURCE = os.path.join(MODELS, "knight", "knight.gltf")
TARGET = os.path.join(MODELS, "knight_node_group", "knight_node_group.blend")
GROUP = "glTF Base Color"


def base_colour_group():
    """The node group: Base Color Texture times Vertex Color, out as Base Color."""
    tree = bpy.data.node_groups.new(GROUP, "ShaderNodeTree")
    tree.interface.new_socket("Base Color Texture", in_out="INPUT", socket_type="NodeSocketColor")
    tree.interface.new_socket("Vertex Color", in_out="INPUT", socket_type="NodeSocketColor")
    tree.interface.new_socket("Base Color", in_out="OUTPUT", socket_type="NodeSocketColor")
    inputs = tree.nodes.new("NodeGroupInput")
    outputs = tree.nodes.new("NodeGroupOutput")
    mix = tree.nodes.new("ShaderNodeMix")
    mix.data_type = "RGBA"
    mix.blend_type = "MULTIPLY"
    mix.inputs["Factor"].default_value = 1.0
    inputs.location, mix.location, outputs.location = (-300, 0), (0, 0), (300, 0)
    colour_in = {socket.identifier: socket for socket in mix.inputs}
    colour_out = {socket.identifier: socket for socket in mix.outputs}
    tree.links.new(inputs.outputs["Base Color Texture"], colour_in["A_Color"])
    tree.links.new(inputs.outputs["Vertex Color"], colour_in["B_Color"])
    tree.links.new(colour_out["Result_Color"], outputs.inputs["Base Color"])
    return tree


def main():
    import addon_utils  # importable once bpy is

    addon_utils.enable("io_scene_gltf2")
    bpy.context.preferences.filepaths.save_version = 0      # no .blend1 beside it
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=SOURCE)
    material = bpy.data.materials["knight"]
    nodes, links = material.node_tree.nodes, material.node_tree.links
    bsdf = next(node for node in nodes if node.bl_idname == "ShaderNodeBsdfPrincipled")
    image = next(node for node in nodes if node.bl_idname == "ShaderNodeTexImage")
    attribute = next(node for node in nodes if node.bl_idname == "ShaderNodeAttribute")
    for node in [node for node in nodes if node.bl_idname == "ShaderNodeMix"]:
        nodes.remove(node)
    group = nodes.new("ShaderNodeGroup")
    group.node_tree = base_colour_group()
    group.label = GROUP
    group.location = (bsdf.location.x - 250, bsdf.location.y)
    links.new(image.outputs["Color"], group.inputs["Base Color Texture"])
    links.new(attribute.outputs["Color"], group.inputs["Vertex Color"])
    links.new(group.outputs["Base Color"], bsdf.inputs["Base Color"])
    os.makedirs(os.path.dirname(TARGET), exist_ok=True)
    bpy.ops.wm.save_as_mainfile(filepath=TARGET, compress=True, relative_remap=True)
    # the image is named relative to the saved file
    image.image.filepath = bpy.path.relpath(image.image.filepath_raw)
    bpy.ops.wm.save_mainfile(compress=True)
    print("saved", TARGET, image.image.filepath)


main()
