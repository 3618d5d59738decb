# SPDX-License-Identifier: GPL-3.0-or-later
"""The painted canvas in the scene: the object, its mesh and modifiers, and its relief switched on and off.

The canvas is a plane in the XY plane facing +z, centred on the origin, of
the chosen physical width (metres) and the painting's aspect; UV (0, 0) is
the image's lower-left corner. Every canvas is its own object with its own
material, displacement texture and modifiers; it is marked by the custom
property ``ROLE_KEY == "canvas"`` and remembers the painted folder it shows.
Building from a folder a canvas of the scene already shows rebuilds that
canvas in place: its transform, the modifiers and material nodes the user
added, and their links, stay as they were; only Paint Relief's own parts
(mesh grid, named nodes, named modifiers) are updated. A new canvas goes into
the active collection at the 3D cursor, selected and active.

Relief, by displacement method:

``CYCLES_ADAPTIVE``
    a coarse grid, a Subdivision modifier ('SIMPLE', adaptive) and the
    material's Displacement output with displacement method 'DISPLACEMENT'.
    Blender 5.0 keeps adaptive subdivision on the modifier; Blender 4.2 keeps
    it on ``object.cycles`` and needs Cycles' experimental feature set.
``MESH``
    a grid of one vertex per 2 map pixels (capped) with a Displace modifier
    reading the height map; the material's Displacement output stays
    unconnected (the geometry carries the relief, and a connected output would
    add the same slopes again as bump) and the method is 'BUMP'.

The maps come in as Blender images through ``maps``; the material's node
tree is built in ``material``.
"""

import os

import bpy

from .. import values
from .maps import CanvasError, load_maps, reload_images
from .material import (
    FINE_BUMP_STRENGTH,
    canvas_material,
    normal_strength,
    own_images,
    own_nodes,
    set_material_displacement,
)

ROLE_KEY = "paint_relief_role"
MAP_SIZE_KEY = "paint_relief_map_size"
# Absolute folder of the painted maps the canvas was built from, and its paint thickness in metres.
PAINTING_DIR_KEY = "paint_relief_painting_dir"
THICKNESS_KEY = "paint_relief_thickness"
CANVAS_NAME = "Paint Relief Canvas"
DISPLACE_TEXTURE_NAME = "Paint Relief Height"
SUBDIVISION_MODIFIER = "Paint Relief Subdivision"
DISPLACE_MODIFIER = "Paint Relief Displace"

# Grid of the MESH method: one vertex per this many map pixels, at most this many vertices.
PIXELS_PER_VERTEX = 2.0
MAX_MESH_VERTICES = 300_000
# Grid of the CYCLES_ADAPTIVE method before subdivision: faces along the longer side.
ADAPTIVE_BASE_FACES = 16
# Adaptive subdivision: dicing rate in pixels.
ADAPTIVE_PIXEL_SIZE = 1.0


def find_role(scene, role):
    """Return the scene's object whose ``ROLE_KEY`` property is ``role``, or None.

    For "canvas", the active object when it is a canvas, else the first canvas.
    """
    if role == "canvas":
        return active_canvas(scene)
    for obj in scene.objects:
        if obj.get(ROLE_KEY) == role:
            return obj
    return None


def canvases(scene):
    """Every Paint Relief canvas of the scene, in the scene's order."""
    return [obj for obj in scene.objects if obj.get(ROLE_KEY) == "canvas"]


def active_canvas(scene, view_layer=None):
    """The canvas the canvas operators act on: the active object when it is a canvas, else the first; or None."""
    layer = view_layer or getattr(bpy.context, "view_layer", None)
    active = layer.objects.active if layer is not None and layer.objects is not None else None
    if active is not None and active.get(ROLE_KEY) == "canvas" and active.name in scene.objects:
        return active
    found = canvases(scene)
    return found[0] if found else None


