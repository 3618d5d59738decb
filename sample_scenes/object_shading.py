"""Paint smooth- and flat-shaded objects and keep each before and after, for the shading referee.

For each object (Suzanne smooth-shaded and unwrapped by Smart UV Project, once
reading a photograph and once of one colour, which is baked; a 32 x 16 UV
sphere smooth-shaded reading a photograph; a cube flat-shaded), the script
writes ``OUTDIR/<name>/original.blend``, paints the object with Paint Object
(relief: Displace) into ``OUTDIR/<name>/maps`` and writes
``OUTDIR/<name>/painted.blend``. With ``--look-only`` it paints nothing: it
opens ``original.blend`` and gives the object the look of the maps painted
before, so a change of the look is measured on the same paint. Then::

    .venv/bin/python /work/shared/tools/normal_compare.py OUTDIR/<name>/original.blend \
        OUTDIR/<name>/painted.blend <object> --views 4

compares the two renders' shading normals with the relief at 0.

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
SCENES = ("suzanne_photo", "suzanne_colour", "sphere", "cube")
OBJECT_NAMES = {"suzanne_photo": "Suzanne", "suzanne_colour": "Suzanne", "sphere": "Sphere", "cube": "Cube"}


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


def build(name):
    """An empty scene holding the object of scene ``name``; returns the object."""
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    if name.startswith("suzanne"):
        bpy.ops.mesh.primitive_monkey_add(size=1.0)
    elif name == "sphere":
        bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, segments=32, ring_count=16)
    else:
        bpy.ops.mesh.primitive_cube_add(size=0.4)
    obj = bpy.context.active_object
    obj.name = OBJECT_NAMES[name]
    if name == "cube":
        bpy.ops.object.shade_flat()
    else:
        bpy.ops.object.shade_smooth()
    if name.startswith("suzanne"):
        while obj.data.uv_layers:
            obj.data.uv_layers.remove(obj.data.uv_layers[0])
        bpy.ops.paint_relief.smart_uv_project()
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
            obj = build(name)
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
