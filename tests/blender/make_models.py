# SPDX-License-Identifier: GPL-3.0-or-later
"""Write small model files with Blender's own exporters, for tests/test_model_files.py.

    BLENDER_USER_RESOURCES=/tmp/x python tests/blender/make_models.py OUT_DIR

The scene: "Ball", a UV sphere whose Principled BSDF's Base Color reads chelsea.png; "Crate", a cube whose upper
faces wear a material reading coffee.png and whose lower ones a material reading astronaut.png; "Floor", a plane
with no material. Written as OUT_DIR/models.glb, models.gltf (+ .bin and the pictures beside it), models.obj (+
.mtl, the pictures copied beside it) and models.fbx (pictures embedded). The OBJ holds no Floor: Blender's OBJ
importer gives a mesh without a usemtl line the material read before it. Then OUT_DIR/shared.glb holds Ball and
"Left" and "Right", two objects sharing the crate's mesh, and twins.glb those two alone. Prints
``RESULTS <json>``.
"""

import json
import os
import sys
from pathlib import Path

import bpy

REPO = Path(__file__).resolve().parents[2]
OUT = Path(sys.argv[1]).resolve()


def photo_material(name, photo):
    """A material whose Principled BSDF's Base Color reads ``photo`` of sample_scenes/."""
    material = bpy.data.materials.new(name)
    if material.node_tree is None:
        material.use_nodes = True
    nodes = material.node_tree.nodes
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = bpy.data.images.load(str(REPO / "sample_scenes" / photo))
    bsdf = next(node for node in nodes if node.bl_idname == "ShaderNodeBsdfPrincipled")
    material.node_tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
    return material


def build():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, segments=16, ring_count=8, location=(-0.7, 0.0, 0.0))
    ball = bpy.context.active_object
    ball.name = ball.data.name = "Ball"
    bpy.ops.object.shade_smooth()
    ball.data.materials.append(photo_material("Cat", "chelsea.png"))
    bpy.ops.mesh.primitive_cube_add(size=0.6, location=(0.7, 0.0, 0.0))
    crate = bpy.context.active_object
    crate.name = crate.data.name = "Crate"
    crate.data.materials.append(photo_material("Coffee", "coffee.png"))
    crate.data.materials.append(photo_material("Astronaut", "astronaut.png"))
    for polygon in crate.data.polygons:
        polygon.material_index = 0 if polygon.center.z > -1e-6 else 1
    bpy.ops.mesh.primitive_plane_add(size=3.0, location=(0.0, 0.0, -0.6))
    floor = bpy.context.active_object
    floor.name = floor.data.name = "Floor"


def export():
    bpy.ops.object.select_all(action="SELECT")
    files = {}
    files["glb"] = OUT / "models.glb"
    bpy.ops.export_scene.gltf(filepath=str(files["glb"]), export_format="GLB")
    (OUT / "gltf").mkdir(exist_ok=True)
    files["gltf"] = OUT / "gltf" / "models.gltf"
    bpy.ops.export_scene.gltf(filepath=str(files["gltf"]), export_format="GLTF_SEPARATE")
    (OUT / "obj").mkdir(exist_ok=True)
    files["obj"] = OUT / "obj" / "models.obj"
    bpy.data.objects["Floor"].select_set(False)
    bpy.ops.wm.obj_export(filepath=str(files["obj"]), path_mode="COPY", export_selected_objects=True)
    files["fbx"] = OUT / "models.fbx"
    bpy.ops.export_scene.fbx(filepath=str(files["fbx"]), path_mode="COPY", embed_textures=True)
    crate = bpy.data.objects["Crate"]
    for name, x in (("Left", 0.7), ("Right", 1.5)):     # two objects sharing the crate's mesh
        twin = bpy.data.objects.new(name, crate.data)
        twin.location = (x, 1.0, 0.0)
        bpy.context.scene.collection.objects.link(twin)
    bpy.ops.object.select_all(action="DESELECT")
    for name in ("Ball", "Left", "Right"):
        bpy.data.objects[name].select_set(True)
    files["shared"] = OUT / "shared.glb"
    bpy.ops.export_scene.gltf(filepath=str(files["shared"]), export_format="GLB", use_selection=True)
    bpy.data.objects["Ball"].select_set(False)
    files["twins"] = OUT / "twins.glb"
    bpy.ops.export_scene.gltf(filepath=str(files["twins"]), export_format="GLB", use_selection=True)
    return {kind: str(path) for kind, path in files.items()}


OUT.mkdir(parents=True, exist_ok=True)
import addon_utils  # noqa: E402 (bpy first)

for module in ("io_scene_gltf2", "io_scene_fbx"):
    addon_utils.enable(module, default_set=True)
build()
found = export()
print("RESULTS " + json.dumps({"files": found, "exists": {k: os.path.isfile(v) for k, v in found.items()}}))
