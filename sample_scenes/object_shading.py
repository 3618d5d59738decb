"""Paint smooth- and flat-shaded objects, texture sets and continuous sources, and keep each before and after, for
the shading, sources and seams referees.

For each object (Suzanne smooth-shaded and unwrapped by Smart UV Project, once
reading a photograph and once of one colour, which is baked; a 32 x 16 UV
sphere smooth-shaded reading a photograph; a cube flat-shaded; a UV sphere
whose colour is a procedural noise, baked, continuous across its seams; a
cube whose faces lie on two UDIM tiles; a ball of two materials, each with
its own photograph), the script
writes ``OUTDIR/<name>/original.blend``, paints the object with Paint Object
(relief: Displace) into ``OUTDIR/<name>/maps`` and writes
``OUTDIR/<name>/painted.blend``. With ``--look-only`` it paints nothing: it
opens ``original.blend`` and gives the object the look of the maps painted
before, so a change of the look is measured on the same paint. Then::

    .venv/bin/python /work/shared/tools/normal_compare.py OUTDIR/<name>/original.blend \
        OUTDIR/<name>/painted.blend <object> --views 4

compares the two renders' shading normals with the relief at 0, and
``object_sources.py`` the same two files' colour, slot by slot and tile by tile.

Usage (with the bpy module)::

    .venv/bin/python sample_scenes/object_shading.py -o OUTDIR [--texture-size 1024] [--look-only] [--only NAME]
"""

from __future__ import annotations

import argparse
import importlib
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from extension import extension_package  # noqa: E402 (the launcher's folder first)

HERE = Path(__file__).resolve().parent
SCENES = ("suzanne_photo", "suzanne_colour", "sphere", "cube", "sphere_noise", "udim", "two_materials")
OBJECT_NAMES = {"suzanne_photo": "Suzanne", "suzanne_colour": "Suzanne", "sphere": "Sphere", "cube": "Cube",
                "sphere_noise": "Sphere", "udim": "Cube", "two_materials": "Ball"}


def material(name, photo=None, colour=(0.8, 0.3, 0.05, 1.0)):
    """A Principled BSDF material whose Base Color reads ``photo``, else is ``colour``."""
    import bpy

    made = bpy.data.materials.new(name)
    if made.node_tree is None:
        made.use_nodes = True
    nodes = made.node_tree.nodes
    bsdf = next(node for node in nodes if node.bl_idname == "ShaderNodeBsdfPrincipled")
    if photo is None:
        bsdf.inputs["Base Color"].default_value = colour
    else:
        texture = nodes.new("ShaderNodeTexImage")
        texture.image = bpy.data.images.load(str(photo))
        made.node_tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
    return made


def noise_material(name):
    """A material whose Base Color is a coloured procedural noise in object space (continuous on the surface)."""

    made = material(name)
    nodes, links = made.node_tree.nodes, made.node_tree.links
    bsdf = next(node for node in nodes if node.bl_idname == "ShaderNodeBsdfPrincipled")
    coordinates = nodes.new("ShaderNodeTexCoord")
    noise = nodes.new("ShaderNodeTexNoise")
    noise.inputs["Scale"].default_value = 4.0
    noise.inputs["Detail"].default_value = 4.0
    links.new(coordinates.outputs["Object"], noise.inputs["Vector"])
    links.new(noise.outputs["Color"], bsdf.inputs["Base Color"])
    return made


def udim_material(name, folder):
    """A material whose Base Color is a UDIM image of two tiles, 1001 (chelsea) and 1002 (coffee), copied into
    ``folder`` as tiles.1001.png and tiles.1002.png."""
    import shutil

    import bpy

    for tile, photo in ((1001, "chelsea.png"), (1002, "coffee.png")):
        shutil.copyfile(HERE / photo, folder / f"tiles.{tile}.png")
    made = material(name, folder / "tiles.1001.png")
    image = next(node for node in made.node_tree.nodes if node.bl_idname == "ShaderNodeTexImage").image
    image.source = "TILED"                  # Blender finds tile 1002 beside it
    if 1002 not in {tile.number for tile in image.tiles}:
        image.tiles.new(tile_number=1002)
    image.reload()
    assert bpy.path.abspath(image.filepath).endswith("tiles.<UDIM>.png"), image.filepath
    return made


