# SPDX-License-Identifier: GPL-3.0-or-later
"""Run Paint Object inside Blender (the bpy module) and print what it did, for tests/test_paint_object.py.

Run in its own process (``bpy`` can be imported once per process), with
``BLENDER_USER_RESOURCES`` pointing at a throw-away folder::

    BLENDER_USER_RESOURCES=/tmp/x python tests/blender/object_checks.py WORK_DIR

The repository is loaded as the package ``paint_relief`` and registered as
Blender would. A UV sphere whose material's Base Color comes from an image is
painted at 1024 texels with displacement; Suzanne, which has no UV map, is
refused in one sentence, unwrapped by Smart UV Project and painted from a bake
of its diffuse colour with the Normal Map relief. Both are painted again (from
their originals), a cube's refused run changes nothing, and the file is
saved and reopened with the original and the painting in it. Each check stores its
findings under its name (a check that raises stores its traceback). The last
line printed is ``RESULTS <json>``.
"""

import json
import os
import sys

from recorder import REPO, RESULTS, check, load_extension

WORK = os.path.abspath(sys.argv[1])
bpy = load_extension(WORK)
settings = bpy.context.scene.paint_relief
settings.object_texture_size = "1024"
settings.seed = 3


def run(op, **kwargs):
    """Call an operator; (sorted result or None, the error it reported)."""
    try:
        return sorted(op(**kwargs)), ""
    except RuntimeError as error:
        return None, str(error)


def photo_material(name, photo):
    """A material whose Principled BSDF's Base Color reads the picture ``photo``."""
    material = bpy.data.materials.new(name)
    if material.node_tree is None:
        material.use_nodes = True
    nodes = material.node_tree.nodes
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = bpy.data.images.load(photo)
    bsdf = next(node for node in nodes if node.bl_idname == "ShaderNodeBsdfPrincipled")
    material.node_tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
    return material


def textured_sphere():
    """A UV sphere of radius 0.5 m whose Principled BSDF's Base Color reads a photograph."""
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, segments=32, ring_count=16)
    sphere = bpy.context.active_object
    sphere.name = "Sphere"
    material = bpy.data.materials.new("Photo")
    if material.node_tree is None:
        material.use_nodes = True
    nodes = material.node_tree.nodes
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = bpy.data.images.load(os.path.join(REPO, "sample_scenes", "chelsea.png"))
    bsdf = next(node for node in nodes if node.bl_idname == "ShaderNodeBsdfPrincipled")
    material.node_tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
    sphere.data.materials.append(material)
    return sphere


@check
def sphere_painted():
    sphere = textured_sphere()
    settings.object_output_dir = os.path.join(WORK, "sphere")
    result, error = run(bpy.ops.paint_relief.paint_object)
    folder = settings.object_output_dir
    report = json.load(open(os.path.join(folder, "report.json")))
    return {"result": result, "error": error, "files": sorted(os.listdir(folder)),
            "input": report["input"], "width": report["width"], "islands": len(report["islands"]),
            "slots": [slot.material.name for slot in sphere.material_slots],
            "modifiers": [(m.name, m.type) for m in sphere.modifiers],
            "displace_uv": sphere.modifiers["Paint Relief Displace"].uv_layer,
            "strength": sphere.modifiers["Paint Relief Displace"].strength,
            "render_levels": sphere.modifiers["Paint Relief Subdivision"].render_levels}


@check
def original_material_back():
    sphere = bpy.data.objects["Sphere"]
    back, _ = run(bpy.ops.paint_relief.object_painting, show=False)
    original = [slot.material.name for slot in sphere.material_slots]
    hidden = [m.show_render for m in sphere.modifiers]
    again, _ = run(bpy.ops.paint_relief.object_painting, show=True)
    settings.thickness_mm = 4.0                       # the panel's thickness: a live update of painted objects
    bump = next(node for node in sphere.active_material.node_tree.nodes if node.bl_idname == "ShaderNodeBump")
    thicker = [sphere.modifiers["Paint Relief Displace"].strength, bump.inputs["Distance"].default_value]
    settings.thickness_mm = 2.0
    return {"back": back, "original": original, "relief_shown": hidden, "again": again,
            "painted": [slot.material.name for slot in sphere.material_slots],
            "relief_again": [m.show_render for m in sphere.modifiers], "thicker": thicker}


