# SPDX-License-Identifier: GPL-3.0-or-later
"""The catalogue of odd meshes and scenes: each built in a fresh scene and painted with Paint Object, for
tests/test_object_catalogue.py.

Run in its own process (``bpy`` can be imported once per process), with
``BLENDER_USER_RESOURCES`` pointing at a throw-away folder::

    BLENDER_USER_RESOURCES=/tmp/x python tests/blender/object_catalogue.py WORK_DIR

Each case builds its scene from the factory settings and calls
``bpy.ops.paint_relief.paint_object`` as the panel's button does, at a small
texture (SIZE texels) unless the case is about the size. A case ends either
painted (FINISHED, the maps written, the object wearing its painted material
and relief, its original materials kept) or refused (CANCELLED: an ERROR of
one sentence). A refused case is run twice: into a folder that does not
exist, which must not exist afterwards, and into a copy of an earlier
painting holding a file of the user's own, which must keep every byte; the
object's slots and modifiers must be as they were. Each case's findings go
under its name (a case that raises stores its traceback); the last line
printed is ``RESULTS <json>``. Scenes that the sample script is run on are
saved into WORK_DIR/scenes/.
"""

import json
import os
import shutil
import sys
import tempfile
import time

from recorder import REPO, RESULTS, load_extension

WORK = os.path.abspath(sys.argv[1])
SIZE = 128
"""Texels a side of the catalogue's textures."""
MAPS = ("color.exr", "height.exr", "opacity.exr", "orientation.exr", "painting.png", "report.json", "strokes.json")
COFFEE = os.path.join(REPO, "sample_scenes", "coffee.png")
SCRATCH = os.path.join(WORK, "tmp")
os.makedirs(SCRATCH, exist_ok=True)
tempfile.tempdir = SCRATCH          # Paint Object's scratch folders: none may be left behind
bpy = load_extension(WORK)

from paint_relief.addon.objects import object_material, ops_object, relief  # noqa: E402 (after bpy)


def fresh():
    """The factory settings' empty scene and the catalogue's Paint Object settings."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    settings = bpy.context.scene.paint_relief
    settings.seed = 1
    settings.object_relief = "DISPLACE"
    settings.object_texture_path = ""
    return settings


def activate(obj):
    """Make ``obj`` the only selected and the active object."""
    for other in bpy.context.view_layer.objects:
        other.select_set(False)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    return obj


def mesh_object(name, vertices, faces, uvs=None, edges=()):
    """A mesh object of ``vertices`` and ``faces`` linked to the scene and active; ``uvs``: one (u, v) per face
    corner in face order (a UV map "UVMap"), or None for none."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices, list(edges), faces)
    if uvs is not None:
        layer = mesh.uv_layers.new(name="UVMap")
        for loop, uv in zip(layer.data, uvs, strict=True):
            loop.uv = uv
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return activate(obj)


def square(name, size=1.0, uv=((0, 0), (1, 0), (1, 1), (0, 1))):
    """One square face of ``size`` metres whose corners take ``uv``."""
    h = size / 2
    return mesh_object(name, [(-h, -h, 0), (h, -h, 0), (h, h, 0), (-h, h, 0)], [(0, 1, 2, 3)], list(uv))


def image_material(image, name="Picture"):
    """A material whose Principled BSDF's Base Color reads ``image``."""
    material = bpy.data.materials.new(name)
    nodes = material.node_tree.nodes
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image
    bsdf = next(node for node in nodes if node.bl_idname == "ShaderNodeBsdfPrincipled")
    material.node_tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
    return material


def coffee_material():
    return image_material(bpy.data.images.load(COFFEE), "Coffee")


def colour_material(colour=(0.8, 0.3, 0.05, 1.0), name="Orange"):
    material = bpy.data.materials.new(name)
    bsdf = next(node for node in material.node_tree.nodes if node.bl_idname == "ShaderNodeBsdfPrincipled")
    bsdf.inputs["Base Color"].default_value = colour
    return material


def textured(obj, material=None):
    """``obj`` with ``material`` (default: the coffee photograph) in its one slot."""
    obj.data.materials.append(coffee_material() if material is None else material)
    return obj