def move_to_tile_1002(obj):
    """Move the UVs of the faces of ``obj`` whose normal points up or right into the next tile (u + 1)."""
    mesh = obj.data
    uv = mesh.uv_layers.active.data
    for polygon in mesh.polygons:
        if polygon.normal.z > 0.5 or polygon.normal.x > 0.5:
            for loop in polygon.loop_indices:
                uv[loop].uv = (uv[loop].uv[0] + 1.0, uv[loop].uv[1])


def two_slots(obj):
    """Give ``obj`` two materials (Lower: coffee, Upper: chelsea), the faces above its centre the second's."""
    obj.data.materials.append(material("Lower", HERE / "coffee.png"))
    obj.data.materials.append(material("Upper", HERE / "chelsea.png"))
    for polygon in obj.data.polygons:
        polygon.material_index = int(polygon.center.z > 0.0)


def build(name, folder):
    """An empty scene holding the object of scene ``name`` (its files in ``folder``); returns the object."""
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    if name.startswith("suzanne"):
        bpy.ops.mesh.primitive_monkey_add(size=1.0)
    elif name in ("sphere_noise", "two_materials"):
        bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, segments=48, ring_count=24)
    elif name == "sphere":
        bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, segments=32, ring_count=16)
    else:
        bpy.ops.mesh.primitive_cube_add(size=0.4)
    obj = bpy.context.active_object
    obj.name = OBJECT_NAMES[name]
    if name in ("cube", "udim"):
        bpy.ops.object.shade_flat()
    else:
        bpy.ops.object.shade_smooth()
    if name.startswith("suzanne"):
        while obj.data.uv_layers:
            obj.data.uv_layers.remove(obj.data.uv_layers[0])
        bpy.ops.paint_relief.smart_uv_project()
    if name == "sphere_noise":
        obj.data.materials.append(noise_material("Noise"))
    elif name == "udim":
        obj.data.materials.append(udim_material("Tiles", folder))
        move_to_tile_1002(obj)
    elif name == "two_materials":
        two_slots(obj)
    else:
        photo = None if name == "suzanne_colour" else HERE / ("coffee.png" if name == "cube" else "chelsea.png")
        obj.data.materials.append(material("Original", photo))
    return obj


def main(argv):
    parser = argparse.ArgumentParser(prog="object_shading.py", description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", type=Path, required=True, metavar="OUTDIR")
    parser.add_argument("--texture-size", type=int, default=1024, metavar="N")
    parser.add_argument("--look-only", action="store_true", help="give the maps painted before, paint nothing")
    parser.add_argument("--only", choices=SCENES, action="append", help="this scene only (repeatable)")
    args = parser.parse_args(argv[argv.index("--") + 1:] if "--" in argv else argv[1:])
    import bpy

    package = extension_package("PAINT_RELIEF_OT_paint_object")
    if not hasattr(bpy.types, "PAINT_RELIEF_OT_paint_object"):
        package.register()
    object_material = importlib.import_module(package.__name__ + ".addon.objects.object_material")
    for name in args.only or SCENES:
        folder = (args.output / name).resolve()
        folder.mkdir(parents=True, exist_ok=True)
        if args.look_only:
            bpy.ops.wm.open_mainfile(filepath=str(folder / "original.blend"))
            obj = bpy.data.objects[OBJECT_NAMES[name]]
            object_material.paint_object_look(bpy.context.scene, obj, str(folder / "maps"), 0.002, "DISPLACE",
                                              args.texture_size)
        else:
            obj = build(name, folder)
            bpy.ops.wm.save_as_mainfile(filepath=str(folder / "original.blend"), check_existing=False)
            settings = bpy.context.scene.paint_relief
            settings.object_texture_size = str(args.texture_size)
            settings.object_output_dir = str(folder / "maps")
            settings.object_relief = "DISPLACE"
            bpy.context.view_layer.objects.active = obj
            obj.select_set(True)
            if "FINISHED" not in bpy.ops.paint_relief.paint_object():
                raise SystemExit(f"Paint Object did not finish on {name}.")
        bpy.ops.wm.save_as_mainfile(filepath=str(folder / "painted.blend"), check_existing=False)
        print(f"{name}: {[(m.name, m.type) for m in obj.modifiers]}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