@check
def sphere_with_cycles_displacement():
    """The sphere's relief as Cycles' material displacement, then back to the Displace modifier."""
    from paint_relief.addon.objects import object_material

    scene, sphere = bpy.context.scene, bpy.data.objects["Sphere"]
    material = object_material.paint_object_look(scene, sphere, settings.object_output_dir, 0.002,
                                                 "CYCLES_ADAPTIVE", 1024)
    output = next(node for node in material.node_tree.nodes if node.bl_idname == "ShaderNodeOutputMaterial")
    method = getattr(material, "displacement_method", None) or material.cycles.displacement_method
    subdivision = sphere.modifiers["Paint Relief Subdivision"]
    adaptive = (subdivision.use_adaptive_subdivision if hasattr(subdivision, "use_adaptive_subdivision")
                else sphere.cycles.use_adaptive_subdivision)
    found = {"modifiers": [(m.name, m.type) for m in sphere.modifiers], "method": method, "adaptive": adaptive,
             "displacement_linked": [link.from_node.bl_idname for link in output.inputs["Displacement"].links]}
    object_material.paint_object_look(scene, sphere, settings.object_output_dir, 0.002, "DISPLACE", 1024)
    found["then_modifiers"] = [(m.name, m.type) for m in sphere.modifiers]
    output = next(node for node in material.node_tree.nodes if node.bl_idname == "ShaderNodeOutputMaterial")
    found["then_linked"] = [link.from_node.bl_idname for link in output.inputs["Displacement"].links]
    found["then_method"] = getattr(material, "displacement_method", None) or material.cycles.displacement_method
    return found


def evaluated(obj):
    """``obj``'s evaluated mesh as arrays: vertex positions, corner normals, each face's centre and loop start and
    size, and its triangles' vertices and corners (object space)."""
    import numpy as np

    depsgraph = bpy.context.evaluated_depsgraph_get()
    mesh = obj.evaluated_get(depsgraph).to_mesh()
    mesh.calc_loop_triangles()
    found = {"co": np.zeros(3 * len(mesh.vertices)), "normals": np.zeros(3 * len(mesh.loops)),
             "centre": np.zeros(3 * len(mesh.polygons)), "start": np.zeros(len(mesh.polygons), dtype=np.int32),
             "total": np.zeros(len(mesh.polygons), dtype=np.int32),
             "tri_vertices": np.zeros(3 * len(mesh.loop_triangles), dtype=np.int32),
             "tri_loops": np.zeros(3 * len(mesh.loop_triangles), dtype=np.int32),
             "loop_vertex": np.zeros(len(mesh.loops), dtype=np.int32)}
    mesh.vertices.foreach_get("co", found["co"])
    mesh.corner_normals.foreach_get("vector", found["normals"])
    mesh.polygons.foreach_get("center", found["centre"])
    mesh.polygons.foreach_get("loop_start", found["start"])
    mesh.polygons.foreach_get("loop_total", found["total"])
    mesh.loop_triangles.foreach_get("vertices", found["tri_vertices"])
    mesh.loop_triangles.foreach_get("loops", found["tri_loops"])
    mesh.loops.foreach_get("vertex_index", found["loop_vertex"])
    obj.evaluated_get(depsgraph).to_mesh_clear()
    for key in ("co", "normals", "centre"):
        found[key] = found[key].reshape(-1, 3)
    for key in ("tri_vertices", "tri_loops"):
        found[key] = found[key].reshape(-1, 3)
    return found


def shading_angles(reference, painted):
    """Degrees between the shading normal at each face centre of the ``painted`` mesh (the mean of its corner
    normals) and the ``reference`` mesh's normal interpolated at that point of its nearest triangle."""
    import numpy as np
    from mathutils import Vector
    from mathutils.bvhtree import BVHTree

    tree = BVHTree.FromPolygons([Vector(c) for c in reference["co"]], reference["tri_vertices"].tolist())
    faces = np.repeat(np.arange(len(painted["start"])), painted["total"])
    sums = np.zeros((len(painted["start"]), 3))
    np.add.at(sums, faces, painted["normals"])
    mine = sums / np.linalg.norm(sums, axis=1, keepdims=True)
    angles = []
    for centre, normal in zip(painted["centre"], mine, strict=True):
        location, _, index, _ = tree.find_nearest(Vector(centre))
        a, b, c = reference["co"][reference["tri_vertices"][index]]
        p = np.array(location)
        area = np.cross(b - a, c - a)
        weights = np.array([np.cross(c - b, p - b) @ area, np.cross(a - c, p - c) @ area,
                            np.cross(b - a, p - a) @ area]) / (area @ area)
        theirs = weights @ reference["normals"][reference["tri_loops"][index]]
        theirs /= np.linalg.norm(theirs)
        angles.append(np.degrees(np.arccos(np.clip(normal @ theirs, -1.0, 1.0))))
    return np.array(angles)


