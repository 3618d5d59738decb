# SPDX-License-Identifier: GPL-3.0-or-later
"""What Paint Animation paints: the frames of an image sequence, or the scene's own animation.

An image sequence is Blender's image-sequence datablock (an Image whose
source is 'SEQUENCE'), a folder of frames, or a ``#`` pattern such as
``render/frame_####.exr``. A folder and a pattern go to the painter as they
are (it finds, orders and checks their frames); a datablock's files are
found here, as Blender finds them (``image_sequence_files``). Each problem is
a ValueError of one sentence for the operator to report.
"""

import os

import bpy

# Where an image's frame range is set, first found first: what the Image Editor shows, then texture nodes,
# textures, image empties and camera background images.
_NODE_TREE_OWNERS = ("materials", "worlds", "lights", "node_groups")


def _tree_users(image):
    for collection in _NODE_TREE_OWNERS:
        for owner in getattr(bpy.data, collection):
            tree = owner if collection == "node_groups" else getattr(owner, "node_tree", None)
            for node in getattr(tree, "nodes", ()):
                if getattr(node, "image", None) == image and getattr(node, "image_user", None) is not None:
                    yield node.image_user


def _other_users(image):
    for texture in bpy.data.textures:
        if getattr(texture, "image", None) == image:
            yield texture.image_user
    for obj in bpy.data.objects:
        if obj.type == "EMPTY" and obj.data == image:
            yield obj.image_user
    for camera in bpy.data.cameras:
        for background in camera.background_images:
            if background.image == image:
                yield background.image_user


def _editor_users(image):
    window_manager = bpy.context.window_manager
    for window in getattr(window_manager, "windows", ()):
        for area in window.screen.areas:
            for space in area.spaces:
                if space.type == "IMAGE_EDITOR" and space.image == image:
                    yield space.image_user


def image_user(image):
    """The first ImageUser that shows ``image`` (Image Editor, texture node, texture, image empty, camera
    background), or None: its ``frame_offset`` and ``frame_duration`` set which files the sequence plays."""
    for users in (_editor_users, _tree_users, _other_users):
        for user in users(image):
            return user
    return None


def image_path(image):
    """The absolute path of ``image``'s file (relative to its library's .blend when linked)."""
    return os.path.normpath(bpy.path.abspath(image.filepath, library=image.library))


def image_sequence_files(image):
    """The files of the image-sequence datablock ``image``, in frame order, as Blender plays them.

    Blender plays file number ``frame_offset + 1`` to ``frame_offset +
    frame_duration`` of the image's user (``image_user``), named as the
    image's file with its last run of digits replaced (``core.files.shot_files.numbered_file``).
    The sequence starts at that first file, or at the image's own file when
    no user shows the image or that file does not exist, and runs on while
    the next numbered file exists, for at most the user's duration.
    ValueError when ``image`` is not an image sequence or its first file is missing.
    """
    if image.source != "SEQUENCE":
        raise ValueError("Image {} is not an image sequence (its source is {}): choose an image whose source is "
                         "Image Sequence.".format(image.name, image.source.title()))
    path = image_path(image)
    if not image.filepath:
        raise ValueError("Image sequence {} has no file path.".format(image.name))
    from ...core.files import shot_files

    pattern, number = shot_files.numbered_file(path)
    user = image_user(image)
    limit = None
    if user is not None:
        limit = max(1, user.frame_duration)
        if os.path.isfile(shot_files.pattern_file(pattern, user.frame_offset + 1)):
            number = user.frame_offset + 1
    first = shot_files.pattern_file(pattern, number)
    if not os.path.isfile(first):
        raise ValueError("Image sequence {} starts with {}, which does not exist.".format(image.name, first))
    files = []
    while limit is None or len(files) < limit:
        candidate = shot_files.pattern_file(pattern, number + len(files))
        if not os.path.isfile(candidate):
            break
        files.append(candidate)
    return files


def sequence_inputs(settings):
    """The painter's ``inputs`` for the chosen image sequence (not the scene): a list of frame files, or one
    folder or pattern. ValueError (one sentence) when nothing usable is chosen."""
    source = settings.animation_source
    if source == "IMAGE":
        if settings.animation_image is None:
            raise ValueError("Choose an image sequence of this .blend file to paint.")
        return image_sequence_files(settings.animation_image)
    if source == "FOLDER":
        if not settings.animation_folder:
            raise ValueError("Choose the folder of frames to paint.")
        folder = os.path.normpath(bpy.path.abspath(settings.animation_folder))
        if not os.path.isdir(folder):
            raise ValueError("The folder of frames {} does not exist.".format(folder))
        return [folder]
    if source == "PATTERN":
        if not settings.animation_pattern:
            raise ValueError("Give a frame pattern such as //render/frame_####.exr to paint.")
        pattern = os.path.normpath(bpy.path.abspath(settings.animation_pattern))
        if "#" not in os.path.basename(pattern):
            raise ValueError("The frame pattern {} holds no '#' for the frame number, as in "
                             "frame_####.exr.".format(pattern))
        return [pattern]
    raise ValueError("The animation's source {} is not an image sequence.".format(source))


def source_name(settings, scene):
    """The name the painted sequence's folder is made from: the scene's, the image's, the folder's, or the
    pattern's file name."""
    source = settings.animation_source
    if source == "SCENE":
        return scene.name
    if source == "IMAGE":
        return settings.animation_image.name if settings.animation_image is not None else "animation"
    if source == "FOLDER":
        return os.path.basename(bpy.path.abspath(settings.animation_folder).rstrip("/\\")) or "animation"
    return os.path.basename(settings.animation_pattern).replace("#", "") or "animation"


def source_key(settings, scene, view_layer, params):
    """Text naming what a run paints and how (the source: for the scene, its name and ``view_layer``'s; what makes
    a shot's frames, ``core.sequence.shot_settings.shot_key``, its motion's source left to the frames): a stopped
    run's folder is taken up again by a run with the same key."""
    import json

    from ...core.sequence.shot_settings import shot_key

    source = settings.animation_source
    where = {"SCENE": lambda: "{}|{}".format(scene.name, view_layer.name),
             "IMAGE": lambda: settings.animation_image.name if settings.animation_image is not None else "",
             "FOLDER": lambda: bpy.path.abspath(settings.animation_folder),
             "PATTERN": lambda: bpy.path.abspath(settings.animation_pattern)}[source]()
    key = shot_key(params, int(settings.animation_fade_frames), normal_map=False, motion=None)
    return json.dumps({"source": source, "where": where, **key}, sort_keys=True)
