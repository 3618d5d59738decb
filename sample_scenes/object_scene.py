"""Build the Paint Object demo scene: a box whose faces take their photograph at texel densities 4x apart.

The box (0.4 x 0.4 x 0.4 m, named ``Box``) has a UV map of six islands, one
a face. The front and back faces get large UV squares, the side faces
squares half as wide and the top and bottom squares a quarter as wide, so
one texel spans 4x more of the top than of the front (ALGORITHM §10: one
stroke size in the world). Its material's Base Color reads a photograph
(sample_scenes/coffee.png) through that UV map, so each face shows a
different part of it, at its own scale.

Usage (with the bpy module, or inside Blender):
  python sample_scenes/object_scene.py -o SCENE.blend
  blender -b --python-exit-code 1 --python sample_scenes/object_scene.py -- -o SCENE.blend

``box_obj`` writes the same box as a Wavefront OBJ file for ``core object``
(no Blender needed).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

PHOTO = Path(__file__).resolve().parent / "coffee.png"
OBJECT_NAME = "Box"
SIDE = 0.4
"""Metres: the box's edge."""

ISLANDS = {                      # face normal: (u0, v0, UV side)
    (0, -1, 0): (0.02, 0.02, 0.46),   # front
    (0, 1, 0): (0.52, 0.02, 0.46),    # back
    (1, 0, 0): (0.02, 0.52, 0.23),    # right
    (-1, 0, 0): (0.27, 0.52, 0.23),   # left
    (0, 0, 1): (0.52, 0.52, 0.115),   # top: a quarter of the front's side
    (0, 0, -1): (0.66, 0.52, 0.115),  # bottom
}
"""Each face's UV square: its lower left corner and its side, in UV units."""


def face_uv(key: tuple, offset) -> tuple:
    """The UV of a point of the box's face of normal ``key`` lying ``offset`` (x, y, z m) from the face's centre:
    its two in-face coordinates, from -SIDE/2 to SIDE/2, mapped onto the face's UV square (ISLANDS)."""
    u0, v0, side = ISLANDS[key]
    s, t = (offset[a] / SIDE + 0.5 for a in range(3) if key[a] == 0)
    return u0 + side * s, v0 + side * t


def box_obj(path: Path) -> Path:
    """Write the box (its faces as quads, their UVs as ``box_uvs`` gives them) as a Wavefront OBJ file."""
    lines, corners = ["# the Paint Object demo box, metres"], []
    for key in ISLANDS:
        axis = next(a for a in range(3) if key[a])
        plane = [a for a in range(3) if a != axis]
        for s, t in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            offset = [0.0, 0.0, 0.0]
            offset[plane[0]], offset[plane[1]] = s * SIDE / 2, t * SIDE / 2
            point = [SIDE / 2 * key[a] + offset[a] for a in range(3)]
            lines.append("v {:.6f} {:.6f} {:.6f}".format(point[0], point[1], point[2] + SIDE / 2))
            lines.append("vt {:.6f} {:.6f}".format(*face_uv(key, offset)))
            corners.append(len(corners) + 1)
    for face in range(len(ISLANDS)):
        lines.append("f " + " ".join(f"{k}/{k}" for k in corners[4 * face:4 * face + 4]))
    Path(path).write_text("\n".join(lines) + "\n")
    return Path(path)


def box_uvs(obj) -> None:
    """Give each face of the box ``obj`` its UV square (ISLANDS), corners in the order of the face's loops."""
    mesh = obj.data
    layer = mesh.uv_layers[0] if mesh.uv_layers else mesh.uv_layers.new(name="UVMap")
    for polygon in mesh.polygons:
        key = tuple(int(round(c)) for c in polygon.normal)
        for loop in polygon.loop_indices:
            corner = mesh.vertices[mesh.loops[loop].vertex_index].co
            layer.data[loop].uv = face_uv(key, corner - polygon.center)


def build(photo: Path = PHOTO):
    """An empty scene holding the box with its UV islands and a material whose Base Color reads ``photo``;
    returns the box."""
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_cube_add(size=SIDE, location=(0.0, 0.0, SIDE / 2))
    box = bpy.context.active_object
    box.name = OBJECT_NAME
    box_uvs(box)
    material = bpy.data.materials.new("Photograph")
    if material.node_tree is None:
        material.use_nodes = True
    tree = material.node_tree
    texture = tree.nodes.new("ShaderNodeTexImage")
    texture.image = bpy.data.images.load(str(photo))
    shader = next(node for node in tree.nodes if node.bl_idname == "ShaderNodeBsdfPrincipled")
    tree.links.new(texture.outputs["Color"], shader.inputs["Base Color"])
    shader.inputs["Roughness"].default_value = 0.6
    box.data.materials.append(material)
    return box


if __name__ == "__main__":
    parser = argparse.ArgumentParser(prog="object_scene.py", description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", type=Path, required=True, help="the .blend file to write")
    args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:])
    build()
    import bpy

    bpy.ops.wm.save_as_mainfile(filepath=str(args.output.resolve()))