def canvas_for_folder(scene, folder):
    """The scene's canvas built from painted ``folder`` (absolute, normalised), or None."""
    folder = os.path.normpath(bpy.path.abspath(folder))
    for obj in canvases(scene):
        if obj.get(PAINTING_DIR_KEY) == folder:
            return obj
    return None


def link_new_object(context, obj, select=False):
    """Link ``obj`` into the active collection; with ``select``, make it the only selected and the active object."""
    collection = context.collection or context.scene.collection
    collection.objects.link(obj)
    if select:
        for other in context.view_layer.objects:
            if other.select_get():
                other.select_set(False)
        obj.select_set(True)
        context.view_layer.objects.active = obj


# ---------------------------------------------------------------------------
# mesh


def grid_mesh(name, nx, ny, width, height):
    """A new mesh: a flat ``nx`` x ``ny`` vertex grid of ``width`` x ``height`` metres with a UV map."""
    co, loops, loop_starts, uv = values.grid_arrays(nx, ny, width, height)
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(nx * ny)
    mesh.vertices.foreach_set("co", co)
    mesh.loops.add(len(loops))
    mesh.loops.foreach_set("vertex_index", loops)
    mesh.polygons.add(len(loop_starts))
    mesh.polygons.foreach_set("loop_start", loop_starts)
    if not bpy.types.MeshPolygon.bl_rna.properties["loop_total"].is_readonly:
        mesh.polygons.foreach_set("loop_total", [4] * len(loop_starts))
    mesh.uv_layers.new(name="UVMap").data.foreach_set("uv", uv)
    mesh.update(calc_edges=True)
    mesh.validate()
    return mesh


# ---------------------------------------------------------------------------
# modifiers


def _remove_modifier(obj, name):
    modifier = obj.modifiers.get(name)
    if modifier is not None:
        obj.modifiers.remove(modifier)


def set_object_adaptive(scene, obj, enabled):
    """Blender 4.2 keeps adaptive subdivision on the object's Cycles settings (experimental)."""
    cycles = getattr(obj, "cycles", None)
    if cycles is not None and hasattr(cycles, "use_adaptive_subdivision"):
        cycles.use_adaptive_subdivision = enabled
        if enabled:
            cycles.dicing_rate = ADAPTIVE_PIXEL_SIZE
            scene.cycles.feature_set = "EXPERIMENTAL"


def add_adaptive_subdivision(scene, obj, modifier=None):
    """The canvas's Subdivision modifier ('SIMPLE') that Cycles dices adaptively at render time (updated in place;
    ``modifier``, a Subdivision Surface modifier, when given)."""
    modifier = obj.modifiers.get(SUBDIVISION_MODIFIER) if modifier is None else modifier
    if modifier is not None and modifier.type != "SUBSURF":
        obj.modifiers.remove(modifier)
        modifier = None
    if modifier is None:
        modifier = obj.modifiers.new(SUBDIVISION_MODIFIER, "SUBSURF")
    modifier.subdivision_type = "SIMPLE"
    modifier.levels = 1
    modifier.render_levels = 1
    if hasattr(modifier, "use_adaptive_subdivision"):  # Blender 5.0+
        modifier.use_adaptive_subdivision = True
        modifier.adaptive_space = "PIXEL"
        modifier.adaptive_pixel_size = ADAPTIVE_PIXEL_SIZE
    else:
        set_object_adaptive(scene, obj, True)
    return modifier