def cube(name="Cube", size=1.0):
    bpy.ops.mesh.primitive_cube_add(size=size)
    obj = bpy.context.active_object
    obj.name = name
    return obj


def run(**options):
    """Paint Object on the active object; (sorted result or None, the error it reported)."""
    try:
        return sorted(bpy.ops.paint_relief.paint_object(texture_size=SIZE, **options)), ""
    except RuntimeError as error:
        return None, str(error)


def files(folder):
    """{relative path: bytes} of every file under ``folder``."""
    found = {}
    for root, _, names in os.walk(folder):
        for name in names:
            path = os.path.join(root, name)
            with open(path, "rb") as handle:
                found[os.path.relpath(path, folder)] = handle.read()
    return found


def look(obj):
    """What a run must not change on a refused object: its slots' materials and its modifiers."""
    if obj is None or obj.name not in bpy.data.objects:
        return None
    return {"slots": [slot.material.name if slot.material else None for slot in obj.material_slots],
            "modifiers": [(m.name, m.type, m.show_viewport, m.show_render) for m in obj.modifiers]}


def leftovers():
    """What a run may not leave behind: Paint Object's scratch folders and bake images."""
    return sorted(os.listdir(SCRATCH)) + [image.name for image in bpy.data.images
                                          if image.name.startswith("Paint Relief Bake")]


EARLIER = os.path.join(WORK, "earlier")
"""An earlier painting with a file of the user's own beside it (made once, copied for each refused case)."""


def earlier_painting():
    fresh()
    textured(square("Earlier"))
    bpy.context.scene.paint_relief.object_output_dir = EARLIER
    result, error = run()
    assert result == ["FINISHED"], error
    with open(os.path.join(EARLIER, "notes.txt"), "w") as notes:
        notes.write("the user's own file")


def one_sentence(text):
    """The sentence an ERROR report raised by bpy.ops carries, and whether it is one line free of a traceback."""
    text = text.strip()
    sentence = text[len("Error: "):] if text.startswith("Error: ") else text
    return sentence, ("\n" not in sentence and "Traceback" not in text and sentence.endswith((".", "!"))
                      and text.startswith("Error: "))


def outcome(name, obj, output=None, earlier=True):
    """Run Paint Object on the active object (``obj``, the one expected to be painted or named) and record how it
    ended: painted (maps, material, originals) or refused (one sentence, nothing written, scene unchanged, also
    into a copy of the earlier painting)."""
    settings = bpy.context.scene.paint_relief
    before = look(obj)
    originals = before["slots"] if before else None
    folder = output or os.path.join(WORK, "cases", name, "maps")
    settings.object_output_dir = folder
    started = time.perf_counter()
    result, error = run()
    found = {"result": result, "error": error, "seconds": time.perf_counter() - started, "leftovers": leftovers()}
    if result == ["FINISHED"]:
        with open(os.path.join(folder, "report.json")) as report:
            report = json.load(report)
        found.update(
            painted=True, files=sorted(os.listdir(folder)), maps=all(m in os.listdir(folder) for m in MAPS),
            input=report["input"], width=report["width"], strokes=report.get("strokes"),
            wears_painting=object_material.shows_painting(obj),
            painted_material=getattr(object_material.painted_material(obj), "name", None),
            originals=[m.name if m else None for m in object_material.original_materials(obj) or []],
            originals_before=originals,
            relief=[m.name for m in relief.relief_modifiers(obj)],
            modifiers=[m.name for m in obj.modifiers])
        return found
    sentence, single = one_sentence(error)
    found.update(painted=False, sentence=sentence, one_sentence=single,
                 folder_absent=not os.path.exists(os.path.dirname(folder) if output is None else folder),
                 look_kept=look(obj) == before)
    if not earlier:
        return found
    copy = os.path.join(WORK, "cases", name, "earlier")
    shutil.copytree(EARLIER, copy)
    kept = files(copy)
    settings.object_output_dir = copy
    again, error_again = run()
    found.update(again=again, same_sentence=one_sentence(error_again)[0] == sentence, earlier_kept=files(copy) == kept,
                 look_kept_again=look(obj) == before, leftovers_again=leftovers())
    return found