@check
def shape_and_shading_kept():
    """Relief 0 on a smooth-shaded Suzanne with a modifier of the user's own: the painted mesh's shading normals
    are the original's interpolated normals (no facets), the user's modifier stays first; a flat-shaded cube
    stays a cube with sharp normals; a mesh with custom normals keeps them; relief on moves the surface."""
    import numpy as np
    from paint_relief.addon.objects import object_material

    scene, folder = bpy.context.scene, settings.object_output_dir
    bpy.ops.mesh.primitive_monkey_add(size=1.0, location=(0.0, 3.0, 0.0))
    monkey = bpy.context.active_object
    monkey.name = "Smooth Suzanne"
    bpy.ops.object.shade_smooth()
    twist = monkey.modifiers.new("Twist", "SIMPLE_DEFORM")
    twist.angle = 0.3
    bpy.ops.mesh.primitive_cube_add(size=0.4, location=(0.0, -3.0, 0.0))
    cube = bpy.context.active_object
    cube.name = "Flat Cube"
    bpy.ops.object.shade_flat()
    found = {}
    for name, obj in (("monkey", monkey), ("cube", cube)):
        reference = evaluated(obj)
        object_material.paint_object_look(scene, obj, folder, 0.002, "DISPLACE", 1024)
        displace = obj.modifiers["Paint Relief Displace"]
        displace.strength = 0.0
        painted = evaluated(obj)
        angles = shading_angles(reference, painted)
        found[name] = {"modifiers": [m.name for m in obj.modifiers], "mean": float(angles.mean()),
                       "p95": float(np.percentile(angles, 95)), "faces": len(painted["start"])}
        if name == "cube":
            normals = painted["normals"]
            found[name]["axis_stray"] = float(np.degrees(np.arccos(np.abs(normals).max(axis=1).min())))
            found[name]["off_surface"] = float(np.abs(np.abs(painted["co"]).max(axis=1) - 0.2).max())
        displace.strength = 0.002
        relief = evaluated(obj)
        found[name]["moved_mm"] = float(1000 * np.linalg.norm(relief["co"] - painted["co"], axis=1).max())
    found["twist_angle"] = monkey.modifiers["Twist"].angle
    mesh = cube.data.copy()
    mesh.normals_split_custom_set_from_vertices([(0.0, 0.0, 1.0)] * len(mesh.vertices))
    custom = bpy.data.objects.new("Custom", mesh)
    scene.collection.objects.link(custom)
    object_material.paint_object_look(scene, custom, folder, 0.002, "DISPLACE", 1024)
    custom.modifiers["Paint Relief Displace"].strength = 0.0
    up = evaluated(custom)["normals"]
    found["custom"] = {"modifiers": [m.name for m in custom.modifiers], "lowest_up": float(up[:, 2].min())}
    return found


class Labels:
    """A panel layout that records the labels it is asked to show and takes everything else silently."""

    def __init__(self, shown=None):
        self.shown = [] if shown is None else shown

    def label(self, text="", **options):
        self.shown.append(text)

    def __getattr__(self, name):
        return lambda *args, **options: Labels(self.shown)


@check
def sphere_with_hertzmann_1998():
    """Paint Object with Hertzmann 1998 chosen in the Paint panel: one sentence, nothing written; the panel says so."""
    from paint_relief.addon import panels

    settings.object_output_dir = os.path.join(WORK, "hertzmann")
    shown = {}
    for method in ("HERTZMANN98", "HUANG11"):
        settings.method = method
        layout = Labels()
        panel = type("Panel", (), {"layout": layout, "_layout": lambda self: self.layout})()
        panels.VIEW3D_PT_paint_relief_object.draw(panel, bpy.context)
        shown[method] = layout.shown
    settings.method = "HERTZMANN98"
    refused, error = run(bpy.ops.paint_relief.paint_object)
    settings.method = "HUANG11"
    return {"refused": refused, "error": error, "output_exists": os.path.exists(settings.object_output_dir),
            "labels": shown}