def add_displace(obj, height_image, thickness, modifier=None):
    """The canvas's Displace modifier moving vertices along +z by ``thickness`` x the height map (UV mapped).

    An existing one is updated in place (its position in the stack stays):
    ``modifier``, a Displace modifier, when given, else the one named
    DISPLACE_MODIFIER; each canvas has its own image texture.
    """
    modifier = obj.modifiers.get(DISPLACE_MODIFIER) if modifier is None else modifier
    if modifier is not None and modifier.type != "DISPLACE":
        obj.modifiers.remove(modifier)
        modifier = None
    texture = modifier.texture if modifier is not None else None
    if texture is None or texture.type != "IMAGE" or texture.users > 1:
        texture = bpy.data.textures.new(DISPLACE_TEXTURE_NAME, "IMAGE")
    texture.image = height_image
    texture.extension = "EXTEND"
    texture.use_interpolation = True
    # Blender 4.2 has texture filtering options; 5.0 dropped them (modifiers never filter).
    if hasattr(texture, "use_mipmap"):
        texture.use_mipmap = False
    if hasattr(texture, "filter_type"):
        texture.filter_type = "BOX"
    if modifier is None:
        modifier = obj.modifiers.new(DISPLACE_MODIFIER, "DISPLACE")
    modifier.texture = texture
    modifier.texture_coords = "UV"
    modifier.uv_layer = "UVMap"
    modifier.direction = "NORMAL"
    modifier.mid_level = 0.0
    modifier.strength = thickness
    return modifier


# ---------------------------------------------------------------------------
# the canvas object


def build_canvas(context, folder, width_cm, thickness_mm, method):
    """Create or update the scene's canvas from the maps in ``folder``; return the object.

    width_cm: physical canvas width; thickness_mm: paint height 1 in
    millimetres; method: 'CYCLES_ADAPTIVE', 'MESH' or 'NORMAL_MAP' (a flat
    plane shaded by normal.exr, no displacement). Raises CanvasError
    (before changing anything in the scene) when a map is missing or unreadable.
    """
    normal_map = method == "NORMAL_MAP"
    images = load_maps(folder, values.CANVAS_MAPS + ((values.NORMAL_MAP,) if normal_map else ()))
    return canvas_from_images(context, folder, images, width_cm, thickness_mm, method)


def canvas_from_images(context, folder, images, width_cm, thickness_mm, method):
    """Create or update the scene's canvas of painted ``folder`` showing ``images``; return the object.

    images: {role: image} as ``maps.load_images`` returns them (the normal
    map's among them for 'NORMAL_MAP'); the other arguments as for
    :func:`build_canvas`. The canvas of the scene built from ``folder``
    already is rebuilt in place.
    """
    scene = context.scene
    normal_map = method == "NORMAL_MAP"
    map_w, map_h = images[values.COLOR_MAP].size
    width, height = values.canvas_size(map_w, map_h, width_cm)
    thickness = thickness_mm / 1000.0

    if method == "MESH":
        nx, ny = values.grid_resolution(map_w, map_h, PIXELS_PER_VERTEX, MAX_MESH_VERTICES)
    elif normal_map:
        nx = ny = 2
    else:
        longer = max(map_w, map_h)
        nx = max(2, round(ADAPTIVE_BASE_FACES * map_w / longer) + 1)
        ny = max(2, round(ADAPTIVE_BASE_FACES * map_h / longer) + 1)
    mesh = grid_mesh(CANVAS_NAME, nx, ny, width, height)
    connect = method == "CYCLES_ADAPTIVE"

    obj = canvas_for_folder(scene, folder)
    if obj is None:
        obj = bpy.data.objects.new(CANVAS_NAME, mesh)
        obj[ROLE_KEY] = "canvas"
        obj.location = scene.cursor.location
        link_new_object(context, obj, select=True)
        material = None
    else:
        old = obj.data
        material = old.materials[0] if old is not None and len(old.materials) else None
        obj.data = mesh
        if old is not None and old.users == 0:
            bpy.data.meshes.remove(old)
    obj[MAP_SIZE_KEY] = (int(map_w), int(map_h))
    obj[PAINTING_DIR_KEY] = os.path.normpath(bpy.path.abspath(folder))
    obj[THICKNESS_KEY] = thickness

    material = canvas_material(material, images, thickness, connect, normal_map)
    mesh.materials.append(material)

    set_object_adaptive(scene, obj, False)
    if method == "CYCLES_ADAPTIVE":
        _remove_modifier(obj, DISPLACE_MODIFIER)
        set_material_displacement(material, "DISPLACEMENT")
        add_adaptive_subdivision(scene, obj)
        scene.render.engine = "CYCLES"
    elif normal_map:
        for name in (DISPLACE_MODIFIER, SUBDIVISION_MODIFIER):
            _remove_modifier(obj, name)
        set_material_displacement(material, "BUMP")
    else:
        _remove_modifier(obj, SUBDIVISION_MODIFIER)
        set_material_displacement(material, "BUMP")
        add_displace(obj, images[values.HEIGHT_MAP], thickness)
    return obj


