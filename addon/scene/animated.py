# SPDX-License-Identifier: GPL-3.0-or-later
"""The animated canvas: a painted sequence's maps as image sequences that follow the scene's frame.

A folder painted by ``python -m core sequence`` (or Paint Animation) holds,
for every frame N, ``color_NNNN.exr``, ``height_NNNN.exr`` and
``opacity_NNNN.exr`` (``normal_NNNN.exr`` when painted with normal maps)
and a report.json that lists the frames. Its canvas is a still canvas
(``canvas_plane.canvas_from_images``: the same object, mesh, modifiers and
material, rebuilt in place with the user's transform, nodes and modifiers
kept) whose images are Blender image sequences (``image.source ==
'SEQUENCE'``) read by every image user of the canvas: the material's colour,
height, opacity (and normal) nodes and the Displace modifier's texture. Each
image user shows frame N of the sequence at scene frame N and holds the
last frame after the sequence; it refreshes with the scene's frame, so
scrubbing the timeline and rendering an animation show each painted frame
with its own relief. Before the sequence's first frame there is no file to
show, as for any image sequence in Blender: no relief, and Blender's
missing-image colour (the option to set the scene's frame range to the
sequence keeps the timeline on painted frames).

The canvas remembers the sequence's first frame and frame count
(``SEQUENCE_KEY``); Reload Maps reads the folder's report again, so frames
painted since (a resumed sequence) join the canvas.
"""

import os

import bpy

from .. import values
from .canvas_plane import PAINTING_DIR_KEY, canvas_from_images
from .maps import CanvasError, load_images
from .material import own_nodes

# (first frame number, frame count) of the painted sequence an animated canvas shows.
SEQUENCE_KEY = "paint_relief_sequence"


def is_sequence_folder(folder):
    """True when ``folder`` holds a painted sequence's report (``values.sequence_frames``)."""
    return values.sequence_frames(os.path.normpath(bpy.path.abspath(folder))) is not None


def is_animated(obj):
    """True when ``obj`` is a canvas built from a painted sequence."""
    return obj is not None and SEQUENCE_KEY in obj


def painted_frames(folder, map_names):
    """The painted sequence's frame numbers in ``folder``, its maps checked; CanvasError (one sentence) otherwise.

    map_names: the still names of the maps the canvas reads (``values.CANVAS_MAPS``, and ``values.NORMAL_MAP``).
    Every frame's files must exist; the first and the last frame's are read
    in full by the painter's checks (finite values, expected sizes, one
    painting). The frames of a sequence are committed whole, each frame's
    files together, so the ones between are complete too.
    """
    from ... import core
    from ...core.files import shot_files

    frames = values.sequence_frames(folder)
    if frames is None:
        raise CanvasError("The folder {} holds no painted sequence (no sequence report.json).".format(folder))
    if not frames:
        raise CanvasError("The painted sequence in {} has no painted frame yet; paint it first.".format(folder))
    for number in frames:
        for name in map_names:
            path = os.path.join(folder, shot_files.numbered_name(name, number))
            if not os.path.isfile(path):
                hint = (" (paint the sequence with normal maps, or choose another displacement method)"
                        if name == values.NORMAL_MAP else "")
                raise CanvasError("Painted map {} does not exist{}.".format(path, hint))
    try:
        for number in sorted({frames[0], frames[-1]}):
            core.check_maps(folder, [shot_files.numbered_name(name, number) for name in map_names])
    except core.PaintReliefError as error:
        raise CanvasError(str(error)) from None
    return frames


def load_sequence_maps(folder, frames, map_names):
    """{still map name: image} of the sequence's maps ``map_names``, loaded from the first frame's files.

    The images are still images ('FILE') when this returns, so Blender
    reports their size; :func:`make_sequences` turns them into image
    sequences. Images of an earlier build are reused. Raises CanvasError as
    ``maps.load_images`` (images of an earlier build are sequences again then).
    """
    from ...core.files import shot_files

    paths = {name: os.path.join(folder, shot_files.numbered_name(name, frames[0])) for name in map_names}
    wanted = {os.path.normpath(path) for path in paths.values()}
    earlier = [image for image in bpy.data.images if image.source == "SEQUENCE"
               and os.path.normpath(bpy.path.abspath(image.filepath)) in wanted]
    for image in earlier:  # an image sequence has no size until an image user shows a frame of it
        image.source = "FILE"
    try:
        return load_images(paths)
    except CanvasError:
        make_sequences(earlier)
        raise


