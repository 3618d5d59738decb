"""Build a small animated world to paint: five textured objects, a camera on an arc and a rolling ball, for Cycles.

The set (metres; z up; the camera looks along +y):

- ``Ground``: a 12 x 8 m plane, its base colour ``coffee.png`` over the
  whole UV square (a large, flat object of low texel density);
- ``Wall``: a standing 3.6 x 2.4 m panel behind the others, ``chelsea.png``
  over its whole UV square (a flat object seen face on);
- ``Crate``: a 0.8 m cube on the ground, ``astronaut.png`` through the cube's
  own cross-shaped UV map (six islands, hard edges, flat shading);
- ``Column``: a 0.45 m radius, 1.7 m tall cylinder, smooth shaded with
  sharp rims, through the cylinder's own UV map (the side and two caps)
  reading the same image as the crate: one picture painted once for two
  objects of different shapes at about one texel density (193 and 160
  texels a metre);
- ``Ball``: a 0.35 m radius UV sphere, smooth shaded, whose base colour is a
  Voronoi texture in object space (no image: a painter must bake it); it
  rolls without slipping 3.8 m along +x at a constant speed, in front of the
  crate and the column.

The camera (``Camera``, 40 mm on a 36 mm sensor) swings on a 24 degree arc
about a point above the ground while that point slides 1.2 m along +x and
stays at the centre of its view (keyed on every frame, linear between
keys). A sun (``Sun``) lights the set at a raking 25 degrees above the
ground from the front left, beside a weak, sky-blue world (``Sky``). At
640 x 360 the still objects move 0.3 to 7 px a frame on screen and the
rolling ball's surface up to 32 px.

Render settings: Cycles on the CPU, 640 x 360 px at 100 %, 24 fps, frames 1
to N (24 unless ``--frames``), 32 samples denoised with a fixed seed, motion
blur off, the Vector pass on, the Standard view transform, PNG frames. The
three photographs are packed into the .blend, which is self-contained. The
script uses no random numbers: the same command saves a scene that renders
the same.

Usage (with the bpy module, or inside Blender):
  python sample_scenes/world_scene.py -o SCENE.blend [--frames 24]
  blender -b --python-exit-code 1 --python sample_scenes/world_scene.py -- -o SCENE.blend [--frames 24]
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
WIDTH, HEIGHT = 640, 360
"""Pixels: the render size (at 100 %)."""
FPS = 24
"""Frames per second."""
FRAMES = 24
"""The default number of frames, numbered from 1."""

GROUND_SIZE = (12.0, 8.0)
"""Metres: the ground's width (x) and depth (y), 3:2 as coffee.png."""
WALL_SIZE = (3.6, 2.4)
"""Metres: the wall's width (x) and height (z), 3:2 as chelsea.png."""
WALL_Y = 2.4
"""Metres: the wall's distance behind the x axis."""
CRATE_SIDE = 0.8
"""Metres: the crate's edge."""
CRATE_AT = (-1.0, 0.9)
"""Metres: the crate's centre on the ground (x, y)."""
COLUMN_RADIUS, COLUMN_HEIGHT = 0.45, 1.7
"""Metres: the column's radius and height, which give its UV map about the crate's texel density (193 and 160
px/m of astronaut.png)."""
COLUMN_AT = (1.2, 1.3)
"""Metres: the column's centre on the ground (x, y)."""
BALL_RADIUS = 0.35
"""Metres: the ball's radius."""
BALL_PATH = (-2.0, 1.8, -0.2)
"""Metres: the ball's centre's x on the first and the last frame, and its y."""
TARGET = (-0.6, 0.6, 0.8, 0.8)
"""Metres: the point the camera looks at: its x on the first and the last frame, its y and its z."""
CAMERA_DISTANCE, CAMERA_HEIGHT = 6.8, 2.4
"""Metres: the camera's distance from the point it looks at in the ground plane, and its height above the
ground."""
LENS = 40.0
"""Millimetres: the camera's focal length, on a 36 mm wide sensor."""
CAMERA_ARC = (-12.0, 12.0)
"""Degrees: the camera's bearing about the target on the first and the last frame (0: straight in front, on -y;
positive: to the right, +x)."""
SUN_ELEVATION, SUN_HEADING = 25.0, 60.0
"""Degrees: the sun's height above the ground, and the heading its light travels along in the ground plane, from
+y towards +x (60: from the front left, across the set and away from the camera)."""