CASES = []


def case(function):
    CASES.append(function)
    return function


def run_cases():
    for function in CASES:
        try:
            settings = fresh()
            RESULTS[function.__name__] = function(settings)
        except Exception:
            import traceback

            RESULTS[function.__name__] = {"exception": traceback.format_exc()}


# --- meshes -----------------------------------------------------------------------------------------------------


@case
def no_uv_map(settings):
    obj = textured(cube("NoUVs"))
    while obj.data.uv_layers:
        obj.data.uv_layers.remove(obj.data.uv_layers[0])
    return outcome("no_uv_map", obj)


@case
def uvs_all_at_one_point(settings):
    obj = textured(square("Collapsed", uv=[(0.5, 0.5)] * 4))
    return outcome("uvs_all_at_one_point", obj)


@case
def uvs_overlapping(settings):
    obj = textured(mesh_object("Overlapping", [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1)],
                               [(0, 1, 2, 3), (0, 1, 5, 4)], [(0, 0), (1, 0), (1, 1), (0, 1)] * 2))
    return outcome("uvs_overlapping", obj)


@case
def uvs_outside_the_unit_square(settings):
    obj = textured(square("Outside", uv=[(-0.5, -0.5), (1.5, -0.5), (1.5, 1.5), (-0.5, 1.5)]))
    found = outcome("uvs_outside_the_unit_square", obj)
    if found.get("painted"):
        from paint_relief.core.files.reading import read_image

        opacity = read_image(os.path.join(WORK, "cases", "uvs_outside_the_unit_square", "maps", "opacity.exr"))
        found["opacity_covered"] = float((opacity[..., 0] > 0).mean())
    return found


@case
def uvs_partly_outside(settings):
    obj = textured(square("PartlyOutside", uv=[(0.25, 0.25), (1.25, 0.25), (1.25, 0.75), (0.25, 0.75)]))
    return outcome("uvs_partly_outside", obj)


@case
def uvs_wholly_outside_the_unit_square(settings):
    obj = textured(square("NextTile", uv=[(1.1, 0.1), (1.9, 0.1), (1.9, 0.9), (1.1, 0.9)]))
    return outcome("uvs_wholly_outside_the_unit_square", obj)


@case
def faces_collapsed_to_a_point(settings):
    obj = textured(mesh_object("Point", [(1, 1, 1)] * 4, [(0, 1, 2, 3)], [(0, 0), (1, 0), (1, 1), (0, 1)]))
    return outcome("faces_collapsed_to_a_point", obj)


@case
def zero_area_faces(settings):
    vertices = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (2, 0, 0), (3, 0, 0), (2, 0, 0)]
    uvs = [(0, 0), (0.5, 0), (0.5, 0.5), (0, 0.5), (0.6, 0), (0.9, 0), (0.6, 0)]
    obj = textured(mesh_object("Slivers", vertices, [(0, 1, 2, 3), (4, 5, 6), (1, 4, 5)],
                               [uvs[i] for i in (0, 1, 2, 3, 4, 5, 6, 1, 4, 5)]))
    return outcome("zero_area_faces", obj)


@case
def only_zero_area_faces(settings):
    obj = textured(mesh_object("Flat", [(0, 0, 0), (1, 0, 0), (2, 0, 0)], [(0, 1, 2)], [(0, 0), (0.5, 0), (1, 0)]))
    return outcome("only_zero_area_faces", obj)


@case
def concave_ngons(settings):
    import math

    star = [(math.cos(k * math.pi / 5) * (1.0 if k % 2 == 0 else 0.4),
             math.sin(k * math.pi / 5) * (1.0 if k % 2 == 0 else 0.4), 0.0) for k in range(10)]
    ell = [(2, 0, 0), (4, 0, 0), (4, 1, 0), (3, 1, 0), (3, 3, 0), (2, 3, 0)]
    uvs = [(0.25 + 0.24 * x, 0.5 + 0.24 * y) for x, y, _ in star] + [(0.5 + (x - 2) / 8, y / 4) for x, y, _ in ell]
    obj = textured(mesh_object("Star", star + ell, [tuple(range(10)), tuple(range(10, 16))], uvs))
    return outcome("concave_ngons", obj)


