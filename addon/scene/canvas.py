# SPDX-License-Identifier: GPL-3.0-or-later
"""The painted canvas in the scene: maps, mesh, relief and material.

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

In both, a Bump node adds paint detail finer than the geometry and a canvas
weave where the paint is thin, and roughness goes from glossy paint to matte
bare canvas with the opacity.
"""

import os

import bpy

from .. import values

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


def linear_colorspace_name():
    """The name of scene-linear Rec.709 in this Blender's colour management configuration."""
    items = bpy.types.ColorManagedInputColorspaceSettings.bl_rna.properties["name"].enum_items
    available = {item.identifier for item in items}
    for name in _LINEAR_COLORSPACES:
        if name in available:
            return name
    raise CanvasError("Blender's colour configuration has no scene-linear Rec.709 colour space.")


def load_maps(folder, names=values.CANVAS_MAPS):
    """Load (or reload) the canvas maps ``names`` of a painted ``folder``; return {file name: image}.

    Raises CanvasError naming the first missing or unreadable file; images this
    call added are removed again then, so a failure leaves the file's data as
    it was.
    """
    folder = os.path.normpath(bpy.path.abspath(folder))
    paths = {name: os.path.join(folder, name) for name in names}
    for name, path in paths.items():
        if not os.path.isfile(path) and name != values.NORMAL_MAP:
            raise CanvasError("Painted map {} does not exist; paint first or choose a painted folder.".format(path))
    from ... import core

    try:  # Blender only ever receives maps OpenImageIO read in full: finite, expected channels, equal sizes
        core.check_maps(folder, values.CANVAS_MAPS)
        if values.NORMAL_MAP in names:  # made from height.exr when the painter was not asked for it
            core.ensure_normal_map(folder)
            core.check_maps(folder, (values.HEIGHT_MAP, values.NORMAL_MAP))
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
    for name in (values.HEIGHT_MAP, values.OPACITY_MAP, values.NORMAL_MAP):
        if name in images:
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


# Node names of the canvas material's own nodes; a rebuild updates these and leaves every other node alone.
NODE_PREFIX = "Paint Relief "
OWN_NODE_KEY = "paint_relief_node"


def own_nodes(tree):
    """{name: node} of the Paint Relief nodes of ``tree`` (marked by OWN_NODE_KEY)."""
    return {node.name: node for node in tree.nodes if node.get(OWN_NODE_KEY)}


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


def build_material(material, images, thickness, connect_displacement, normal_map=False):
    """Fill ``material``'s node tree with the canvas shader; return the tree.

    thickness: metres of paint of height 1. connect_displacement: link the
    Displacement node to the material output (CYCLES_ADAPTIVE) or leave it
    unconnected (MESH, where the geometry is displaced already). Earlier
    Paint Relief nodes and Blender's default nodes are replaced; nodes the
    user added stay. The nodes made here carry OWN_NODE_KEY, and the ones
    :func:`update_material` needs are named NODE_PREFIX + role.
    """
    if material.node_tree is None:  # Blender 4.2 creates the tree only with use_nodes
        material.use_nodes = True
    tree = material.node_tree
    nodes = tree.nodes
    for node in list(nodes):
        if node.get(OWN_NODE_KEY) or node.bl_idname in ("ShaderNodeBsdfPrincipled", "ShaderNodeOutputMaterial") \
                and not material.get(OWN_NODE_KEY):
            nodes.remove(node)
    material[OWN_NODE_KEY] = True
    before = set(nodes)

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
    if normal_map:
        # The painter's tangent-space normals (normal.exr) shade a flat plane; the weave bump stacks on top.
        normal_image = _image_node(nodes, images[values.NORMAL_MAP], "Normal", "Linear", (-1000, -1050))
        _link(tree, uv.outputs["UV"], normal_image.inputs["Vector"])
        normal = nodes.new("ShaderNodeNormalMap")
        normal.location = (-600, -1000)
        normal.space = "TANGENT"
        normal.uv_map = "UVMap"
        normal.inputs["Strength"].default_value = normal_strength(thickness)
        normal.name = NODE_PREFIX + "Normal Map"
        _link(tree, normal_image.outputs["Color"], normal.inputs["Color"])
        _link(tree, normal.outputs["Normal"], bump.inputs["Normal"])
        bump.inputs["Strength"].default_value = 0.0 if thickness <= 0 else FINE_BUMP_STRENGTH
    _link(tree, bump.outputs["Normal"], bsdf.inputs["Normal"])

    displacement = nodes.new("ShaderNodeDisplacement")
    displacement.location = (0, -250)
    displacement.space = "OBJECT"
    displacement.inputs["Midlevel"].default_value = 0.0
    displacement.inputs["Scale"].default_value = thickness
    _link(tree, height.outputs["Color"], displacement.inputs["Height"])
    if connect_displacement:
        _link(tree, displacement.outputs["Displacement"], output.inputs["Displacement"])
    for node, name in ((color, "Colour"), (height, "Height"), (opacity, "Opacity"), (bump, "Bump"),
                       (displacement, "Displacement"), (output, "Output"), (bsdf, "BSDF")):
        node.name = NODE_PREFIX + name
    for node in set(nodes) - before:
        node[OWN_NODE_KEY] = True
    output.is_active_output = True
    return tree