def arguments(argv: list) -> argparse.Namespace:
    """The options after Blender's own (after ``--`` when Blender runs the script)."""
    parser = argparse.ArgumentParser(prog="world_scene.py", description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", type=Path, required=True, help="the .blend file to write")
    parser.add_argument("--frames", type=int, default=FRAMES,
                        help=f"the animation's length in frames, numbered from 1 (default {FRAMES})")
    args = parser.parse_args(argv[argv.index("--") + 1:] if "--" in argv else argv[1:])
    if args.frames < 2:
        parser.error("the animation needs at least 2 frames")
    return args


def photograph(name: str):
    """The bundled photograph ``name`` (sample_scenes/), loaded once and packed into the .blend."""
    import bpy

    image = bpy.data.images.get(name)
    if image is None:
        image = bpy.data.images.load(str(HERE / name))
        image.name = name
        image.pack()
    return image


def image_material(name: str, image):
    """A Principled material whose Base Color reads ``image`` through the object's UV map (roughness 0.6)."""
    import bpy

    made = bpy.data.materials.new(name)
    tree = made.node_tree
    shader = tree.nodes["Principled BSDF"]
    texture = tree.nodes.new("ShaderNodeTexImage")
    texture.image = image
    texture.location = (-400.0, 300.0)
    tree.links.new(texture.outputs["Color"], shader.inputs["Base Color"])
    shader.inputs["Roughness"].default_value = 0.6
    return made


def voronoi_material(name: str):
    """A Principled material whose Base Color is a Voronoi texture's cell colours in object space (scale 6 per
    metre, so cells of about 0.17 m; no image)."""
    import bpy

    made = bpy.data.materials.new(name)
    tree = made.node_tree
    shader = tree.nodes["Principled BSDF"]
    coordinates = tree.nodes.new("ShaderNodeTexCoord")
    coordinates.location = (-700.0, 300.0)
    voronoi = tree.nodes.new("ShaderNodeTexVoronoi")
    voronoi.location = (-400.0, 300.0)
    voronoi.inputs["Scale"].default_value = 6.0
    voronoi.inputs["Randomness"].default_value = 1.0
    tree.links.new(coordinates.outputs["Object"], voronoi.inputs["Vector"])
    tree.links.new(voronoi.outputs["Color"], shader.inputs["Base Color"])
    shader.inputs["Roughness"].default_value = 0.45
    return made


def mesh_object(name: str, material, smooth: bool = False):
    """Name the active object ``name`` (and its mesh), give it ``material``; smooth shade it with edges sharper
    than 30 degrees kept hard when ``smooth``. Returns the object."""
    import bpy

    thing = bpy.context.active_object
    thing.name = thing.data.name = name
    thing.data.materials.append(material)
    if smooth:
        thing.data.shade_smooth()
        thing.data.set_sharp_from_angle(angle=math.radians(30.0))
    return thing


def look_at(camera, target) -> None:
    """Turn ``camera`` so that it looks at the point ``target`` (metres) with its up towards +z."""
    from mathutils import Vector

    direction = Vector(target) - camera.location
    camera.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()


def linear_keys(thing) -> None:
    """Make every keyframe of ``thing``'s action linear, so that its motion between keys is uniform."""
    from bpy_extras.anim_utils import animdata_get_channelbag_for_assigned_slot

    for curve in animdata_get_channelbag_for_assigned_slot(thing.animation_data).fcurves:
        for point in curve.keyframe_points:
            point.interpolation = "LINEAR"


def build_scene(frames: int = FRAMES):
    """The set (module docstring) in an empty scene, animated over frames 1 to ``frames``; returns the scene."""
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.name = "World"

    world = bpy.data.worlds.new("Sky")
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (0.55, 0.68, 0.9, 1.0)
    background.inputs["Strength"].default_value = 0.25
    scene.world = world

    astronaut = photograph("astronaut.png")
    bpy.ops.mesh.primitive_plane_add(size=1.0)
    ground = mesh_object("Ground", image_material("Ground", photograph("coffee.png")))
    ground.scale = (GROUND_SIZE[0], GROUND_SIZE[1], 1.0)

    bpy.ops.mesh.primitive_plane_add(size=1.0, location=(0.0, WALL_Y, WALL_SIZE[1] / 2),
                                     rotation=(math.radians(90.0), 0.0, 0.0))
    wall = mesh_object("Wall", image_material("Wall", photograph("chelsea.png")))
    wall.scale = (WALL_SIZE[0], WALL_SIZE[1], 1.0)

    bpy.ops.mesh.primitive_cube_add(size=CRATE_SIDE, location=(*CRATE_AT, CRATE_SIDE / 2),
                                    rotation=(0.0, 0.0, math.radians(20.0)))
    mesh_object("Crate", image_material("Crate", astronaut))

    bpy.ops.mesh.primitive_cylinder_add(vertices=48, radius=COLUMN_RADIUS, depth=COLUMN_HEIGHT,
                                        location=(*COLUMN_AT, COLUMN_HEIGHT / 2))
    mesh_object("Column", image_material("Column", astronaut), smooth=True)

    bpy.ops.mesh.primitive_uv_sphere_add(segments=48, ring_count=24, radius=BALL_RADIUS,
                                         location=(BALL_PATH[0], BALL_PATH[2], BALL_RADIUS))
    ball = mesh_object("Ball", voronoi_material("Ball"), smooth=True)

    bpy.ops.object.light_add(type="SUN")
    sun = bpy.context.active_object
    sun.name = sun.data.name = "Sun"
    sun.rotation_euler = (math.radians(90.0 - SUN_ELEVATION), 0.0, -math.radians(SUN_HEADING))
    sun.data.energy = 4.0
    sun.data.angle = math.radians(1.0)

    bpy.ops.object.camera_add()
    camera = bpy.context.active_object
    camera.name = camera.data.name = "Camera"
    camera.data.lens, camera.data.sensor_width = LENS, 36.0
    scene.camera = camera

    scene.frame_start, scene.frame_end, scene.frame_current = 1, frames, 1
    for frame in range(1, frames + 1):
        along = (frame - 1) / (frames - 1)
        bearing = math.radians(CAMERA_ARC[0] + (CAMERA_ARC[1] - CAMERA_ARC[0]) * along)
        target = (TARGET[0] + (TARGET[1] - TARGET[0]) * along, TARGET[2], TARGET[3])
        camera.location = (target[0] + CAMERA_DISTANCE * math.sin(bearing),
                           target[1] - CAMERA_DISTANCE * math.cos(bearing), CAMERA_HEIGHT)
        look_at(camera, target)
        camera.keyframe_insert("location", frame=frame)
        camera.keyframe_insert("rotation_euler", frame=frame)
    for frame, x in ((1, BALL_PATH[0]), (frames, BALL_PATH[1])):
        ball.location.x = x
        ball.rotation_euler.y = x / BALL_RADIUS          # rolling without slipping along +x
        ball.keyframe_insert("location", frame=frame)
        ball.keyframe_insert("rotation_euler", frame=frame)
    linear_keys(camera)
    linear_keys(ball)
    scene.frame_set(1)
    render_settings(scene)
    return scene


def render_settings(scene) -> None:
    """Cycles on the CPU, WIDTH x HEIGHT px at 100 %, FPS, 32 samples denoised with a fixed seed, motion blur
    off, the Vector pass on, the Standard view transform, 8-bit RGB PNG frames."""
    import bpy

    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 32
    scene.cycles.use_denoising = True
    scene.cycles.seed = 0
    scene.cycles.use_animated_seed = False
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100
    scene.render.fps, scene.render.fps_base = FPS, 1.0
    scene.render.use_motion_blur = False                 # Cycles writes the Vector pass only without it
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    bpy.context.view_layer.use_pass_vector = True
    settings = scene.render.image_settings
    if hasattr(settings, "media_type"):                   # Blender 5.x
        settings.media_type = "IMAGE"
    settings.file_format = "PNG"
    settings.color_mode = "RGB"
    settings.color_depth = "8"


def main(argv: list) -> int:
    import bpy

    args = arguments(argv)
    output = args.output.resolve()
    output.parent.mkdir(parents=True, exist_ok=True)
    build_scene(args.frames)
    bpy.ops.wm.save_as_mainfile(filepath=str(output))
    print(f"world_scene: {output} ({args.frames} frames)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