@case
def loose_geometry_only(settings):
    obj = textured(mesh_object("Wires", [(0, 0, 0), (1, 0, 0), (1, 1, 0), (5, 5, 5)], [], None,
                               edges=[(0, 1), (1, 2)]))
    return outcome("loose_geometry_only", obj)


@case
def one_triangle(settings):
    obj = textured(mesh_object("Triangle", [(0, 0, 0), (1, 0, 0), (0, 1, 0)], [(0, 1, 2)], [(0, 0), (1, 0), (0, 1)]))
    return outcome("one_triangle", obj)


@case
def mesh_of_100k_faces(settings):
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=317, y_subdivisions=317, size=2.0, calc_uvs=True)
    obj = textured(bpy.context.active_object)
    obj.name = "Grid"
    found = outcome("mesh_of_100k_faces", obj)
    found["faces"] = len(obj.data.polygons)
    return found


@case
def negative_scale(settings):
    obj = textured(cube("Mirrored"))
    obj.scale = (-1.0, 1.0, 1.0)
    return outcome("negative_scale", obj)


@case
def non_uniform_scale(settings):
    obj = textured(cube("Stretched"))
    obj.scale = (3.0, 0.5, 1.0)
    return outcome("non_uniform_scale", obj)


# --- images and materials ---------------------------------------------------------------------------------------


@case
def missing_image_file(settings):
    image = bpy.data.images.load(COFFEE)
    image.name = "Lost"
    image.filepath = os.path.join(WORK, "nowhere", "lost.png")
    image.reload()
    return outcome("missing_image_file", textured(square("LostPhoto"), image_material(image)))


@case
def packed_image(settings):
    image = bpy.data.images.load(COFFEE)
    image.pack()
    image.filepath = os.path.join(WORK, "nowhere", "packed.png")     # its file gone: only the packed copy
    found = outcome("packed_image", textured(square("Packed"), image_material(image)))
    found["packed"] = image.packed_file is not None
    return found


@case
def generated_image(settings):
    image = bpy.data.images.new("Grid", 256, 256)
    image.generated_type = "COLOR_GRID"
    return outcome("generated_image", textured(square("Generated"), image_material(image)))


def picture(name, data, **options):
    """Write ``data`` (H, W, C floats in [0, 1]) to WORK/pictures/``name`` with core's writers; return the path."""
    from paint_relief.core.files import writing

    path = os.path.join(WORK, "pictures", name)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    (writing.write_exr if name.endswith(".exr") else writing.write_png)(path, data, **options)
    return path


def gradient(height, width, channels=3):
    import numpy as np

    y, x = np.mgrid[0:height, 0:width].astype(np.float32)
    rgb = np.stack([x / width, y / height, 0.5 + 0.5 * np.sin(x / 7.0) * np.cos(y / 5.0)], axis=-1)
    if channels == 4:
        rgb = np.concatenate([rgb, (x / width)[..., None]], axis=-1)
    return rgb.astype(np.float32)


@case
def png_of_16_bits(settings):
    path = picture("sixteen.png", gradient(96, 128), bits=16)
    return outcome("png_of_16_bits", textured(square("Sixteen"), image_material(bpy.data.images.load(path))))


@case
def float_exr(settings):
    path = picture("linear.exr", gradient(96, 128) ** 2.2 * 4.0)
    return outcome("float_exr", textured(square("Linear"), image_material(bpy.data.images.load(path))))


@case
def transparent_png(settings):
    path = picture("transparent.png", gradient(96, 128, channels=4))
    return outcome("transparent_png", textured(square("Transparent"), image_material(bpy.data.images.load(path))))


@case
def material_with_use_nodes_off(settings):
    import warnings

    material = colour_material(name="NoNodes")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        material.use_nodes = False
    material.diffuse_color = (0.1, 0.6, 0.2, 1.0)
    nodes = sorted(node.name for node in material.node_tree.nodes)
    found = outcome("material_with_use_nodes_off", textured(cube("Plain"), material))
    found["nodes_kept"] = sorted(node.name for node in material.node_tree.nodes) == nodes
    return found


