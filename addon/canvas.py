# SPDX-License-Identifier: GPL-3.0-or-later
"""The painted canvas in the scene: maps, mesh, relief and material.

The canvas is a plane in the XY plane facing +z, centred on the origin, of
the chosen physical width (metres) and the painting's aspect; UV (0, 0) is
the image's lower-left corner. It is found again by the custom property
``ROLE_KEY == "canvas"``, so building again updates the same object.

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

In both, a Bump node adds paint detail finer than the geometry and a canvas
weave where the paint is thin, and roughness goes from glossy paint to matte
bare canvas with the opacity.
"""

import os

import bpy

from . import values

ROLE_KEY = "paint_relief_role"
MAP_SIZE_KEY = "paint_relief_map_size"
# Absolute folder of the painted maps the canvas was built from, and its paint thickness in metres.
PAINTING_DIR_KEY = "paint_relief_painting_dir"
THICKNESS_KEY = "paint_relief_thickness"
CANVAS_NAME = "Paint Relief Canvas"
MATERIAL_NAME = "Paint Relief Canvas"
DISPLACE_TEXTURE_NAME = "Paint Relief Height"
SUBDIVISION_MODIFIER = "Paint Relief Subdivision"
DISPLACE_MODIFIER = "Paint Relief Displace"

# Roughness of fully covering paint and of bare canvas.
PAINT_ROUGHNESS = 0.35
CANVAS_ROUGHNESS = 0.8
# Strength of the Bump node that adds detail finer than the displaced geometry.
FINE_BUMP_STRENGTH = 0.3
# Canvas weave: thread period (metres) and its height relative to the paint thickness.
WEAVE_PERIOD = 0.0008
WEAVE_HEIGHT = 0.05
# Grid of the MESH method: one vertex per this many map pixels, at most this many vertices.
PIXELS_PER_VERTEX = 2.0
MAX_MESH_VERTICES = 300_000
# Grid of the CYCLES_ADAPTIVE method before subdivision: faces along the longer side.
ADAPTIVE_BASE_FACES = 16
# Adaptive subdivision: dicing rate in pixels.
ADAPTIVE_PIXEL_SIZE = 1.0

# Scene-linear Rec.709 has had several names across Blender versions.
_LINEAR_COLORSPACES = ("Linear Rec.709", "Linear", "Linear BT.709", "scene_linear")


class CanvasError(Exception):
    """A map cannot be used; the message is one sentence naming the file."""


def find_role(scene, role):
    """Return the scene's object whose ``ROLE_KEY`` property is ``role``, or None."""
    for obj in scene.objects:
        if obj.get(ROLE_KEY) == role:
            return obj
    return None


def linear_colorspace_name():
    """The name of scene-linear Rec.709 in this Blender's colour management configuration."""
    items = bpy.types.ColorManagedInputColorspaceSettings.bl_rna.properties["name"].enum_items
    available = {item.identifier for item in items}
    for name in _LINEAR_COLORSPACES:
        if name in available:
            return name
    raise CanvasError("Blender's colour configuration has no scene-linear Rec.709 colour space.")


