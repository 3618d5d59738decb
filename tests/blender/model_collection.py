# SPDX-License-Identifier: GPL-3.0-or-later
"""The collection of models made by others (tests/models/models.json), each imported with Blender's own
importer into a fresh empty scene and described, for tests/test_model_collection.py.

    python tests/blender/model_collection.py OUT [--only NAME]

For each model: the factory settings' empty scene, the file imported by its extension (.glb and .gltf with the
glTF importer, .fbx with the FBX importer, .obj with the OBJ importer; a .blend is opened), the scene saved as
OUT/<name>/original.blend, and one line printed: faces, UV range, materials, and whether a material has a
normal map, metal, emission and a colour from a node group. An image that a material's nodes use and whose
file is missing is named in ``missing_images``. What is described is the model's object to paint
(its ``object``), or every mesh with a material when that is null. The last line printed is ``RESULTS <json>``,
the findings by model name (a model whose import raised holds its traceback).
"""

import json
import os
import sys
import time
import traceback

import bpy

MODELS = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "models")


def import_model(path):
    """Open or import ``path`` into the factory settings' empty scene with Blender's importer for its kind."""
    import addon_utils

    extension = os.path.splitext(path)[1].lower()
    if extension == ".blend":
        bpy.ops.wm.open_mainfile(filepath=path, load_ui=False)
        return
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if extension in (".glb", ".gltf"):
        addon_utils.enable("io_scene_gltf2")
        result = bpy.ops.import_scene.gltf(filepath=path)
    elif extension == ".fbx":
        addon_utils.enable("io_scene_fbx")
        result = bpy.ops.import_scene.fbx(filepath=path)
    elif extension == ".obj":
        result = bpy.ops.wm.obj_import(filepath=path)
    else:
        raise ValueError("no importer for {}".format(path))
    if result != {"FINISHED"}:
        raise RuntimeError("importing {} gave {}".format(path, result))


def upstream(socket, seen=None):
    """Every node that feeds ``socket``, through any number of links (into node groups' trees as well)."""
    seen = set() if seen is None else seen
    found = []
    for link in socket.links:
        node = link.from_node
        if node.as_pointer() in seen:
            continue
        seen.add(node.as_pointer())
        found.append(node)
        if node.bl_idname == "ShaderNodeGroup" and node.node_tree:
            for inner in node.node_tree.nodes:
                found.append(inner)
        for feeding in node.inputs:
            found.extend(upstream(feeding, seen))
    return found


def image_wrap(node):
    """How the Image Texture ``node`` repeats its image: its extension, or REPEAT or MIRROR when a Math node
    before its vector wraps the coordinates (as the glTF importer writes a mirrored or mixed wrap)."""
    operations = {feeding.operation for feeding in upstream(node.inputs["Vector"])
                  if feeding.bl_idname == "ShaderNodeMath"}
    if "PINGPONG" in operations:
        return "MIRROR"
    if "WRAP" in operations or "FRACT" in operations:
        return "REPEAT"
    return node.extension


def describe_material(material):
    """What the Principled BSDFs of ``material`` take: a normal map fed by an image, metal, emission, a base
    colour from a node group, and the images (name, size, how they repeat)."""
    found = {"normal_map": False, "metal": False, "emission": False, "node_group_colour": False, "images": []}
    if material is None or material.node_tree is None:
        return found
    nodes = material.node_tree.nodes
    for node in nodes:
        if node.bl_idname == "ShaderNodeTexImage" and node.image is not None:
            found["images"].append({"name": node.image.name, "size": list(node.image.size),
                                    "wrap": image_wrap(node)})
        if node.bl_idname == "ShaderNodeNormalMap" and any(
                feeding.bl_idname == "ShaderNodeTexImage" for feeding in upstream(node.inputs["Color"])):
            found["normal_map"] = True
        if node.bl_idname != "ShaderNodeBsdfPrincipled":
            continue
        metallic = node.inputs["Metallic"]
        if metallic.is_linked:
            found["metal"] |= any(feeding.bl_idname == "ShaderNodeTexImage" for feeding in upstream(metallic))
        else:
            found["metal"] |= metallic.default_value > 0.5
        strength, colour = node.inputs["Emission Strength"], node.inputs["Emission Color"]
        lit = strength.is_linked or strength.default_value > 0
        coloured = colour.is_linked or max(colour.default_value[:3]) > 0
        found["emission"] |= lit and coloured
        base = node.inputs["Base Color"]
        found["node_group_colour"] |= any(link.from_node.bl_idname == "ShaderNodeGroup" for link in base.links)
    return found


