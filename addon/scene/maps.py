# SPDX-License-Identifier: GPL-3.0-or-later
"""A painted folder's maps as Blender images: loading them for a canvas and reading them from disk again.

The painter's checks run first (``core.check_maps``): Blender only ever
receives maps OpenImageIO read in full, finite, with the expected channels
and of equal sizes. The colour map is scene-linear; height, opacity and
normal maps are data. A normal map a folder lacks is made from its height
map (``core.ensure_normal_map``).
"""

import os

import bpy

from .. import values

# Scene-linear Rec.709 has had several names across Blender versions.
_LINEAR_COLORSPACES = ("Linear Rec.709", "Linear", "Linear BT.709", "scene_linear")


class CanvasError(Exception):
    """A map cannot be used; the message is one sentence naming the file."""


def linear_colorspace_name():
    """The name of scene-linear Rec.709 in this Blender's colour management configuration."""
    items = bpy.types.ColorManagedInputColorspaceSettings.bl_rna.properties["name"].enum_items
    available = {item.identifier for item in items}
    for name in _LINEAR_COLORSPACES:
        if name in available:
            return name
    raise CanvasError("Blender's colour configuration has no scene-linear Rec.709 colour space.")


def load_maps(folder, names=values.CANVAS_MAPS):
    """Load (or reload) the canvas maps ``names`` of a painted ``folder``; return {file name: image}.

    Raises CanvasError naming the first missing or unreadable file; images this
    call added are removed again then, so a failure leaves the file's data as
    it was.
    """
    folder = os.path.normpath(bpy.path.abspath(folder))
    paths = {name: os.path.join(folder, name) for name in names}
    for name, path in paths.items():
        if not os.path.isfile(path) and name != values.NORMAL_MAP:
            raise CanvasError("Painted map {} does not exist; paint first or choose a painted folder.".format(path))
    from ... import core

    try:  # Blender only ever receives maps OpenImageIO read in full: finite, expected channels, equal sizes
        core.check_maps(folder, values.CANVAS_MAPS)
        if values.NORMAL_MAP in names:  # made from height.exr when the painter was not asked for it
            core.ensure_normal_map(folder)
            core.check_maps(folder, (values.HEIGHT_MAP, values.NORMAL_MAP))
    except core.PaintReliefError as error:
        raise CanvasError(str(error)) from None
    return load_images(paths)


def load_images(paths):
    """Load (or reload) checked map files as images; return {key: image} for ``paths`` ({key: file path}).

    A key is the map's role, the still painting's file name (``values.COLOR_MAP``, ``HEIGHT_MAP``,
    ``OPACITY_MAP``, ``NORMAL_MAP``): the colour map is loaded as scene-linear, the others as data. A new image
    is named "Paint Relief " and its file's name. Raises CanvasError naming the first file Blender cannot open
    or whose size differs from the colour map's; images this call added are removed again then.
    """
    before = set(bpy.data.images)
    images = {}
    try:
        for name, path in paths.items():
            try:
                image = bpy.data.images.load(path, check_existing=True)
            except RuntimeError as error:
                raise CanvasError("Painted map {} cannot be read: {}.".format(path, str(error).strip().rstrip("."))) from None
            if image not in before:
                image.name = "Paint Relief " + os.path.basename(path)
            else:
                image.reload()
            images[name] = image
            if image.size[0] == 0 or image.size[1] == 0 or not image.has_data and not _loads(image):
                raise CanvasError("Painted map {} cannot be read: not an image Blender can open.".format(path))
        size = tuple(images[values.COLOR_MAP].size)
        for name, image in images.items():
            if tuple(image.size) != size:
                raise CanvasError("Painted map {} is {} x {} px but {} is {} x {} px.".format(
                    paths[name], image.size[0], image.size[1], os.path.basename(paths[values.COLOR_MAP]), size[0],
                    size[1]))
    except CanvasError:
        for image in set(bpy.data.images) - before:
            bpy.data.images.remove(image)
        raise
    images[values.COLOR_MAP].colorspace_settings.name = linear_colorspace_name()
    for name in (values.HEIGHT_MAP, values.OPACITY_MAP, values.NORMAL_MAP):
        if name in images:
            images[name].colorspace_settings.is_data = True
    return images


def _loads(image):
    """True when the pixels of ``image`` can be read (forces a load)."""
    try:
        return len(image.pixels) > 0
    except RuntimeError:
        return False


def reload_images(folder, images):
    """Read ``images``, maps of the painted ``folder``, from disk again (after a repaint from a script); return
    how many.

    A normal map among them is made again from the folder's new height map
    first. Raises CanvasError when a map's file is gone, before any image is
    reloaded.
    """
    if any(os.path.basename(image.filepath) == values.NORMAL_MAP for image in images):
        from ... import core

        try:  # a repainted folder's normal map is made again from its new height map
            core.ensure_normal_map(os.path.normpath(bpy.path.abspath(folder)))
        except core.PaintReliefError as error:
            raise CanvasError(str(error)) from None
    for image in images:
        path = bpy.path.abspath(image.filepath)
        if not os.path.isfile(path):
            raise CanvasError("Painted map {} does not exist; paint again or build the canvas from another "
                              "folder.".format(path))
    for image in images:
        image.reload()
    return len(images)
