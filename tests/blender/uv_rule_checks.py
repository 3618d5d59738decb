# SPDX-License-Identifier: GPL-3.0-or-later
"""Run Paint Object inside Blender on UVs as Blender reads them and print what it did, for
tests/test_uv_rules_blender.py.

Run in its own process (``bpy`` can be imported once per process), with
``BLENDER_USER_RESOURCES`` pointing at a throw-away folder::

    BLENDER_USER_RESOURCES=/tmp/x python tests/blender/uv_rule_checks.py WORK_DIR

A plane whose UVs lie at u 1..2 under an image set to Clip is refused in one
sentence and under Repeat paints the bytes of the same plane at u 0..1; a
grid whose Base Color image reads a second UV map (its faces' UVs of the
first map moved aside and shuffled) through a Reroute is painted in that map. The last line
printed is ``RESULTS <json>``.
"""

import json
import os
import sys

from recorder import RESULTS, check, load_extension

WORK = os.path.abspath(sys.argv[1])
bpy = load_extension(WORK)
SIZE = 256


def run(op, **kwargs):
    """Call an operator; (sorted result or None, the error it reported)."""
    try:
        return sorted(op(**kwargs)), ""
    except RuntimeError as error:
        return None, str(error)


def picture():
    """The path of a random 256 x 256 picture of 8 x 8 flat blocks (seed 21), written once."""
    import numpy as np
    from paint_relief.core.files.writing import write_png

    path = os.path.join(WORK, "blocks.png")
    if not os.path.isfile(path):
        coarse = np.random.default_rng(21).random((8, 8, 3))
        write_png(path, np.repeat(np.repeat(coarse, SIZE // 8, axis=0), SIZE // 8, axis=1), bits=16)
    return path


def image_material(name, extension="REPEAT"):
    """A material whose Principled BSDF's Base Color reads ``picture()`` with the ``extension``; (material, node)."""
    material = bpy.data.materials.new(name)
    if material.node_tree is None:
        material.use_nodes = True
    nodes = material.node_tree.nodes
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = bpy.data.images.load(picture(), check_existing=True)
    texture.extension = extension
    bsdf = next(node for node in nodes if node.bl_idname == "ShaderNodeBsdfPrincipled")
    material.node_tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
    return material, texture


def plane(name, shift, extension, location):
    """A 1 m plane whose UVs lie at u ``shift``..``shift`` + 1, its material's image set to ``extension``."""
    bpy.ops.mesh.primitive_plane_add(size=1.0, location=location)
    obj = bpy.context.active_object
    obj.name = name
    obj.data.materials.append(image_material(name, extension)[0])
    uv = obj.data.uv_layers.active.data
    for loop in uv:
        loop.uv = (loop.uv[0] + shift, loop.uv[1])
    return obj


def paint(obj, folder):
    """Paint ``obj`` at SIZE texels into ``WORK/folder``; (result, error, the folder)."""
    for other in bpy.context.view_layer.objects:
        other.select_set(other == obj)
    bpy.context.view_layer.objects.active = obj
    bpy.context.scene.paint_relief.object_output_dir = os.path.join(WORK, folder)
    result, error = run(bpy.ops.paint_relief.paint_object, texture_size=SIZE)
    return result, error, os.path.join(WORK, folder)


def digests(folder):
    """{map name: SHA-256} of the colour, height and opacity maps in ``folder``."""
    import hashlib

    return {name: hashlib.sha256(open(os.path.join(folder, name), "rb").read()).hexdigest()
            for name in ("color.exr", "height.exr", "opacity.exr")}


@check
def plane_beyond_the_square():
    """The same plane at u 0..1 and at u 1..2 under Repeat, and at u 1..2 under Clip and Extend."""
    from paint_relief.addon.objects import sources

    bpy.context.scene.paint_relief.seed = 5
    found = {}
    for name, shift, extension in (("Home", 0.0, "REPEAT"), ("Far", 1.0, "REPEAT"), ("Clipped", 1.0, "CLIP"),
                                   ("Extended", 1.0, "EXTEND")):
        obj = plane(name, shift, extension, (0.0, 0.0, 0.0))
        source_set = sources.texture_sources(bpy.context, obj, "", SIZE, WORK)
        result, error, folder = paint(obj, name.lower())
        found[name] = {"result": result, "error": error, "exists": os.path.isdir(folder),
                       "extensions": source_set.extensions, "uv_maps": source_set.uv_maps,
                       "slots": [slot.material.name for slot in obj.material_slots],
                       "digests": digests(folder) if result else {},
                       "cells": json.load(open(os.path.join(folder, "report.json")))["atlas"]["cells"]
                       if result else []}
        obj.hide_set(True)
        obj.hide_render = True
    return found


def face_uvs(obj, name):
    """(F, 4, 2) float64: the UVs of each quad face of ``obj``'s mesh in its UV map ``name``."""
    import numpy as np

    mesh = obj.data
    uv = np.empty(len(mesh.loops) * 2, np.float32)
    mesh.uv_layers[name].data.foreach_get("uv", uv)
    starts = np.array([polygon.loop_start for polygon in mesh.polygons])
    return uv.reshape(-1, 2)[starts[:, None] + np.arange(4)].astype(np.float64)


def points_in_faces(quads, per_face=24):
    """(face (P,), uv (P, 2)): random points (seed 0) inside each quad of ``quads`` (F, 4, 2) (bilinear)."""
    import numpy as np

    a, b = np.random.default_rng(0).random((2, len(quads), per_face))
    q = quads[:, None]
    points = ((1 - a)[..., None] * (1 - b)[..., None] * q[..., 0, :] + a[..., None] * (1 - b)[..., None] * q[..., 1, :]
              + a[..., None] * b[..., None] * q[..., 2, :] + (1 - a)[..., None] * b[..., None] * q[..., 3, :])
    return np.repeat(np.arange(len(quads)), per_face), points.reshape(-1, 2)


def sampled(image, uv):
    """(P,) the luminance of (H, W, 3) ``image`` at UV ``uv`` (P, 2), the nearest texel (v up, row 0 at the top)."""
    import numpy as np

    h, w = image.shape[:2]
    rows = np.clip(((1 - uv[:, 1]) * h).astype(int), 0, h - 1)
    cols = np.clip((uv[:, 0] * w).astype(int), 0, w - 1)
    return image[rows, cols].mean(axis=1)


@check
def second_uv_map():
    """A grid of 8 x 8 faces with two UV maps: UVMap (rendered) over u 0..0.45 and UVMap.001 over u 0.55..1, the
    same faces' UVs moved and handed out shuffled; its Base Color image reads UVMap.001 through a Reroute from a UV
    Map node. Painted in UVMap.001, the colour map follows the picture at UVMap.001's points and is bare canvas
    at UVMap's."""
    import numpy as np
    from paint_relief.addon.objects import sources, surface
    from paint_relief.core.colour import srgb_to_linear
    from paint_relief.core.files.reading import read_exr, read_image

    bpy.context.scene.paint_relief.seed = 6
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=9, y_subdivisions=9, size=1.0, location=(3.0, 0.0, 0.0))
    grid = bpy.context.active_object
    grid.name = "Grid"
    mesh = grid.data
    first = mesh.uv_layers[0]
    first.name = "UVMap"
    second = mesh.uv_layers.new(name="UVMap.001")
    mesh.uv_layers.active = first
    first.active_render = True
    quads = face_uvs(grid, "UVMap") * [0.45, 1.0]             # the rendered map: u 0..0.45
    shuffled = quads[np.random.default_rng(3).permutation(len(quads))] + [0.55, 0.0]    # u 0.55..1, faces shuffled
    for face, polygon in enumerate(mesh.polygons):
        for corner, loop in enumerate(polygon.loop_indices):
            first.data[loop].uv = quads[face, corner]
            second.data[loop].uv = shuffled[face, corner]
    material, texture = image_material("Second", "REPEAT")
    nodes, links = material.node_tree.nodes, material.node_tree.links
    uv_node = nodes.new("ShaderNodeUVMap")
    uv_node.uv_map = "UVMap.001"
    reroute = nodes.new("NodeReroute")
    links.new(uv_node.outputs["UV"], reroute.inputs[0])
    links.new(reroute.outputs[0], texture.inputs["Vector"])
    grid.data.materials.append(material)
    source_set = sources.texture_sources(bpy.context, grid, "", SIZE, WORK)
    triangles = surface.mesh_triangles(bpy.context, grid, source_set.slot_uv_maps())[0]
    rendered = surface.mesh_triangles(bpy.context, grid)[0]
    result, error, folder = paint(grid, "second")
    found = {"result": result, "error": error, "uv_maps": source_set.uv_maps, "extensions": source_set.extensions,
             "slot_uv_maps": source_set.slot_uv_maps(),
             "triangles_in_second": bool(np.array_equal(np.unique(triangles.reshape(-1, 2), axis=0),
                                                        np.unique(face_uvs(grid, "UVMap.001").reshape(-1, 2),
                                                                  axis=0))),
             "differs_from_render_map": bool(not np.allclose(triangles, rendered)),
             "render_map": next(layer.name for layer in mesh.uv_layers if layer.active_render)}
    if result:
        painted = read_exr(os.path.join(folder, "color.exr"))[0][..., :3]
        source = srgb_to_linear(read_image(picture()))
        _, second_points = points_in_faces(face_uvs(grid, "UVMap.001"))
        _, first_points = points_in_faces(face_uvs(grid, "UVMap"))
        found["r_second"] = float(np.corrcoef(sampled(painted, second_points), sampled(source, second_points))[0, 1])
        opacity = read_exr(os.path.join(folder, "opacity.exr"))[0][..., :1].repeat(3, axis=2)
        found["opacity_second"] = float(sampled(opacity, second_points).min())
        found["opacity_first"] = float(sampled(opacity, first_points).max())
    uv_node.uv_map = "Missing"
    found["missing"] = run(bpy.ops.paint_relief.paint_object, texture_size=SIZE)[1]
    return found


@check
def vector_chains():
    """Where an image is read through a Mapping node, through the glTF importer's mirroring nodes, and through a
    node that is not followed, at a few UVs."""
    import numpy as np
    from paint_relief.addon.objects.uv_chain import vector_chain

    material = bpy.data.materials.new("Chains")
    tree = material.node_tree or (setattr(material, "use_nodes", True) or material.node_tree)
    nodes, links = tree.nodes, tree.links
    uv = nodes.new("ShaderNodeUVMap")
    uv.uv_map = "UVMap"
    mapping = nodes.new("ShaderNodeMapping")
    mapping.inputs["Location"].default_value = (0.25, 0.0, 0.0)
    mapping.inputs["Scale"].default_value = (2.0, 3.0, 1.0)
    mapped = nodes.new("ShaderNodeTexImage")
    links.new(uv.outputs["UV"], mapping.inputs["Vector"])
    links.new(mapping.outputs["Vector"], mapped.inputs["Vector"])
    separate, pingpong, combine = (nodes.new(kind) for kind in ("ShaderNodeSeparateXYZ", "ShaderNodeMath",
                                                                "ShaderNodeCombineXYZ"))
    pingpong.operation = "PINGPONG"
    pingpong.inputs[1].default_value = 1.0
    mirrored = nodes.new("ShaderNodeTexImage")
    links.new(uv.outputs["UV"], separate.inputs["Vector"])
    links.new(separate.outputs["X"], pingpong.inputs[0])
    links.new(pingpong.outputs["Value"], combine.inputs["X"])
    links.new(separate.outputs["Y"], combine.inputs["Y"])
    links.new(combine.outputs["Vector"], mirrored.inputs["Vector"])
    noise = nodes.new("ShaderNodeTexNoise")
    noisy = nodes.new("ShaderNodeTexImage")
    links.new(noise.outputs["Color"], noisy.inputs["Vector"])
    points = np.array([[0.0, 0.0], [0.5, 0.25], [1.5, 0.75], [2.25, -0.5]])
    chains = {name: vector_chain(node) for name, node in (("mapped", mapped), ("mirrored", mirrored),
                                                          ("noisy", noisy))}
    return {"mapped": chains["mapped"].transform(points).tolist(), "mapped_map": chains["mapped"].uv_map,
            "mapped_feed": list(chains["mapped"].feed), "mirrored": chains["mirrored"].transform(points).tolist(),
            "noisy": chains["noisy"] is None, "plain": vector_chain(nodes.new("ShaderNodeTexImage")).transform is None}


print("RESULTS " + json.dumps(RESULTS))