@check
def monkey_without_uvs():
    bpy.ops.object.select_all(action="DESELECT")
    bpy.ops.mesh.primitive_monkey_add(size=1.0, location=(2.0, 0.0, 0.0))
    monkey = bpy.context.active_object
    monkey.name = "Suzanne"
    while monkey.data.uv_layers:
        monkey.data.uv_layers.remove(monkey.data.uv_layers[0])
    material = bpy.data.materials.new("Orange")
    if material.node_tree is None:
        material.use_nodes = True
    bsdf = next(node for node in material.node_tree.nodes if node.bl_idname == "ShaderNodeBsdfPrincipled")
    bsdf.inputs["Base Color"].default_value = (0.8, 0.3, 0.05, 1.0)
    monkey.data.materials.append(material)
    refused, error = run(bpy.ops.paint_relief.paint_object)
    unwrapped, _ = run(bpy.ops.paint_relief.smart_uv_project)
    return {"refused": refused, "error": error, "unwrapped": unwrapped,
            "uv_maps": [layer.name for layer in monkey.data.uv_layers]}


@check
def monkey_baked_with_a_normal_map():
    monkey = bpy.data.objects["Suzanne"]
    settings.object_output_dir = os.path.join(WORK, "monkey")
    settings.object_relief = "NORMAL_MAP"
    engine = bpy.context.scene.render.engine
    result, error = run(bpy.ops.paint_relief.paint_object)
    folder = settings.object_output_dir
    import numpy as np
    from paint_relief.core.files.reading import read_image

    source = read_image(os.path.join(folder, "source.png")).reshape(-1, 3)
    orange = np.array([0.8, 0.3, 0.05]) ** (1 / 2.2)                # the Base Color, near enough in sRGB
    covered = source[np.abs(source - orange).max(axis=1) < 0.05]
    with open(os.path.join(folder, "report.json")) as report:
        named = json.load(report)["input"]
    return {"result": result, "error": error, "files": sorted(os.listdir(folder)),
            "input_is_the_kept_source": named == os.path.realpath(os.path.join(folder, "source.png")),
            "engine_kept": bpy.context.scene.render.engine == engine,
            "bake_share_orange": len(covered) / len(source),
            "images_left": [image.name for image in bpy.data.images if image.name.startswith("Paint Relief Bake")],
            "modifiers": [m.name for m in monkey.modifiers],
            "normal_map_uv": [node.uv_map for node in monkey.material_slots[0].material.node_tree.nodes
                              if node.bl_idname == "ShaderNodeNormalMap"]}


def listing(folder):
    """{file name: its bytes} of ``folder``'s files."""
    return {name: open(os.path.join(folder, name), "rb").read() for name in sorted(os.listdir(folder))}


def colour_map(folder):
    """The painted colour of ``folder`` (color.exr) as a nested list."""
    from paint_relief.core.files.reading import read_image

    return read_image(os.path.join(folder, "color.exr")).tolist()


@check
def painted_again_from_the_original():
    """The painted sphere and Suzanne painted a second time (same seed): from the photograph and from a bake of
    the orange material, never from their paintings."""
    import numpy as np
    from paint_relief.core.files.reading import read_image

    sphere, monkey = bpy.data.objects["Sphere"], bpy.data.objects["Suzanne"]
    found = {}
    for obj, folder, relief in ((sphere, "sphere", "DISPLACE"), (monkey, "monkey", "NORMAL_MAP")):
        bpy.ops.object.select_all(action="DESELECT")
        obj.select_set(True)
        bpy.context.view_layer.objects.active = obj
        settings.object_relief = relief
        settings.object_output_dir = os.path.join(WORK, folder + "_again")
        result, error = run(bpy.ops.paint_relief.paint_object)
        with open(os.path.join(settings.object_output_dir, "report.json")) as report:
            named = json.load(report)["input"]
        found[folder] = {"result": result, "error": error, "input": named,
                         "same_colours": colour_map(os.path.join(WORK, folder)) == colour_map(
                             settings.object_output_dir),
                         "slots": [slot.material.name for slot in obj.material_slots],
                         "relief_shown": [m.show_render for m in obj.modifiers]}
    source = read_image(os.path.join(WORK, "monkey_again", "source.png")).reshape(-1, 3)
    orange = np.array([0.8, 0.3, 0.05]) ** (1 / 2.2)
    found["monkey"]["bake_share_orange"] = float(np.mean(np.abs(source - orange).max(axis=1) < 0.05))
    found["images_left"] = [image.name for image in bpy.data.images if image.name.startswith("Paint Relief Bake")]
    return found


