# SPDX-License-Identifier: GPL-3.0-or-later
"""Scene settings of Paint Relief: ``bpy.types.Scene.paint_relief``."""

import os

import bpy
from bpy.props import PointerProperty, StringProperty
from bpy.types import PropertyGroup

# ``__package__`` here is "<extension package>.addon"; the extension package
# (``bl_ext.<repository>.paint_relief`` when installed) is its parent. Blender
# keys preferences and per-extension user folders by that parent name.
EXTENSION_PACKAGE = __package__.rpartition(".")[0]

# Sub-folder of the saved .blend file's folder used for outputs by default.
BLEND_RELATIVE_OUTPUT_DIR = "//paint_relief/"

# Blender 4.5+ can mark path properties as accepting "//" (relative to the .blend).
_PATH_OPTIONS = (
    {"PATH_SUPPORTS_BLEND_RELATIVE"}
    if "is_path_supports_blend_relative" in bpy.types.Property.bl_rna.properties
    else set()
)


def default_output_dir(context, *, create=True):
    """Return the folder outputs go to when ``output_dir`` is left empty.

    ``//paint_relief/`` (beside the .blend file) once the file is saved,
    otherwise the extension's own user folder ``.../.user/<repo>/paint_relief/output``
    (created if missing and ``create`` is true; the UI passes ``create=False``).
    The result may be blend-relative: pass it through ``bpy.path.abspath``
    before using it on disk, or use :func:`output_dir`.
    """
    if context.blend_data.filepath:
        return BLEND_RELATIVE_OUTPUT_DIR
    try:
        return bpy.utils.extension_path_user(EXTENSION_PACKAGE, path="output", create=create)
    except ValueError:
        # Not installed as an extension (e.g. the ``addon`` package imported
        # directly in a test): fall back to Blender's temporary folder.
        return os.path.join(bpy.app.tempdir or bpy.utils.user_resource("DATAFILES"), "paint_relief")


def output_dir(context):
    """Return the absolute output folder for the scene's settings.

    The user's ``output_dir`` when set, else :func:`default_output_dir`;
    blend-relative paths ("//...") are made absolute.
    """
    settings = context.scene.paint_relief
    path = settings.output_dir or default_output_dir(context)
    return os.path.normpath(bpy.path.abspath(path))


class PaintReliefSettings(PropertyGroup):
    """Per-scene settings of Paint Relief."""

    image_path: StringProperty(
        name="Photograph",
        description="Image file to paint (PNG, JPEG, TIFF, EXR and other formats OpenImageIO reads)",
        subtype="FILE_PATH",
        options=_PATH_OPTIONS,
    )
    output_dir: StringProperty(
        name="Output Folder",
        description=(
            "Folder for the painted colour, height and opacity maps and the stroke list. "
            "Leave empty to use a 'paint_relief' folder beside the saved .blend file, "
            "or the extension's user folder when the file is not saved yet"
        ),
        subtype="DIR_PATH",
        options=_PATH_OPTIONS,
    )


classes = (PaintReliefSettings,)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.paint_relief = PointerProperty(
        type=PaintReliefSettings,
        name="Paint Relief",
        description="Paint Relief settings of this scene",
    )


def unregister():
    del bpy.types.Scene.paint_relief
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
