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


OBJECT_KINDS = {"CURVE": "a curve", "SURFACE": "a NURBS surface", "META": "a metaball", "FONT": "a text object",
                "CURVES": "a hair curves object", "POINTCLOUD": "a point cloud", "VOLUME": "a volume",
                "GREASEPENCIL": "a Grease Pencil object", "GPENCIL": "a Grease Pencil object", "EMPTY": "an empty",
                "ARMATURE": "an armature", "LATTICE": "a lattice", "CAMERA": "a camera", "LIGHT": "a light",
                "LIGHT_PROBE": "a light probe", "SPEAKER": "a speaker"}
"""What each kind of object other than a mesh is called in a sentence."""
CONVERTIBLE = ("CURVE", "SURFACE", "META", "FONT")
"""The kinds of object Blender converts to a mesh (Object > Convert > Mesh)."""
MODES = {"EDIT": "Edit Mode", "SCULPT": "Sculpt Mode", "VERTEX_PAINT": "Vertex Paint", "WEIGHT_PAINT": "Weight Paint",
         "TEXTURE_PAINT": "Texture Paint", "PARTICLE_EDIT": "Particle Edit"}


def mesh_problem(obj, context=None):
    """One sentence when ``obj`` cannot be painted as an object (none, not a mesh, not in Object Mode, not in
    ``context``'s view layer, its mesh shared with another object, no faces, no UV map), else None."""
    if obj is None:
        return "There is no active object: click the mesh object to paint, then press Paint Object."
    if obj.type != "MESH":
        kind = OBJECT_KINDS.get(obj.type, "a {} object".format(obj.type.lower().replace("_", " ")))
        if obj.type in CONVERTIBLE:
            return ("Object {} is {}: Paint Object paints meshes; convert it to a mesh (Object > Convert > Mesh) "
                    "first.".format(obj.name, kind))
        return "Object {} is {}, which has no surface to paint: Paint Object paints meshes.".format(obj.name, kind)
    if obj.mode != "OBJECT":
        return "Object {} is in {}: switch to Object Mode, then paint.".format(
            obj.name, MODES.get(obj.mode, obj.mode.replace("_", " ").title()))
    if context is not None and context.view_layer.objects.get(obj.name) is None:
        return "Object {} is not in view layer {}: include its collection, then paint.".format(
            obj.name, context.view_layer.name)
    if obj.data.users > 1:
        others = [other.name for other in bpy.data.objects if other.data == obj.data and other != obj]
        if others:
            return ("Object {} shares its mesh {} with {}: make it a single user (Object > Relation > Make Single "
                    "User > Object & Data) to paint it alone.".format(
                        obj.name, obj.data.name, "object " + others[0] if len(others) == 1 else
                        "{} other objects".format(len(others))))
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


def slot_uv_names(obj, slot_uv_maps=None):
    """One UV map name per material slot of ``obj`` (one for an object without slots): ``slot_uv_maps[k]`` where
    it names one, else ``uv_map_name`` (the map Blender renders with)."""
    default = uv_map_name(obj)
    count = max(len(obj.material_slots), 1)
    given = list(slot_uv_maps or [])
    return [given[k] if k < len(given) and given[k] else default for k in range(count)]


def triangle_uv(mesh, loops, material_index, names, obj):
    """(T, 3, 2) float64: each loop triangle's corners (``loops`` (3 T,) int) in the UV map its material slot
    (``material_index`` (T,), an index past the slots counting as the last) reads, ``names`` one per slot; ValueError
    (one sentence naming ``obj`` and the map) when ``mesh`` lacks one of them."""
    count = len(material_index)
    slot = np.clip(np.asarray(material_index, np.int64), 0, len(names) - 1)
    corners = np.zeros((count, 3, 2), np.float64)
    for name in sorted(set(names[k] for k in np.unique(slot).tolist())):
        layer = mesh.uv_layers.get(name)
        if layer is None:
            raise ValueError("Object {}'s modifiers leave its surface without its UV map {}, which the texture "
                             "is painted in.".format(obj.name, name))
        uv = np.empty(len(mesh.loops) * 2, np.float32)
        layer.data.foreach_get("uv", uv)
        picked = np.asarray(names, object)[slot] == name
        corners[picked] = uv.reshape(-1, 2)[loops].astype(np.float64).reshape(count, 3, 2)[picked]
    return corners