def normal_strength(thickness):
    """Strength of the Normal Map node for paint ``thickness`` metres thick (1 at NORMAL_MAP_THICKNESS)."""
    return max(0.0, thickness / NORMAL_MAP_THICKNESS)


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
    """The canvas's Subdivision modifier ('SIMPLE') that Cycles dices adaptively at render time (updated in place)."""
    modifier = obj.modifiers.get(SUBDIVISION_MODIFIER)
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
        _set_object_adaptive(scene, obj, True)
    return modifier


def add_displace(obj, height_image, thickness):
    """The canvas's Displace modifier moving vertices along +z by ``thickness`` x the height map (UV mapped).

    An existing one is updated in place (its position in the stack stays);
    each canvas has its own image texture.
    """
    modifier = obj.modifiers.get(DISPLACE_MODIFIER)
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
    scene = context.scene
    normal_map = method == "NORMAL_MAP"
    images = load_maps(folder, values.CANVAS_MAPS + ((values.NORMAL_MAP,) if normal_map else ()))
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

    has_normal = material is not None and material.node_tree is not None and \
        (NODE_PREFIX + "Normal Map") in material.node_tree.nodes
    if material is None or not material.get(OWN_NODE_KEY):
        material = bpy.data.materials.new(MATERIAL_NAME)
        build_material(material, images, thickness, connect_displacement=connect, normal_map=normal_map)
    elif has_normal != normal_map or not update_material(material, images, thickness, connect_displacement=connect):
        build_material(material, images, thickness, connect_displacement=connect, normal_map=normal_map)
    elif normal_map:
        nodes = material.node_tree.nodes
        nodes[NODE_PREFIX + "Normal Map"].inputs["Strength"].default_value = normal_strength(thickness)
        for node in nodes:
            if node.bl_idname == "ShaderNodeTexImage" and node.get(OWN_NODE_KEY) and node.label == "Normal":
                node.image = images[values.NORMAL_MAP]
    mesh.materials.append(material)

    _set_object_adaptive(scene, obj, False)
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
    material = obj.active_material
    images = {node.image for node in (material.node_tree.nodes if material and material.node_tree else ())
              if node.bl_idname == "ShaderNodeTexImage" and node.get(OWN_NODE_KEY) and node.image is not None}
    if any(os.path.basename(image.filepath) == values.NORMAL_MAP for image in images):
        from ... import core

        try:  # a repainted folder's normal map is made again from its new height map
            core.ensure_normal_map(os.path.normpath(bpy.path.abspath(folder)))
        except core.PaintReliefError as error:
            raise CanvasError(str(error)) from None
    for image in images:
        path = bpy.path.abspath(image.filepath)
        if not os.path.isfile(path):
            raise CanvasError("Painted map {} does not exist; paint again or build the canvas from another "
                              "folder.".format(path))
    for image in images:
        image.reload()
    return len(images)


# ---------------------------------------------------------------------------
# relief on and off (the lighting comparison's flat renders)


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