@check
def refused_changes_nothing():
    """A cube painted from a texture file, then painted again without one: its original has no material to bake,
    so the run is refused in one sentence; its slots, relief, earlier painting and the user's own file in that
    folder are as they were, and a refused run into a new folder leaves no folder."""
    bpy.ops.object.select_all(action="DESELECT")
    bpy.ops.mesh.primitive_cube_add(size=0.4, location=(0.0, 3.0, 0.0))
    cube = bpy.context.active_object
    cube.name = "Cube"
    settings.object_relief = "DISPLACE"
    settings.object_texture_path = os.path.join(REPO, "sample_scenes", "coffee.png")
    folder = settings.object_output_dir = os.path.join(WORK, "cube")
    painted, error = run(bpy.ops.paint_relief.paint_object)
    with open(os.path.join(folder, "notes.txt"), "w") as notes:
        notes.write("the user's own file")
    before = listing(folder)
    look = ([slot.material.name for slot in cube.material_slots],
            [(m.name, m.show_viewport, m.show_render) for m in cube.modifiers])
    settings.object_texture_path = ""
    refused, refusal = run(bpy.ops.paint_relief.paint_object)
    after = listing(folder)
    settings.object_output_dir = os.path.join(WORK, "cube_new", "maps")
    refused_new, refusal_new = run(bpy.ops.paint_relief.paint_object)
    return {"painted": painted, "error": error, "refused": refused, "refusal": refusal,
            "files": sorted(before), "folder_kept": before == after,
            "look_kept": look == ([slot.material.name for slot in cube.material_slots],
                                  [(m.name, m.show_viewport, m.show_render) for m in cube.modifiers]),
            "slots": look[0], "refused_new": refused_new, "refusal_new": refusal_new,
            "new_folder_exists": os.path.exists(os.path.join(WORK, "cube_new"))}


def node_tree(material):
    """What shows of ``material``'s node tree: its nodes' types and its links (from node type to node type:
    socket), sorted."""
    tree = material.node_tree
    return {"nodes": sorted(node.bl_idname for node in tree.nodes),
            "links": sorted("{} -> {}: {}".format(link.from_node.bl_idname, link.to_node.bl_idname,
                                                  link.to_socket.name) for link in tree.links),
            "image": next((node.image.name for node in tree.nodes
                           if node.bl_idname == "ShaderNodeTexImage" and node.image is not None), None)}


def reopened(name):
    """Save the file as WORK/``name`` and open it again; returns the sphere."""
    path = os.path.join(WORK, name)
    bpy.ops.wm.save_as_mainfile(filepath=path, check_existing=False)
    bpy.ops.wm.open_mainfile(filepath=path)
    sphere = bpy.data.objects["Sphere"]
    for obj in bpy.context.view_layer.objects:
        obj.select_set(obj == sphere)
    bpy.context.view_layer.objects.active = sphere
    return sphere


