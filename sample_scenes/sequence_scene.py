"""Render a short test shot with Cycles: a panning camera and a rolling, textured ball, with Blender's Vector pass.

The shot for sequences (ALGORITHM §9): a camera panning slowly to the
right over a tiled floor and a brick wall, and a checkered ball rolling
left to right faster and faster (about 20 px a frame at the start and
60 px at the end at 640 x 360), so that the footage has rigid motion,
a moving object, occlusion and disocclusion. Each frame is written as a
multilayer EXR (`frame_0001.exr`, ...): the Combined pass (scene-linear
RGBA) and the Vector pass (Blender's motion to the previous and next frames,
in pixels), with motion blur off so that Cycles writes the Vector pass.
With ``--png`` the frames are 8-bit sRGB PNG (`frame_0001.png`, ...) and
carry no Vector pass, as a camera's footage does, so that the painter finds
their motion by optical flow.

Usage (with the bpy module, or inside Blender):
  python sample_scenes/sequence_scene.py -o OUTDIR [--frames 12] [--size 640x360] [--samples 16] [--png]
  blender -b --python-exit-code 1 --python sample_scenes/sequence_scene.py -- -o OUTDIR [options]
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import bpy


def arguments(argv: list) -> argparse.Namespace:
    """The options after Blender's own (after ``--`` when Blender runs the script)."""
    parser = argparse.ArgumentParser(prog="sequence_scene.py", description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", type=Path, required=True, help="folder for frame_####.exr (or .png)")
    parser.add_argument("--frames", type=int, default=12, help="frames to render, numbered from 1 (default 12)")
    parser.add_argument("--size", default="640x360", help="width x height in px (default 640x360)")
    parser.add_argument("--samples", type=int, default=16, help="Cycles samples per pixel (default 16)")
    parser.add_argument("--png", action="store_true",
                        help="8-bit sRGB PNG frames without the Vector pass (motion left to optical flow)")
    args = parser.parse_args(argv[argv.index("--") + 1:] if "--" in argv else argv[1:])
    try:
        args.width, args.height = (int(v) for v in args.size.lower().split("x"))
    except ValueError:
        parser.error(f"--size {args.size!r} is not WIDTHxHEIGHT")
    if args.frames < 2 or args.width < 16 or args.height < 16:
        parser.error("the shot needs at least 2 frames of at least 16 x 16 px")
    return args


def material(name: str, texture: str, scale: float, first: tuple, second: tuple) -> bpy.types.Material:
    """A Principled material whose base colour is a checker or brick texture of two colours (RGBA)."""
    made = bpy.data.materials.new(name)
    tree = made.node_tree
    shader = tree.nodes["Principled BSDF"]
    pattern = tree.nodes.new("ShaderNodeTexChecker" if texture == "checker" else "ShaderNodeTexBrick")
    pattern.inputs["Scale"].default_value = scale
    pattern.inputs["Color1"].default_value = first
    pattern.inputs["Color2"].default_value = second
    tree.links.new(pattern.outputs["Color"], shader.inputs["Base Color"])
    shader.inputs["Roughness"].default_value = 0.6
    return made


def build_scene(frames: int) -> bpy.types.Scene:
    """The set: floor, wall, ball, sun, world and camera, animated over frames 1 to ``frames``."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    world = bpy.data.worlds.new("Sky")
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.55, 0.65, 0.8, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.5
    scene.world = world
    bpy.ops.mesh.primitive_plane_add(size=40.0)
    bpy.context.object.data.materials.append(
        material("Floor", "checker", 30.0, (0.55, 0.5, 0.42, 1.0), (0.25, 0.22, 0.2, 1.0)))
    bpy.ops.mesh.primitive_plane_add(size=40.0, location=(0.0, 4.0, 0.0), rotation=(math.radians(90.0), 0.0, 0.0))
    bpy.context.object.data.materials.append(
        material("Wall", "brick", 8.0, (0.6, 0.2, 0.08, 1.0), (0.38, 0.13, 0.06, 1.0)))
    radius = 0.8
    bpy.ops.mesh.primitive_uv_sphere_add(radius=radius, segments=48, ring_count=24, location=(-4.0, 0.5, radius))
    bpy.ops.object.shade_smooth()
    ball = bpy.context.object
    ball.data.materials.append(material("Ball", "checker", 4.0, (0.9, 0.85, 0.2, 1.0), (0.1, 0.25, 0.7, 1.0)))
    bpy.ops.object.light_add(type="SUN", rotation=(math.radians(45.0), math.radians(15.0), math.radians(30.0)))
    bpy.context.object.data.energy = 3.5
    bpy.ops.object.camera_add(location=(-1.0, -9.0, 2.2), rotation=(math.radians(84.0), 0.0, 0.0))
    camera = bpy.context.object
    scene.camera = camera
    scene.frame_start, scene.frame_end = 1, frames
    bpy.context.preferences.edit.keyframe_new_interpolation_type = "LINEAR"   # motion between frames as between keys
    x = -4.0
    for frame in range(1, frames + 1):
        step = 0.22 + 0.45 * (frame - 1) / max(1, frames - 1)        # world units a frame: ~20 to ~60 px
        ball.location.x = x
        ball.rotation_euler.y = x / radius                            # rolling without slipping
        camera.location.x = -1.0 + 0.06 * (frame - 1)                 # a slow pan to the right
        for thing, paths in ((ball, ("location", "rotation_euler")), (camera, ("location",))):
            for path in paths:
                thing.keyframe_insert(path, frame=frame)
        x += step
    return scene


def set_output(scene: bpy.types.Scene, width: int, height: int, samples: int, folder: Path,
               denoise: bool = True, png: bool = False) -> None:
    """Cycles on the CPU at ``samples`` per pixel, the Vector pass on and motion blur off, frames of ``width`` x
    ``height`` px written as multilayer EXR to ``folder``/frame_####.exr; with ``png``, as 8-bit sRGB
    ``folder``/frame_####.png without the Vector pass."""
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = denoise
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.use_motion_blur = False                  # Cycles writes the Vector pass only without it
    scene.view_settings.view_transform = "Standard"
    bpy.context.view_layer.use_pass_vector = not png
    settings = scene.render.image_settings
    if png:
        if hasattr(settings, "media_type"):               # Blender 5.x
            settings.media_type = "IMAGE"
        settings.file_format = "PNG"
        settings.color_mode = "RGB"
        settings.color_depth = "8"
    else:
        if hasattr(settings, "media_type"):
            settings.media_type = "MULTI_LAYER_IMAGE"
        settings.file_format = "OPEN_EXR_MULTILAYER"
        settings.exr_codec = "ZIP"
        settings.color_depth = "32"
    scene.render.filepath = str(Path(folder).resolve() / "frame_####")


def main(argv: list) -> int:
    args = arguments(argv)
    args.output.mkdir(parents=True, exist_ok=True)
    scene = build_scene(args.frames)
    set_output(scene, args.width, args.height, args.samples, args.output, png=args.png)
    bpy.ops.render.render(animation=True)
    written = sorted(args.output.glob("frame_*.png" if args.png else "frame_*.exr"))
    print(f"sequence_scene: {len(written)} frames in {args.output}")
    return 0 if len(written) >= args.frames else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