def mesh_triangles(context, obj, slot_uv_maps=None):
    """(uv (T, 3, 2) float64, position (T, 3, 3) float64 metres, material_index (T,) int32): the corners of the
    loop triangles of the surface the user sees (``obj``'s mesh through its modifiers, shape keys and pose, the
    relief modifiers of Paint Object left out when they are hidden), UVs of ``uv_map_name``, positions in the
    world (the object's transform and the scene's unit scale applied), and each triangle's material slot.
    slot_uv_maps: one UV map name (or None) per material slot, the map each slot's source is read through
    (``sources.SourceSet.uv_maps``): a triangle's UVs are then its slot's map's, the render map's where None.
    ValueError (one sentence) when the modifiers leave no face or drop one of those UV maps."""
    names = slot_uv_names(obj, slot_uv_maps)
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    try:
        if len(mesh.polygons) == 0:
            raise ValueError("Object {}'s modifiers leave it no faces to paint.".format(obj.name))
        mesh.calc_loop_triangles()
        count = len(mesh.loop_triangles)
        loops = np.empty(count * 3, np.int32)
        mesh.loop_triangles.foreach_get("loops", loops)
        vertices = np.empty(count * 3, np.int32)
        mesh.loop_triangles.foreach_get("vertices", vertices)
        material_index = np.empty(count, np.int32)
        mesh.loop_triangles.foreach_get("material_index", material_index)
        corners = triangle_uv(mesh, loops, material_index, names, obj)
        co = np.empty(len(mesh.vertices) * 3, np.float32)
        mesh.vertices.foreach_get("co", co)
        world = np.array(evaluated.matrix_world, np.float64)
    finally:
        evaluated.to_mesh_clear()
    points = co.reshape(-1, 3).astype(np.float64) @ world[:3, :3].T + world[:3, 3]
    points *= context.scene.unit_settings.scale_length
    position = points[vertices].reshape(count, 3, 3)
    check_layout(obj, names[0] if len(set(names)) == 1 else ", ".join(sorted(set(names))), corners, position)
    return corners, position, material_index


def check_layout(obj, name, uv, position):
    """ValueError (one sentence naming ``obj`` and its UV map ``name``) when no triangle of (T, 3, 2) ``uv`` and
    (T, 3, 3) ``position`` has an area in UV space, or none an area on the surface (all faces on a point or a
    line). UVs outside the square 0..1 are painted where Blender reads them (wrapped, or their UDIM tile)."""
    u, v = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
    uv_area = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]) / 2
    surface_area = np.linalg.norm(np.cross(position[:, 1] - position[:, 0], position[:, 2] - position[:, 0]),
                                  axis=1) / 2
    extent = np.ptp(position.reshape(-1, 3), axis=0).max()
    has_surface = surface_area > 1e-12 * extent ** 2        # relative to the object's size: float32 rounding
    has_uv = uv_area > 1e-12
    if not np.any(has_uv):
        raise ValueError("Object {}'s UV map {} has no area: its faces lie on a point or a line in UV space; unwrap "
                         "it (Smart UV Project in the Paint Object panel), then paint.".format(obj.name, name))
    if not np.any(has_surface):
        raise ValueError("Object {}'s faces have no area to paint: they lie on a point or a line.".format(obj.name))


def base_color_image(obj, materials=None):
    """The image an Image Texture node feeds into the Base Color of a Principled BSDF of the object's materials
    (the first found, slot by slot; or of ``materials`` when given), or None."""
    node = base_color_node(obj, materials)
    return None if node is None else node.image


def base_color_node(obj, materials=None):
    """The Image Texture node (holding an image) that feeds the Base Color of a Principled BSDF of the object's
    materials (the first found, slot by slot; or of ``materials`` when given), or None."""
    for material in [slot.material for slot in obj.material_slots] if materials is None else materials:
        if material is None or material.node_tree is None:
            continue
        for node in material.node_tree.nodes:
            if node.bl_idname != "ShaderNodeBsdfPrincipled":
                continue
            for link in node.inputs["Base Color"].links:
                if link.from_node.bl_idname == "ShaderNodeTexImage" and link.from_node.image is not None:
                    return link.from_node
    return None


def image_extension(node):
    """The rule of the Image Texture ``node`` beyond the UV square 0..1: its ``extension`` ("REPEAT", "EXTEND",
    "CLIP" or "MIRROR")."""
    return str(getattr(node, "extension", "REPEAT") or "REPEAT")


def image_on_disk(image):
    """The absolute path of ``image``'s file when it is on disk as the image shows it (not packed, not
    generated, not edited since), else None."""
    if image.packed_file is not None or image.source != "FILE" or image.is_dirty or not image.filepath:
        return None
    path = os.path.normpath(bpy.path.abspath(image.filepath, library=image.library))
    return path if os.path.isfile(path) else None