def reload_maps(obj):
    """Read the canvas's maps from disk again (after a repaint from a script); return how many images.

    Raises CanvasError when the canvas's painted folder or a map is gone.
    """
    folder = obj.get(PAINTING_DIR_KEY)
    if not folder:
        raise CanvasError("Canvas {} does not remember its painted folder: build it again.".format(obj.name))
    return reload_images(folder, own_images(obj.active_material))


# ---------------------------------------------------------------------------
# paint thickness, and relief on and off (the lighting comparison's flat renders)


def canvas_thickness(obj):
    """Metres of paint of height 1 the canvas was built with."""
    if THICKNESS_KEY in obj:
        return float(obj[THICKNESS_KEY])
    material = obj.active_material
    tree = material.node_tree if material else None
    bump = next((n for n in own_nodes(tree).values() if n.bl_idname == "ShaderNodeBump"), None) if tree else None
    if bump is None:
        raise CanvasError("Canvas {} has no paint thickness: build the canvas again.".format(obj.name))
    return float(bump.inputs["Distance"].default_value)  # the Bump's distance is never switched off


def set_thickness(obj, thickness):
    """Give a built canvas paint ``thickness`` metres thick at once: modifier, Displacement, Bump, Normal Map.

    Only the extension's own nodes change (a user's Bump or Displacement keeps
    its values). Leaves the canvas's relief switched on, as built; nothing else changes.
    """
    obj[THICKNESS_KEY] = float(thickness)
    modifier = obj.modifiers.get(DISPLACE_MODIFIER)
    if modifier is not None:
        modifier.strength = thickness
    material = obj.active_material
    if material is None or material.node_tree is None:
        return
    for node in own_nodes(material.node_tree).values():
        if node.bl_idname == "ShaderNodeDisplacement":
            node.inputs["Scale"].default_value = thickness
        elif node.bl_idname == "ShaderNodeBump":
            node.inputs["Distance"].default_value = thickness
        elif node.bl_idname == "ShaderNodeNormalMap":
            node.inputs["Strength"].default_value = normal_strength(thickness)


def set_relief(obj, enabled):
    """Switch the canvas's paint relief on (as built) or off (a flat canvas with the same colours).

    Off: the Displace modifier's strength, the material Displacement's scale and
    the fine Bump's strength are 0, so geometry and shading normals are those
    of a flat plane; colour, roughness and everything else stay. On: the values
    ``build_canvas`` set. Works for both displacement methods. Nodes a user
    added are left as they are.
    """
    thickness = canvas_thickness(obj)
    modifier = obj.modifiers.get(DISPLACE_MODIFIER)
    if modifier is not None:
        modifier.strength = thickness if enabled else 0.0
    material = obj.active_material
    if material is not None and material.node_tree is not None:
        for node in own_nodes(material.node_tree).values():
            if node.bl_idname == "ShaderNodeDisplacement":
                node.inputs["Scale"].default_value = thickness if enabled else 0.0
            elif node.bl_idname == "ShaderNodeBump":
                node.inputs["Strength"].default_value = FINE_BUMP_STRENGTH if enabled else 0.0
            elif node.bl_idname == "ShaderNodeNormalMap":
                node.inputs["Strength"].default_value = normal_strength(thickness) if enabled else 0.0