@check
def saved_and_reopened():
    """The sphere's original material and its painting survive save and reopen whichever it shows (no other user
    holds the one not shown), with the extension enabled and disabled, and in a duplicate; a file that named its
    original (painted before) gets it adopted."""
    import paint_relief
    from paint_relief.addon.objects import object_material

    sphere = bpy.data.objects["Sphere"]
    tree = node_tree(bpy.data.materials["Photo"])
    users = bpy.data.materials["Photo"].users
    sphere = reopened("painted.blend")                                  # shows the painting
    found = {"tree_before": tree, "photo_users": users, "materials": sorted(m.name for m in bpy.data.materials),
             "shows_painting": object_material.shows_painting(sphere)}
    found["back"], _ = run(bpy.ops.paint_relief.object_painting, show=False)
    found["original"] = [slot.material.name for slot in sphere.material_slots]
    found["tree_after"] = node_tree(sphere.material_slots[0].material)
    found["relief_shown"] = [m.show_render for m in sphere.modifiers]
    sphere = reopened("original.blend")                                 # shows the original
    found["painted_kept"] = sphere.get(object_material.PAINTED_KEY).name
    found["again"], _ = run(bpy.ops.paint_relief.object_painting, show=True)
    found["painted"] = [slot.material.name for slot in sphere.material_slots]
    found["relief_again"] = [m.show_render for m in sphere.modifiers]
    paint_relief.unregister()                                           # the extension disabled
    sphere = reopened("disabled.blend")
    found["disabled_kept"] = [object_material.original_materials(sphere)[0].name,
                              object_material.painted_material(sphere).name]
    paint_relief.register()
    bpy.ops.object.duplicate()
    copy = bpy.context.active_object
    object_material.show_painting(copy, False)
    found["duplicate_original"] = [slot.material.name for slot in copy.material_slots]
    bpy.data.objects.remove(copy)
    photo = bpy.data.materials["Photo"]                                 # as a file painted before kept it
    photo.use_fake_user = True                                          # (by name, held by something else)
    sphere[object_material.LEGACY_ORIGINALS_KEY] = ["Photo"]
    sphere[object_material.PAINTED_KEY] = sphere[object_material.PAINTED_KEY].name
    del sphere[object_material.ORIGINALS_KEY]
    object_material.show_painting(sphere, False)
    found["legacy_original"] = [slot.material.name for slot in sphere.material_slots]
    found["legacy_adopted"] = [object_material.LEGACY_ORIGINALS_KEY in sphere,
                               object_material.original_materials(sphere)[0].name,
                               isinstance(sphere[object_material.PAINTED_KEY], bpy.types.Material)]
    object_material.show_painting(sphere, True)
    return found


def surface_points(obj, per_triangle=20):
    """(slot (P,) int, uv (P, 2)): random points (seed 0) inside every loop triangle of ``obj``'s mesh."""
    import numpy as np

    mesh = obj.data
    mesh.calc_loop_triangles()
    loops = np.empty(len(mesh.loop_triangles) * 3, np.int32)
    mesh.loop_triangles.foreach_get("loops", loops)
    slots = np.empty(len(mesh.loop_triangles), np.int32)
    mesh.loop_triangles.foreach_get("material_index", slots)
    uv = np.empty(len(mesh.loops) * 2, np.float32)
    mesh.uv_layers["UVMap"].data.foreach_get("uv", uv)
    corners = uv.reshape(-1, 2)[loops].reshape(-1, 3, 2).astype(np.float64)
    a, b = np.random.default_rng(0).random((2, len(corners), per_triangle))
    flip = a + b > 1
    a[flip], b[flip] = 1 - a[flip], 1 - b[flip]
    points = (corners[:, None, 0] * (1 - a - b)[..., None] + corners[:, None, 1] * a[..., None]
              + corners[:, None, 2] * b[..., None])
    return np.repeat(slots, per_triangle), points.reshape(-1, 2)


def source_agreement(obj, folder):
    """{source: Pearson r}: the luminance of the painted cell maps of each source against its own source picture
    (and, as "other", against the next source's) at random points of its faces, each through the original UV map
    (a tiled source's tile 1001 + floor(u) + 10 floor(v))."""
    import numpy as np
    from paint_relief.core.files.reading import read_image

    atlas = json.load(open(os.path.join(folder, "report.json")))["atlas"]
    slots, uv = surface_points(obj)
    whole = np.floor(uv)
    tile = (1001 + whole[:, 0] + 10 * whole[:, 1]).astype(int)
    inner = uv - whole

    def lookup(paths_by_cell, source, picked):
        values = np.full(len(picked), np.nan)
        for cell in atlas["cells"]:
            if cell["source"] != source:
                continue
            at = picked & ((tile == cell["tile"]) if cell["tile"] is not None else True)
            image = read_image(paths_by_cell(cell)).mean(axis=2)
            h, w = image.shape
            rows = np.clip(((1 - inner[at, 1]) * h).astype(int), 0, h - 1)
            values[at] = image[rows, np.clip((inner[at, 0] * w).astype(int), 0, w - 1)]
        return values

    found = {}
    sources = sorted({cell["source"] for cell in atlas["cells"]})
    for source in sources:
        picked = slots == source
        painted = lookup(lambda cell: os.path.join(folder, cell["files"]["color"]), source, picked)[picked]
        own = lookup(lambda cell: cell["path"], source, picked)[picked]
        found[str(source)] = float(np.corrcoef(painted, own)[0, 1])
    return found