def missing_file(image):
    """The absolute path of ``image``'s file when Blender should read it from disk (not packed, not generated)
    and it is not there, else None."""
    if image.packed_file is not None or image.source not in ("FILE", "SEQUENCE") or not image.filepath:
        return None
    path = os.path.normpath(bpy.path.abspath(image.filepath, library=image.library))
    return None if os.path.isfile(path) or image.has_data else path


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


DIELECTRIC_INPUTS = ("Metallic", "Transmission Weight", "Transmission")


def as_dielectric(material):
    """Make every Principled BSDF of ``material`` dielectric and opaque (Metallic and Transmission 0, unlinked);
    returns the functions that put each input back as it was."""
    undo = []
    tree = material.node_tree
    for node in tree.nodes:
        if node.bl_idname != "ShaderNodeBsdfPrincipled":
            continue
        for name in DIELECTRIC_INPUTS:
            socket = node.inputs.get(name)
            if socket is None:
                continue
            value, fed = socket.default_value, [link.from_socket for link in socket.links]
            for link in list(socket.links):
                tree.links.remove(link)
            socket.default_value = 0.0

            def put_back(socket=socket, value=value, fed=fed):
                socket.default_value = value
                for from_socket in fed:
                    tree.links.new(from_socket, socket)
            undo.append(put_back)
    return undo


def check_not_black(obj, material, image):
    """ValueError (one sentence) when ``image``, ``material``'s bake on ``obj``, is black everywhere though the
    colour its surface shader is given is not (linked to something, or a colour that is not black)."""
    from .paint_layer import SHADER_COLOUR, surface_shaders

    pixels = np.empty(len(image.pixels), np.float32)
    image.pixels.foreach_get(pixels)
    if pixels.reshape(-1, 4)[:, :3].max(initial=0.0) > 1.0 / 255.0:
        return
    for shader in surface_shaders(material.node_tree):
        colour = shader.inputs[SHADER_COLOUR[shader.bl_idname]]
        if colour.links or max(colour.default_value[:3]) > 1.0 / 255.0:
            raise ValueError("The colour of material {} on object {} bakes black everywhere, though its {} is "
                             "not black: check what feeds it, or choose a texture file.".format(
                                 material.name, obj.name, colour.name))


def bake_diffuse_colours(context, obj, size, paths):
    """Bake ``obj``'s diffuse colour (Cycles, DIFFUSE with COLOR only) in its UV layout, each material of the
    dict ``paths`` into its own ``size`` x ``size`` image written to the PNG ``paths[material]`` (one bake: the
    faces of the object's other materials go to a target thrown away). A metal's or glass's colour bakes too:
    its Principled BSDFs are dielectric and opaque for the bake (Cycles' diffuse colour is the base colour
    times 1 - metallic, times 1 - transmission). ValueError (one sentence) when a material whose colour is
    not black bakes black everywhere. The scene's render engine and samples, the selection and the materials
    are as they were afterwards."""
    scene = context.scene
    engine, samples = scene.render.engine, scene.cycles.samples
    selected = [o for o in context.view_layer.objects if o.select_get()]
    active = context.view_layer.objects.active
    hidden = obj.hide_get(), obj.hide_viewport, obj.hide_render     # Cycles bakes only what it sees
    targets = {material: bpy.data.images.new(BAKE_IMAGE_NAME, size, size, alpha=False) for material in paths}
    throwaway = None
    added, nodes_off, undo_dielectric = [], [], []
    try:
        obj.hide_set(False)
        obj.hide_viewport = obj.hide_render = False
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
            if material in targets:
                undo_dielectric.extend(as_dielectric(material))
        scene.render.engine = "CYCLES"
        scene.cycles.samples = 1
        for other in selected:
            other.select_set(False)
        obj.select_set(True)
        context.view_layer.objects.active = obj
        try:
            bpy.ops.object.bake(type="DIFFUSE", pass_filter={"COLOR"}, margin=8, use_clear=True)
        except RuntimeError as error:
            why = " ".join(str(error).replace("Error:", " ").split()).rstrip(".")
            raise ValueError("Cycles could not bake the colour of object {}: {}.".format(obj.name, why)) from None
        for material, path in paths.items():
            check_not_black(obj, material, targets[material])
            write_image(targets[material], path)
    finally:
        for undo in reversed(undo_dielectric):
            undo()
        obj.hide_viewport, obj.hide_render = hidden[1:]
        obj.hide_set(hidden[0])
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