def painted_objects(name):
    """The object to paint, or every mesh with a material when ``name`` is null."""
    if name is not None:
        return [bpy.data.objects[name]]
    return [obj for obj in bpy.data.objects if obj.type == "MESH" and any(slot.material for slot in obj.material_slots)]


def describe(model, out):
    """Import ``model`` (an entry of models.json), save the scene into ``out`` and describe it."""
    started = time.perf_counter()
    import_model(os.path.join(MODELS, model["file"]))
    objects = painted_objects(model["object"])
    faces = smooth = 0
    low, high = [float("inf")] * 2, [float("-inf")] * 2
    for obj in objects:
        mesh = obj.data
        faces += len(mesh.polygons)
        smooth += sum(polygon.use_smooth for polygon in mesh.polygons)
        layer = mesh.uv_layers.active
        if layer is None:
            continue
        for loop in layer.data:
            for axis in (0, 1):
                low[axis] = min(low[axis], loop.uv[axis])
                high[axis] = max(high[axis], loop.uv[axis])
    materials = sorted({slot.material.name for obj in objects for slot in obj.material_slots if slot.material})
    found = {"objects": [obj.name for obj in objects], "faces": faces, "smooth_faces": smooth,
             "uv_range": None if low[0] == float("inf") else [[round(v, 3) for v in low], [round(v, 3) for v in high]],
             "materials": materials, "normal_map": False, "metal": False, "emission": False,
             "node_group_colour": False, "images": []}
    for name in materials:
        described = describe_material(bpy.data.materials[name])
        for key in ("normal_map", "metal", "emission", "node_group_colour"):
            found[key] |= described[key]
        found["images"].extend(image for image in described["images"] if image not in found["images"])
    used = {image["name"] for image in found["images"]}
    found["missing_images"] = sorted(image.name for image in bpy.data.images
                                     if image.name in used and image.source == "FILE" and image.packed_file is None
                                     and not os.path.isfile(bpy.path.abspath(image.filepath, library=image.library)))
    saved = os.path.join(out, model["name"], "original.blend")
    os.makedirs(os.path.dirname(saved), exist_ok=True)
    bpy.ops.file.make_paths_absolute()      # the saved scene finds the model's images wherever it lies
    bpy.ops.wm.save_as_mainfile(filepath=saved, relative_remap=False)
    found["saved"] = saved
    found["seconds"] = round(time.perf_counter() - started, 2)
    return found


def main():
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    out = os.path.abspath(args[0])
    only = args[args.index("--only") + 1] if "--only" in args else None
    with open(os.path.join(MODELS, "models.json")) as listing:
        models = json.load(listing)
    results = {}
    for model in models:
        if only is not None and model["name"] != only:
            continue
        try:
            found = results[model["name"]] = describe(model, out)
        except Exception:
            results[model["name"]] = {"exception": traceback.format_exc()}
            print("{}: FAILED\n{}".format(model["name"], results[model["name"]]["exception"]))
            continue
        uv = found["uv_range"]
        print("{}: {} faces ({} smooth), UVs {}, materials {}; normal map {}, metal {}, emission {}, node-group "
              "colour {} ({:.1f} s)".format(
                  model["name"], found["faces"], found["smooth_faces"],
                  "none" if uv is None else "u {}..{} v {}..{}".format(uv[0][0], uv[1][0], uv[0][1], uv[1][1]),
                  ", ".join(found["materials"]), *("yes" if found[key] else "no" for key in (
                      "normal_map", "metal", "emission", "node_group_colour")), found["seconds"]))
    print("RESULTS " + json.dumps(results))


main()
