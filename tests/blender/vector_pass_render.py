# SPDX-License-Identifier: GPL-3.0-or-later
"""Render a tiny shot of a known motion with Cycles and Blender's Vector pass, for tests/test_vector_pass_blender.py.

An orthographic camera looks straight down (-z) at a large plane with a
smooth emissive noise texture; the image's x runs along world +x and its y
(down) along world -y. The camera moves RIGHT_PX pixels to the right and
DOWN_PX pixels down the image every frame (keyed at every frame from 0 to
FRAMES + 1, so frames 1 to FRAMES have a previous and a next frame), so the
plane moves by (-RIGHT_PX, -DOWN_PX) pixels in image axes from a frame to the
next. Frames 1 to FRAMES are written as multilayer EXR (Combined and Vector
parts) to OUTDIR/frame_####.exr, with motion blur and denoising off.

Run in its own process (``bpy`` can be imported once per process), with
``BLENDER_USER_RESOURCES`` pointing at a throw-away folder::

    python tests/blender/vector_pass_render.py OUTDIR WIDTH HEIGHT FRAMES RIGHT_PX DOWN_PX
"""

import sys
from pathlib import Path

import bpy

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "sample_scenes"))
from sequence_scene import set_output  # noqa: E402  (the shot's render settings, written once)

ORTHO_SCALE = 4.8  # world units across the image's width
SAMPLES = 16


def plane_material() -> bpy.types.Material:
    """An emission shader of a smooth noise texture in object coordinates (features of a few pixels)."""
    made = bpy.data.materials.new("Noise")
    tree = made.node_tree
    tree.nodes.clear()
    coordinates = tree.nodes.new("ShaderNodeTexCoord")
    noise = tree.nodes.new("ShaderNodeTexNoise")
    noise.inputs["Scale"].default_value = 1.5
    noise.inputs["Detail"].default_value = 1.0
    emission = tree.nodes.new("ShaderNodeEmission")
    output = tree.nodes.new("ShaderNodeOutputMaterial")
    tree.links.new(coordinates.outputs["Object"], noise.inputs["Vector"])
    tree.links.new(noise.outputs["Color"], emission.inputs["Color"])
    tree.links.new(emission.outputs["Emission"], output.inputs["Surface"])
    return made


def build_scene(width: int, height: int, frames: int, right_px: float, down_px: float) -> bpy.types.Scene:
    """The plane, the camera and its motion over frames 0 to FRAMES + 1."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_plane_add(size=40.0)
    bpy.context.object.data.materials.append(plane_material())
    bpy.ops.object.camera_add(location=(0.0, 0.0, 10.0), rotation=(0.0, 0.0, 0.0))
    camera = bpy.context.object
    camera.data.type = "ORTHO"
    camera.data.ortho_scale = ORTHO_SCALE
    camera.data.sensor_fit = "HORIZONTAL"
    scene.camera = camera
    pixel = ORTHO_SCALE / width  # world units per pixel
    for frame in range(0, frames + 2):
        camera.location = (frame * right_px * pixel, -frame * down_px * pixel, 10.0)
        camera.keyframe_insert("location", frame=frame)
    scene.frame_start, scene.frame_end = 1, frames
    return scene


def main(argv: list) -> int:
    output = Path(argv[1])
    width, height, frames = (int(v) for v in argv[2:5])
    right_px, down_px = (float(v) for v in argv[5:7])
    scene = build_scene(width, height, frames, right_px, down_px)
    set_output(scene, width, height, SAMPLES, output, denoise=False)
    bpy.ops.render.render(animation=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