@check
def texture_set_of_two_materials_and_udim_tiles():
    """A ball of two materials (each its own photograph) and a cube whose faces lie on two UDIM tiles, painted:
    each slot and each tile from its own source, each slot showing its source's painted material (UDIM tiles as a
    tiled image), the relief reading the atlas through a UV map of its own, the originals back with one toggle."""
    import shutil

    bpy.ops.wm.read_factory_settings(use_empty=True)
    settings = bpy.context.scene.paint_relief
    settings.object_texture_size = "1024"
    settings.seed = 3
    found = {}
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, segments=24, ring_count=12)
    ball = bpy.context.active_object
    for name, photo in (("Lower", "coffee.png"), ("Upper", "chelsea.png")):
        ball.data.materials.append(photo_material(name, os.path.join(REPO, "sample_scenes", photo)))
    for polygon in ball.data.polygons:
        polygon.material_index = int(polygon.center.z > 0.0)
    bpy.ops.mesh.primitive_cube_add(size=0.4, location=(2.0, 0.0, 0.0))
    cube = bpy.context.active_object
    for tile, photo in ((1001, "chelsea.png"), (1002, "coffee.png")):
        shutil.copyfile(os.path.join(REPO, "sample_scenes", photo), os.path.join(WORK, "tiles.{}.png".format(tile)))
    tiles = photo_material("Tiles", os.path.join(WORK, "tiles.1001.png"))
    image = next(node for node in tiles.node_tree.nodes if node.bl_idname == "ShaderNodeTexImage").image
    image.source = "TILED"
    cube.data.materials.append(tiles)
    uv = cube.data.uv_layers.active.data
    for polygon in cube.data.polygons:
        if polygon.normal.z > 0.5 or polygon.normal.x > 0.5:
            for loop in polygon.loop_indices:
                uv[loop].uv = (uv[loop].uv[0] + 1.0, uv[loop].uv[1])
    for obj, name in ((ball, "set_ball"), (cube, "set_cube")):
        for other in bpy.context.view_layer.objects:
            other.select_set(other == obj)
        bpy.context.view_layer.objects.active = obj
        settings.object_output_dir = os.path.join(WORK, name)
        result, error = run(bpy.ops.paint_relief.paint_object)
        folder = settings.object_output_dir
        displace = obj.modifiers.get("Paint Relief Displace")
        colour = [node.image for slot in obj.material_slots for node in slot.material.node_tree.nodes
                  if node.bl_idname == "ShaderNodeTexImage" and node.image and "color" in node.image.filepath]
        found[name] = {"result": result, "error": error, "files": sorted(os.listdir(folder)) if result else [],
                       "slots": [slot.material.name for slot in obj.material_slots],
                       "colour_sources": sorted({image.source for image in colour}),
                       "uv_maps": [layer.name for layer in obj.data.uv_layers],
                       "render_uv": next(layer.name for layer in obj.data.uv_layers if layer.active_render),
                       "displace_uv": displace.uv_layer if displace else None,
                       "r": source_agreement(obj, folder) if result else {}}
        found[name]["back"], _ = run(bpy.ops.paint_relief.object_painting, show=False)
        found[name]["original"] = [slot.material.name for slot in obj.material_slots]
        run(bpy.ops.paint_relief.object_painting, show=True)
    path = os.path.join(WORK, "texture_set.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path, check_existing=False)
    bpy.ops.wm.open_mainfile(filepath=path)
    found["reopened"] = {name: [slot.material.name for slot in bpy.data.objects[name].material_slots]
                         for name in ("Sphere", "Cube")}
    found["materials"] = sorted(m.name for m in bpy.data.materials)
    return found


print("RESULTS " + json.dumps(RESULTS))