def load_maps(folder):
    """Load (or reload) the canvas maps of a painted ``folder``; return {file name: image}.

    Raises CanvasError naming the first missing or unreadable file; images this
    call added are removed again then, so a failure leaves the file's data as
    it was.
    """
    folder = os.path.normpath(bpy.path.abspath(folder))
    paths = {name: os.path.join(folder, name) for name in values.CANVAS_MAPS}
    for path in paths.values():
        if not os.path.isfile(path):
            raise CanvasError("Painted map {} does not exist; paint first or choose a painted folder.".format(path))
    from .. import core

    try:  # Blender only ever receives maps OpenImageIO read in full: finite, expected channels, equal sizes
        core.check_maps(folder, values.CANVAS_MAPS)
    except core.PaintReliefError as error:
        raise CanvasError(str(error)) from None
    before = set(bpy.data.images)
    images = {}
    try:
        for name, path in paths.items():
            try:
                image = bpy.data.images.load(path, check_existing=True)
            except RuntimeError as error:
                raise CanvasError("Painted map {} cannot be read: {}.".format(path, str(error).strip().rstrip("."))) from None
            if image not in before:
                image.name = "Paint Relief " + name
            else:
                image.reload()
            images[name] = image
            if image.size[0] == 0 or image.size[1] == 0 or not image.has_data and not _loads(image):
                raise CanvasError("Painted map {} cannot be read: not an image Blender can open.".format(path))
        size = tuple(images[values.COLOR_MAP].size)
        for name, image in images.items():
            if tuple(image.size) != size:
                raise CanvasError("Painted map {} is {} x {} px but {} is {} x {} px.".format(
                    paths[name], image.size[0], image.size[1], values.COLOR_MAP, size[0], size[1]))
    except CanvasError:
        for image in set(bpy.data.images) - before:
            bpy.data.images.remove(image)
        raise
    images[values.COLOR_MAP].colorspace_settings.name = linear_colorspace_name()
    for name in (values.HEIGHT_MAP, values.OPACITY_MAP):
        images[name].colorspace_settings.is_data = True
    return images


def _loads(image):
    """True when the pixels of ``image`` can be read (forces a load)."""
    try:
        return len(image.pixels) > 0
    except RuntimeError:
        return False


def map_height_range(image):
    """(min, max) of a height map's first channel (float pixels in Blender's buffer)."""
    import numpy as np

    pixels = np.empty(len(image.pixels), dtype=np.float32)
    image.pixels.foreach_get(pixels)
    channel = pixels[:: image.channels]
    return float(channel.min()), float(channel.max())


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
# material


def _link(tree, from_socket, to_socket):
    tree.links.new(from_socket, to_socket)


def _image_node(nodes, image, label, interpolation, location):
    node = nodes.new("ShaderNodeTexImage")
    node.image = image
    node.label = label
    node.interpolation = interpolation
    node.extension = "EXTEND"
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


def _principled_input(node, *names):
    """The first of ``names`` the Principled BSDF has (input names changed in Blender 4.0)."""
    for name in names:
        if name in node.inputs:
            return node.inputs[name]
    raise KeyError(names[0])


def build_material(material, images, thickness, connect_displacement):
    """Fill ``material``'s node tree with the canvas shader; return the tree.

    thickness: metres of paint of height 1. connect_displacement: link the
    Displacement node to the material output (CYCLES_ADAPTIVE) or leave it
    unconnected (MESH, where the geometry is displaced already).
    """
    if material.node_tree is None:  # Blender 4.2 creates the tree only with use_nodes
        material.use_nodes = True
    tree = material.node_tree
    nodes, links = tree.nodes, tree.links
    nodes.clear()

    uv = nodes.new("ShaderNodeTexCoord")
    uv.location = (-1300, 0)
    color = _image_node(nodes, images[values.COLOR_MAP], "Colour", "Linear", (-1000, 400))
    height = _image_node(nodes, images[values.HEIGHT_MAP], "Height", "Cubic", (-1000, -300))
    opacity = _image_node(nodes, images[values.OPACITY_MAP], "Opacity", "Linear", (-1000, 50))
    for node in (color, height, opacity):
        _link(tree, uv.outputs["UV"], node.inputs["Vector"])

    bsdf = nodes.new("ShaderNodeBsdfPrincipled")
    bsdf.location = (-100, 300)
    output = nodes.new("ShaderNodeOutputMaterial")
    output.location = (300, 200)
    _link(tree, bsdf.outputs["BSDF"], output.inputs["Surface"])
    _link(tree, color.outputs["Color"], bsdf.inputs["Base Color"])

    # Glossy where the paint covers, matte bare canvas where it does not.
    roughness = nodes.new("ShaderNodeMapRange")
    roughness.label = "Roughness from opacity"
    roughness.location = (-600, 150)
    roughness.inputs["To Min"].default_value = CANVAS_ROUGHNESS
    roughness.inputs["To Max"].default_value = PAINT_ROUGHNESS
    roughness.clamp = True
    _link(tree, opacity.outputs["Color"], roughness.inputs["Value"])
    _link(tree, roughness.outputs["Result"], bsdf.inputs["Roughness"])

    # Canvas weave: two perpendicular sine bands, multiplied, shown where paint is thin.
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

    bump = nodes.new("ShaderNodeBump")
    bump.location = (-350, -150)
    bump.inputs["Strength"].default_value = FINE_BUMP_STRENGTH
    bump.inputs["Distance"].default_value = thickness
    _link(tree, surface.outputs["Value"], bump.inputs["Height"])
    _link(tree, bump.outputs["Normal"], bsdf.inputs["Normal"])

    displacement = nodes.new("ShaderNodeDisplacement")
    displacement.location = (0, -250)
    displacement.space = "OBJECT"
    displacement.inputs["Midlevel"].default_value = 0.0
    displacement.inputs["Scale"].default_value = thickness
    _link(tree, height.outputs["Color"], displacement.inputs["Height"])
    if connect_displacement:
        _link(tree, displacement.outputs["Displacement"], output.inputs["Displacement"])
    return tree


