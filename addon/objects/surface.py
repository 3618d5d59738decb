# SPDX-License-Identifier: GPL-3.0-or-later
"""What the painter needs of a mesh object: its triangles' UV coordinates, world positions and material slots,
and the pictures its texture set is painted from (``sources`` chooses them).

A material's picture is the image that feeds the Base Color of its
Principled BSDF (an Image Texture node linked to the input), else a Cycles
bake of its diffuse colour (DIFFUSE with COLOR only: the surface's colour
without the scene's light) into the UV layout. An image with no file on
disk (packed, generated or baked) is written out as a PNG for the painter.
"""

import os

import bpy
import numpy as np

BAKE_IMAGE_NAME = "Paint Relief Bake"
BAKE_NODE_NAME = "Paint Relief Bake Target"


def mesh_problem(obj):
    """One sentence when ``obj`` cannot be painted as an object (not a mesh, no faces, no UV map), else None."""
    if obj is None or obj.type != "MESH":
        return "Select a mesh object to paint its texture."
    if len(obj.data.polygons) == 0:
        return "Object {} has no faces to paint.".format(obj.name)
    if len(obj.data.uv_layers) == 0:
        return ("Object {} has no UV map: press Smart UV Project in the Paint Object panel to unwrap it, then "
                "paint.".format(obj.name))
    return None


def uv_map_name(obj):
    """The name of the UV map the painted texture follows: the one Blender renders with."""
    layers = obj.data.uv_layers
    rendered = next((layer for layer in layers if getattr(layer, "active_render", False)), None)
    return (rendered or layers.active or layers[0]).name


def mesh_triangles(context, obj):
    """(uv (T, 3, 2) float64, position (T, 3, 3) float64 metres, material_index (T,) int32): the corners of the
    object's mesh's loop triangles (its own mesh, before modifiers), UVs of ``uv_map_name``, positions in the
    world (the object's transform and the scene's unit scale applied), and each triangle's material slot."""
    mesh = obj.data
    mesh.calc_loop_triangles()
    count = len(mesh.loop_triangles)
    loops = np.empty(count * 3, np.int32)
    mesh.loop_triangles.foreach_get("loops", loops)
    vertices = np.empty(count * 3, np.int32)
    mesh.loop_triangles.foreach_get("vertices", vertices)
    material_index = np.empty(count, np.int32)
    mesh.loop_triangles.foreach_get("material_index", material_index)
    uv = np.empty(len(mesh.loops) * 2, np.float32)
    mesh.uv_layers[uv_map_name(obj)].data.foreach_get("uv", uv)
    co = np.empty(len(mesh.vertices) * 3, np.float32)
    mesh.vertices.foreach_get("co", co)
    world = np.array(obj.matrix_world, np.float64)
    points = co.reshape(-1, 3).astype(np.float64) @ world[:3, :3].T + world[:3, 3]
    points *= context.scene.unit_settings.scale_length
    return (uv.reshape(-1, 2)[loops].astype(np.float64).reshape(count, 3, 2),
            points[vertices].reshape(count, 3, 3), material_index)


def base_color_image(obj, materials=None):
    """The image an Image Texture node feeds into the Base Color of a Principled BSDF of the object's materials
    (the first found, slot by slot; or of ``materials`` when given), or None."""
    for material in [slot.material for slot in obj.material_slots] if materials is None else materials:
        if material is None or material.node_tree is None:
            continue
        for node in material.node_tree.nodes:
            if node.bl_idname != "ShaderNodeBsdfPrincipled":
                continue
            for link in node.inputs["Base Color"].links:
                if link.from_node.bl_idname == "ShaderNodeTexImage" and link.from_node.image is not None:
                    return link.from_node.image
    return None


def image_on_disk(image):
    """The absolute path of ``image``'s file when it is on disk as the image shows it (not packed, not
    generated, not edited since), else None."""
    if image.packed_file is not None or image.source != "FILE" or image.is_dirty or not image.filepath:
        return None
    path = os.path.normpath(bpy.path.abspath(image.filepath, library=image.library))
    return path if os.path.isfile(path) else None


def write_image(image, path):
    """Write ``image``'s pixels to the PNG ``path`` (16 bits, its colour as Blender shows it: float images
    converted from scene-linear to sRGB); returns ``path``."""
    from ...core.colour import linear_to_srgb
    from ...core.files.writing import write_png

    width, height = image.size
    if width == 0 or height == 0:
        raise ValueError("Image {} has no pixels to paint.".format(image.name))
    pixels = np.empty(width * height * 4, np.float32)
    image.pixels.foreach_get(pixels)
    rgb = pixels.reshape(height, width, 4)[::-1, :, :3]
    if image.is_float:
        rgb = linear_to_srgb(np.clip(rgb, 0.0, None))
    write_png(path, np.clip(rgb, 0.0, 1.0), bits=16)
    return path


def bake_diffuse_colours(context, obj, size, paths):
    """Bake ``obj``'s diffuse colour (Cycles, DIFFUSE with COLOR only) in its UV layout, each material of the
    dict ``paths`` into its own ``size`` x ``size`` image written to the PNG ``paths[material]`` (one bake: the
    faces of the object's other materials go to a target thrown away). The scene's render engine and samples,
    the selection and the materials are as they were afterwards."""
    scene = context.scene
    engine, samples = scene.render.engine, scene.cycles.samples
    selected = [o for o in context.view_layer.objects if o.select_get()]
    active = context.view_layer.objects.active
    targets = {material: bpy.data.images.new(BAKE_IMAGE_NAME, size, size, alpha=False) for material in paths}
    throwaway = None
    added, nodes_off = [], []
    try:
        for material in {slot.material for slot in obj.material_slots if slot.material is not None}:
            if material.node_tree is None or not material.use_nodes:
                nodes_off.append(material)
                material.use_nodes = True
            if material not in targets and throwaway is None:
                throwaway = bpy.data.images.new(BAKE_IMAGE_NAME, 8, 8, alpha=False)
            node = material.node_tree.nodes.new("ShaderNodeTexImage")
            node.name = BAKE_NODE_NAME
            node.image = targets.get(material, throwaway)
            material.node_tree.nodes.active = node
            added.append((material, node))
        scene.render.engine = "CYCLES"
        scene.cycles.samples = 1
        for other in selected:
            other.select_set(False)
        obj.select_set(True)
        context.view_layer.objects.active = obj
        bpy.ops.object.bake(type="DIFFUSE", pass_filter={"COLOR"}, margin=8, use_clear=True)
        for material, path in paths.items():
            write_image(targets[material], path)
    finally:
        for material, node in added:
            material.node_tree.nodes.remove(node)
        for material in nodes_off:
            material.use_nodes = False
        for image in list(targets.values()) + ([throwaway] if throwaway is not None else []):
            bpy.data.images.remove(image)
        scene.render.engine, scene.cycles.samples = engine, samples
        obj.select_set(False)
        for other in selected:
            other.select_set(True)
        context.view_layer.objects.active = active