@case
def material_with_no_nodes(settings):
    material = bpy.data.materials.new("Bare")
    material.node_tree.nodes.clear()
    found = outcome("material_with_no_nodes", textured(cube("BareCube"), material))
    found["nodes_left"] = [node.name for node in material.node_tree.nodes]
    return found


@case
def no_material(settings):
    return outcome("no_material", cube("Naked"))


@case
def no_material_painted_from_a_file(settings):
    settings.object_texture_path = COFFEE
    return outcome("no_material_painted_from_a_file", cube("NakedWithFile"))


@case
def empty_material_slot(settings):
    obj = cube("EmptySlot")
    obj.data.materials.append(None)
    return outcome("empty_material_slot", obj)


@case
def unused_empty_material_slot(settings):
    obj = textured(square("SpareSlot"))
    obj.data.materials.append(None)                 # a slot no face uses, as imported models often have
    return outcome("unused_empty_material_slot", obj)


@case
def texture_file_missing(settings):
    settings.object_texture_path = os.path.join(WORK, "nowhere", "picture.png")
    return outcome("texture_file_missing", cube("WantsAFile"))


# --- objects and scenes -----------------------------------------------------------------------------------------


def other_object(name, data):
    obj = bpy.data.objects.new(name, data)
    bpy.context.scene.collection.objects.link(obj)
    return activate(obj)


@case
def curve_object(settings):
    bpy.ops.curve.primitive_bezier_curve_add()
    obj = bpy.context.active_object
    obj.name = "Bezier"
    return outcome("curve_object", obj)


@case
def text_object(settings):
    bpy.ops.object.text_add()
    obj = bpy.context.active_object
    obj.name = "Title"
    return outcome("text_object", obj)


@case
def empty_object(settings):
    return outcome("empty_object", other_object("Pivot", None))


@case
def no_active_object(settings):
    textured(cube("Unselected"))
    bpy.context.view_layer.objects.active = None
    return outcome("no_active_object", None)


@case
def edit_mode(settings):
    obj = textured(cube("Editing"))
    bpy.ops.object.mode_set(mode="EDIT")
    found = outcome("edit_mode", obj)
    bpy.ops.object.mode_set(mode="OBJECT")
    return found


@case
def hidden_object(settings):
    obj = textured(cube("Hidden"))
    obj.hide_set(True)
    return outcome("hidden_object", obj)


@case
def hidden_object_baked(settings):
    obj = textured(cube("HiddenBaked"), colour_material())
    obj.hide_set(True)
    found = outcome("hidden_object_baked", obj)
    found["still_hidden"] = obj.hide_get()
    return found


@case
def collection_excluded_from_the_view_layer(settings):
    obj = textured(cube("Excluded"))
    collection = bpy.data.collections.new("Put Away")
    bpy.context.scene.collection.children.link(collection)
    collection.objects.link(obj)
    bpy.context.scene.collection.objects.unlink(obj)
    bpy.context.view_layer.layer_collection.children["Put Away"].exclude = True
    path = os.path.join(WORK, "scenes", "excluded.blend")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    bpy.ops.wm.save_as_mainfile(filepath=path, check_existing=False)
    return outcome("collection_excluded_from_the_view_layer", bpy.context.active_object)


@case
def mesh_shared_by_two_objects(settings):
    obj = textured(cube("First"))
    twin = bpy.data.objects.new("Twin", obj.data)
    bpy.context.scene.collection.objects.link(twin)
    twin.location = (3.0, 0.0, 0.0)
    activate(obj)
    twin_before = look(twin)
    found = outcome("mesh_shared_by_two_objects", obj)
    found["twin_kept"] = look(twin) == twin_before
    return found


# --- modifiers, shape keys, armature ----------------------------------------------------------------------------


def with_modifier(name, kind, **properties):
    obj = textured(cube(name))
    modifier = obj.modifiers.new(kind.title(), kind)
    for key, value in properties.items():
        setattr(modifier, key, value)
    from paint_relief.addon.objects import surface

    found = {"base_triangles": len(obj.data.loop_triangles) if obj.data.calc_loop_triangles() is None else 0,
             "seen_triangles": len(surface.mesh_triangles(bpy.context, obj)[0])}
    found.update(outcome(name, obj))
    found["user_modifiers_first"] = [m.name for m in obj.modifiers][:1] == [kind.title()]
    return found