def set_material_displacement(material, method):
    """Set the material's displacement method ('BUMP', 'DISPLACEMENT', 'BOTH') where this Blender keeps it."""
    if hasattr(material, "displacement_method"):
        material.displacement_method = method
    if hasattr(material, "cycles") and hasattr(material.cycles, "displacement_method"):
        material.cycles.displacement_method = method


# ---------------------------------------------------------------------------
# modifiers


def _remove_modifier(obj, name):
    modifier = obj.modifiers.get(name)
    if modifier is not None:
        obj.modifiers.remove(modifier)


def _set_object_adaptive(scene, obj, enabled):
    """Blender 4.2 keeps adaptive subdivision on the object's Cycles settings (experimental)."""
    cycles = getattr(obj, "cycles", None)
    if cycles is not None and hasattr(cycles, "use_adaptive_subdivision"):
        cycles.use_adaptive_subdivision = enabled
        if enabled:
            cycles.dicing_rate = ADAPTIVE_PIXEL_SIZE
            scene.cycles.feature_set = "EXPERIMENTAL"


def add_adaptive_subdivision(scene, obj):
    """A Subdivision modifier ('SIMPLE') that Cycles dices adaptively at render time."""
    modifier = obj.modifiers.new(SUBDIVISION_MODIFIER, "SUBSURF")
    modifier.subdivision_type = "SIMPLE"
    modifier.levels = 1
    modifier.render_levels = 1
    if hasattr(modifier, "use_adaptive_subdivision"):  # Blender 5.0+
        modifier.use_adaptive_subdivision = True
        modifier.adaptive_space = "PIXEL"
        modifier.adaptive_pixel_size = ADAPTIVE_PIXEL_SIZE
    else:
        _set_object_adaptive(scene, obj, True)
    return modifier


