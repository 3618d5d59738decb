# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared by the Blender check scripts: load the extension, record each check's findings or its traceback."""

import os
import sys
import traceback

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

RESULTS = {}


def check(function):
    """Run one check now, recording what it returns (or its traceback) under its name."""
    try:
        RESULTS[function.__name__] = function()
    except Exception:
        RESULTS[function.__name__] = {"exception": traceback.format_exc()}
    return function


def load_extension(work):
    """Import bpy and the repository as the package ``paint_relief`` (through a symbolic link in the
    folder ``work``), start from an empty scene and register the extension as Blender would; returns bpy."""
    link = os.path.join(work, "pkg", "paint_relief")
    os.makedirs(os.path.dirname(link), exist_ok=True)
    if not os.path.islink(link):
        os.symlink(REPO, link)
    sys.path.insert(0, os.path.dirname(link))

    import bpy
    import paint_relief

    # An empty scene: the start-up file's cube would hide the canvas from the camera.
    bpy.ops.wm.read_factory_settings(use_empty=True)
    paint_relief.register()
    return bpy


def shade_colour_map(material, shader, colour_input, shader_output):
    """Replace the canvas ``material``'s surface by a new node of type ``shader`` (e.g. "ShaderNodeEmission") whose
    input ``colour_input`` reads the colour.exr texture and whose output ``shader_output`` is the surface; return
    the new node."""
    tree = material.node_tree
    colour = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeTexImage"
                  and os.path.basename(n.image.filepath) == "color.exr")
    output = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
    node = tree.nodes.new(shader)
    tree.links.new(colour.outputs["Color"], node.inputs[colour_input])
    tree.links.new(node.outputs[shader_output], output.inputs["Surface"])
    return node