def make_sequences(images):
    """Turn ``images`` (each the first frame's file of a map) into image sequences."""
    for image in images:
        if image.source != "SEQUENCE":
            image.source = "SEQUENCE"


def follow_frames(image_user, first, count):
    """Make ``image_user`` show frame N of a sequence of ``count`` frames from ``first`` at scene frame N.

    At scene frame F Blender shows the file numbered min(F - frame_start + 1, frame_duration) +
    frame_offset: frame_start = first, frame_offset = first - 1. After the sequence it holds the
    last frame; before it, it finds no file. It refreshes when the frame changes.
    """
    image_user.frame_duration = int(count)
    image_user.frame_start = int(first)
    image_user.frame_offset = int(first) - 1
    image_user.use_cyclic = False
    image_user.use_auto_refresh = True


def image_readers(obj):
    """(image, image user) of every reader of the canvas's maps: its material's own image nodes and its
    Displace modifier's image texture."""
    readers = []
    material = obj.active_material
    if material is not None and material.node_tree is not None:
        readers += [(node.image, node.image_user) for node in own_nodes(material.node_tree).values()
                    if node.bl_idname == "ShaderNodeTexImage" and node.image is not None]
    for modifier in obj.modifiers:
        texture = getattr(modifier, "texture", None)
        if modifier.type == "DISPLACE" and texture is not None and texture.type == "IMAGE" and texture.image:
            readers.append((texture.image, texture.image_user))
    return readers


def image_users(obj):
    """The image users of the canvas that read one of its image sequences."""
    return [user for image, user in image_readers(obj) if image.source == "SEQUENCE"]


def show_sequence(obj, frames):
    """Point every image user of the canvas ``obj`` at the painted ``frames`` and record them on it."""
    first, count = int(frames[0]), len(frames)
    for user in image_users(obj):
        follow_frames(user, first, count)
    obj[SEQUENCE_KEY] = (first, count)


def set_frame_range(scene, frames):
    """Set the scene's frame range to the painted ``frames`` (first to last)."""
    scene.frame_start = int(frames[0])
    scene.frame_end = int(frames[-1])


def build_animated_canvas(context, folder, width_cm, thickness_mm, method, frame_range=False):
    """Create or update the scene's animated canvas from the painted sequence in ``folder``; return the object.

    width_cm, thickness_mm, method: as for ``canvas_plane.build_canvas`` (method
    'NORMAL_MAP' needs a sequence painted with normal maps). frame_range:
    also set the scene's frame range to the sequence's frames (the scene's
    range is left alone otherwise). Raises CanvasError (before changing
    anything in the scene) when the folder holds no painted frame or a map is
    missing or unreadable.
    """
    folder = os.path.normpath(bpy.path.abspath(folder))
    map_names = values.CANVAS_MAPS + ((values.NORMAL_MAP,) if method == "NORMAL_MAP" else ())
    frames = painted_frames(folder, map_names)
    images = load_sequence_maps(folder, frames, map_names)
    obj = canvas_from_images(context, folder, images, width_cm, thickness_mm, method)
    make_sequences(images.values())
    show_sequence(obj, frames)
    if frame_range:
        set_frame_range(context.scene, frames)
    return obj


def reload_maps(obj):
    """Read the animated canvas's painted sequence from disk again, frames painted since included; return how
    many image sequences.

    Raises CanvasError when the painted folder, its report or a frame's map is gone.
    """
    folder = obj.get(PAINTING_DIR_KEY)
    if not folder:
        raise CanvasError("Canvas {} does not remember its painted folder: build it again.".format(obj.name))
    images = {image for image, _ in image_readers(obj) if image.source == "SEQUENCE"}
    names = [name for name in values.CANVAS_MAPS + (values.NORMAL_MAP,)
             if any(_is_map(image, name) for image in images)]
    frames = painted_frames(folder, names)
    for image in images:
        image.reload()
    show_sequence(obj, frames)
    return len(images)


def _is_map(image, map_name):
    """True when ``image`` is a frame file of the map ``map_name`` (``color_0001.exr`` of ``color.exr``)."""
    stem = map_name.rpartition(".")[0]
    return os.path.basename(bpy.path.abspath(image.filepath)).startswith(stem + "_")