def add_displace(obj, height_image, thickness):
    """A Displace modifier moving vertices along +z by ``thickness`` x the height map (UV mapped)."""
    texture = bpy.data.textures.get(DISPLACE_TEXTURE_NAME)
    if texture is None or texture.type != "IMAGE":
        texture = bpy.data.textures.new(DISPLACE_TEXTURE_NAME, "IMAGE")
    texture.image = height_image
    texture.extension = "EXTEND"
    texture.use_interpolation = True
    # Blender 4.2 has texture filtering options; 5.0 dropped them (modifiers never filter).
    if hasattr(texture, "use_mipmap"):
        texture.use_mipmap = False
    if hasattr(texture, "filter_type"):
        texture.filter_type = "BOX"
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
    millimetres; method: 'CYCLES_ADAPTIVE' or 'MESH'. Raises CanvasError
    (before changing anything in the scene) when a map is missing or unreadable.
    """
    scene = context.scene
    images = load_maps(folder)
    map_w, map_h = images[values.COLOR_MAP].size
    width, height = values.canvas_size(map_w, map_h, width_cm)
    thickness = thickness_mm / 1000.0

    if method == "MESH":
        nx, ny = values.grid_resolution(map_w, map_h, PIXELS_PER_VERTEX, MAX_MESH_VERTICES)
    else:
        longer = max(map_w, map_h)
        nx = max(2, round(ADAPTIVE_BASE_FACES * map_w / longer) + 1)
        ny = max(2, round(ADAPTIVE_BASE_FACES * map_h / longer) + 1)
    mesh = grid_mesh(CANVAS_NAME, nx, ny, width, height)

    obj = find_role(scene, "canvas")
    if obj is None:
        obj = bpy.data.objects.new(CANVAS_NAME, mesh)
        obj[ROLE_KEY] = "canvas"
        scene.collection.objects.link(obj)
    else:
        old = obj.data
        obj.data = mesh
        if old is not None and old.users == 0:
            bpy.data.meshes.remove(old)
    obj[MAP_SIZE_KEY] = (int(map_w), int(map_h))
    obj[PAINTING_DIR_KEY] = os.path.normpath(bpy.path.abspath(folder))
    obj[THICKNESS_KEY] = thickness
    obj.location = (0.0, 0.0, 0.0)
    obj.rotation_euler = (0.0, 0.0, 0.0)
    obj.scale = (1.0, 1.0, 1.0)

    material = bpy.data.materials.get(MATERIAL_NAME) or bpy.data.materials.new(MATERIAL_NAME)
    build_material(material, images, thickness, connect_displacement=(method == "CYCLES_ADAPTIVE"))
    mesh.materials.append(material)

    for name in (SUBDIVISION_MODIFIER, DISPLACE_MODIFIER):
        _remove_modifier(obj, name)
    _set_object_adaptive(scene, obj, False)
    if method == "CYCLES_ADAPTIVE":
        set_material_displacement(material, "DISPLACEMENT")
        add_adaptive_subdivision(scene, obj)
        scene.render.engine = "CYCLES"
    else:
        set_material_displacement(material, "BUMP")
        add_displace(obj, images[values.HEIGHT_MAP], thickness)
    return obj


# ---------------------------------------------------------------------------
# relief on and off (the lighting comparison's flat renders)


def canvas_thickness(obj):
    """Metres of paint of height 1 the canvas was built with."""
    if THICKNESS_KEY in obj:
        return float(obj[THICKNESS_KEY])
    material = obj.active_material
    bump = next((n for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeBump"), None) if material else None
    if bump is None:
        raise CanvasError("Canvas {} has no paint thickness: build the canvas again.".format(obj.name))
    return float(bump.inputs["Distance"].default_value)  # the Bump's distance is never switched off


def set_relief(obj, enabled):
    """Switch the canvas's paint relief on (as built) or off (a flat canvas with the same colours).

    Off: the Displace modifier's strength, the material Displacement's scale and
    the fine Bump's strength are 0, so geometry and shading normals are those
    of a flat plane; colour, roughness and everything else stay. On: the values
    ``build_canvas`` set. Works for both displacement methods.
    """
    thickness = canvas_thickness(obj)
    modifier = obj.modifiers.get(DISPLACE_MODIFIER)
    if modifier is not None:
        modifier.strength = thickness if enabled else 0.0
    material = obj.active_material
    if material is not None and material.node_tree is not None:
        for node in material.node_tree.nodes:
            if node.bl_idname == "ShaderNodeDisplacement":
                node.inputs["Scale"].default_value = thickness if enabled else 0.0
            elif node.bl_idname == "ShaderNodeBump":
                node.inputs["Strength"].default_value = FINE_BUMP_STRENGTH if enabled else 0.0