@case
def subdivision_catmull_clark(settings):
    return with_modifier("subdivision_catmull_clark", "SUBSURF", levels=2, render_levels=2)


@case
def mirror_modifier(settings):
    return with_modifier("mirror_modifier", "MIRROR", use_axis=(True, False, False))


@case
def array_modifier(settings):
    return with_modifier("array_modifier", "ARRAY", count=3)


@case
def solidify_modifier(settings):
    return with_modifier("solidify_modifier", "SOLIDIFY", thickness=0.1)


@case
def users_own_displace_modifiers(settings):
    """The user's own Displace modifiers, one even named as Paint Relief's: kept, unchanged, never the relief."""
    obj = textured(cube("Bumpy"))
    mine = obj.modifiers.new("Displace", "DISPLACE")
    mine.strength = 0.05
    named = obj.modifiers.new("Paint Relief Displace", "DISPLACE")
    named.strength = 0.01
    found = outcome("users_own_displace_modifiers", obj)
    found["user_strengths"] = [obj.modifiers["Displace"].strength, obj.modifiers["Paint Relief Displace"].strength]
    found["toggled"] = bpy.ops.paint_relief.object_painting(show=False) == {"FINISHED"}
    found["user_shown"] = [obj.modifiers["Displace"].show_viewport, obj.modifiers["Paint Relief Displace"].show_viewport]
    found["relief_hidden"] = [m.show_viewport for m in relief.relief_modifiers(obj)]
    return found


def evaluated_points(obj):
    import numpy as np

    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    co = np.empty(3 * len(mesh.vertices))
    mesh.vertices.foreach_get("co", co)
    evaluated.to_mesh_clear()
    return (co.reshape(-1, 3) @ np.array(evaluated.matrix_world)[:3, :3].T) + np.array(evaluated.matrix_world)[:3, 3]


@case
def shape_keys_and_armature(settings):
    """A column with a shape key and an armature: painted as posed; the relief follows a new pose and key."""
    import numpy as np

    bpy.ops.mesh.primitive_cylinder_add(vertices=16, depth=2.0, location=(0, 0, 1))
    obj = textured(bpy.context.active_object)
    obj.name = "Column"
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.mesh.subdivide(number_cuts=4)
    bpy.ops.object.mode_set(mode="OBJECT")
    obj.shape_key_add(name="Basis")
    bulge = obj.shape_key_add(name="Bulge")
    for point in bulge.data:
        point.co.x *= 1.3
        point.co.y *= 1.3
    armature = bpy.data.objects.new("Rig", bpy.data.armatures.new("Rig"))
    bpy.context.scene.collection.objects.link(armature)
    activate(armature)
    bpy.ops.object.mode_set(mode="EDIT")
    bone = armature.data.edit_bones.new("Bone")
    bone.head, bone.tail = (0, 0, 0), (0, 0, 2)
    bpy.ops.object.mode_set(mode="OBJECT")
    obj.parent = armature
    rig = obj.modifiers.new("Armature", "ARMATURE")
    rig.object = armature
    group = obj.vertex_groups.new(name="Bone")
    group.add(list(range(len(obj.data.vertices))), 1.0, "REPLACE")
    activate(obj)
    found = outcome("shape_keys_and_armature", obj)
    if not found.get("painted"):
        return found
    displace = obj.modifiers["Paint Relief Displace"]
    moves = []
    for value, angle in ((0.0, 0.0), (1.0, 0.6)):
        bulge.value = value
        armature.pose.bones["Bone"].rotation_mode = "XYZ"
        armature.pose.bones["Bone"].rotation_euler = (angle, 0.0, 0.0)
        displace.strength = 0.0
        flat = evaluated_points(obj)
        displace.strength = 0.05
        raised = evaluated_points(obj)
        moves.append({"top_y": float(flat[:, 1].max()), "radius": float(np.hypot(flat[:, 0], flat[:, 1]).max()),
                      "relief_mm": float(1000 * np.linalg.norm(raised - flat, axis=1).max())})
    found["poses"] = moves
    return found


# --- runs and folders -------------------------------------------------------------------------------------------


@case
def painted_twice(settings):
    """A second run on a painted object paints from its original source, never from the first painting."""
    obj = textured(cube("Twice"))
    first = outcome("painted_twice", obj)
    second = outcome("painted_twice_again", obj)
    second["first"] = first
    return second


@case
def cancelled_midway(settings):
    """Esc while the worker paints, through the operator's own modal path (a window's timer events and Esc, as
    tests/blender/paint_shot_checks.py drives them): nothing written, the object as it was, one sentence."""
    from paint_relief.addon.painting import jobs
    from paint_shot_checks import ModalDriver, painter_waiting_for_esc

    obj = textured(cube("Cancelled"))
    folder = settings.object_output_dir = os.path.join(WORK, "cases", "cancelled_midway", "maps")
    before = look(obj)
    driver = ModalDriver(bpy, None, ops_object.PAINT_RELIEF_OT_paint_object)
    driver.operator.texture_size = SIZE
    with painter_waiting_for_esc("Layer"):
        driver.run(stop_when=lambda: "Layer" in getattr(getattr(driver.operator, "_worker", None), "message", ""))
    return {"painted": False, "outcome": driver.outcome, "reports": driver.reports,
            "folder_absent": not os.path.exists(os.path.dirname(folder)), "look_kept": look(obj) == before,
            "leftovers": leftovers(), "running": jobs.is_running(bpy.context.scene)}


@case
def ctrl_c_while_the_sources_are_read(settings):
    """Ctrl-C in a headless run before the painter starts (here, while the sources are read): one sentence,
    nothing written, no scratch folder left."""
    from paint_relief.addon.objects import sources

    obj = textured(cube("Interrupted"))
    texture_sources = sources.texture_sources

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt
    sources.texture_sources = interrupted
    try:
        return outcome("ctrl_c_while_the_sources_are_read", obj)
    finally:
        sources.texture_sources = texture_sources


@case
def output_path_is_a_file(settings):
    obj = textured(cube("IntoAFile"))
    path = os.path.join(WORK, "cases", "output_path_is_a_file", "taken.txt")
    os.makedirs(os.path.dirname(path))
    with open(path, "w") as handle:
        handle.write("the user's own file")
    found = outcome("output_path_is_a_file", obj, output=path, earlier=False)
    with open(path) as handle:
        found["file_kept"] = handle.read() == "the user's own file"
    return found


@case
def painted_over_an_earlier_painting(settings):
    """Painting into a folder of an earlier painting replaces its maps and keeps the user's own file."""
    copy = os.path.join(WORK, "cases", "painted_over_an_earlier_painting", "maps")
    shutil.copytree(EARLIER, copy)
    found = outcome("painted_over_an_earlier_painting", textured(cube("Over")), output=copy)
    with open(os.path.join(copy, "notes.txt")) as notes:
        found["notes_kept"] = notes.read() == "the user's own file"
    return found


@case
def texture_of_8k_on_a_tiny_mesh(settings):
    """A photograph of 8192 x 8192 on a square centimetre, at the panel's default texture size."""
    path = picture("eight_k.png", gradient(8192, 8192))
    obj = textured(square("Stamp", size=0.01), image_material(bpy.data.images.load(path)))
    global SIZE
    size, SIZE = SIZE, 0            # 0: the panel's Texture Size
    try:
        found = outcome("texture_of_8k_on_a_tiny_mesh", obj)
    finally:
        SIZE = size
    found["default_size"] = int(settings.object_texture_size)
    return found


@case
def scenes_for_the_sample_script(settings):
    """A curve and a painted textured box saved for the sample script's own cases."""
    bpy.ops.curve.primitive_bezier_curve_add()
    bpy.context.active_object.name = "Box"
    path = os.path.join(WORK, "scenes", "curve.blend")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    bpy.ops.wm.save_as_mainfile(filepath=path, check_existing=False)
    return {"saved": os.path.isfile(path)}


earlier_painting()
run_cases()
print("RESULTS " + json.dumps(RESULTS))
