# SPDX-License-Identifier: GPL-3.0-or-later
"""Scene settings of Paint Relief: ``bpy.types.Scene.paint_relief``."""

import math
import os

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty
from bpy.types import PropertyGroup

from . import values

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


def comparison_dir(context):
    """Return the absolute folder the lighting comparison writes into.

    The user's ``compare_output_dir`` when set, else ``comparison`` inside
    :func:`output_dir`; blend-relative paths are made absolute.
    """
    settings = context.scene.paint_relief
    if settings.compare_output_dir:
        return os.path.normpath(bpy.path.abspath(settings.compare_output_dir))
    return os.path.join(output_dir(context), "comparison")


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

    # --- painter parameters (defaults equal core.Params's) ---
    detail: FloatProperty(
        name="Detail",
        description="How finely detailed areas of the photograph are split into small strokes (0 coarse, 1 fine)",
        default=0.17, min=0.0, max=1.0, subtype="FACTOR",
    )
    stroke_sizes: StringProperty(
        name="Stroke Sizes",
        description=(
            "Brush widths in pixels for a 1-megapixel photograph, largest first, separated by commas "
            "(they scale with the square root of the photograph's size), each from 1 to {} px".format(
                values.MAX_STROKE_SIZE)
        ),
        default="64,32,16,8,4",
        maxlen=64,
    )
    layers: IntProperty(
        name="Layers",
        description="Number of paint layers laid one over the other",
        default=4, min=1, max=16,
    )
    seed: IntProperty(
        name="Seed",
        description="Seed of the random stroke variations: the same photograph, settings and seed give the same painting",
        default=0, min=0,
    )
    brush: EnumProperty(
        name="Brush",
        description="Bristle pattern of every stroke",
        items=(
            ("FLAT", "Flat", "A flat brush: even bristles across the stroke"),
            ("ROUND", "Round", "A round brush: bristles thin out towards the stroke's sides"),
            ("FILBERT", "Filbert", "A filbert brush: flat with rounded edges"),
            ("CUSTOM", "Custom", "A grayscale PNG brush map of your own (columns across the stroke, rows along it)"),
        ),
        default="FLAT",
    )
    brush_path: StringProperty(
        name="Brush Image",
        description="Grayscale PNG brush map used when Brush is Custom (white = bristle, black = no paint)",
        subtype="FILE_PATH",
        options=_PATH_OPTIONS,
    )
    height_mode: EnumProperty(
        name="Height Mode",
        description="How the paint height of overlapping strokes combines",
        items=(
            ("OVER", "Over", "Each stroke covers the height below it by its opacity (the paper's weighted sum)"),
            ("ACCUMULATE", "Accumulate", "Paint piles up stroke by stroke, as thick impasto does"),
        ),
        default="OVER",
    )

    # --- the canvas in the scene ---
    painting_dir: StringProperty(
        name="Painting",
        description=(
            "Folder of painted maps (color.exr, height.exr, opacity.exr) the canvas is built from. "
            "Paint fills it in; choose any earlier painted folder to use that one"
        ),
        subtype="DIR_PATH",
        options=_PATH_OPTIONS,
    )
    canvas_width_cm: FloatProperty(
        name="Canvas Width",
        description="Physical width of the canvas in centimetres; the height follows the painting's aspect",
        default=40.0, min=1.0, soft_max=300.0, precision=1,
    )
    thickness_mm: FloatProperty(
        name="Paint Thickness",
        description="Physical height in millimetres of paint of height 1 (one full bristle's contact)",
        default=2.0, min=0.0, soft_max=20.0, precision=2,
    )
    displacement_method: EnumProperty(
        name="Displacement",
        description="How the paint's relief becomes geometry",
        items=(
            ("CYCLES_ADAPTIVE", "Cycles Adaptive",
             "Cycles adaptive subdivision with material displacement: finest relief, Cycles renders only"),
            ("MESH", "Mesh",
             "A finely subdivided mesh with a Displace modifier: works in Cycles, EEVEE and Workbench"),
        ),
        default="MESH",
    )

    # --- lighting ---
    light_azimuth: FloatProperty(
        name="Azimuth",
        description=(
            "Direction the key light comes from, in the canvas plane, as the painter measures it: 0 is the "
            "painting's right edge, 90 its bottom edge, 180 the left, 270 the top"
        ),
        default=math.radians(225.0), min=-2.0 * math.pi, max=2.0 * math.pi, subtype="ANGLE",
    )
    light_elevation: FloatProperty(
        name="Elevation",
        description="Angle of the key light above the canvas plane: low angles rake across the paint and show its relief",
        default=math.radians(30.0), min=math.radians(1.0), max=math.radians(90.0), subtype="ANGLE",
    )
    light_strength: FloatProperty(
        name="Brightness",
        description="Brightness of the key light on a flat canvas: 1 makes white paint render white",
        default=0.8, min=0.0, soft_max=5.0,
    )
    fill_light: BoolProperty(
        name="Fill Light",
        description="Add a soft, weak light from the opposite side so shadowed paint keeps some colour",
        default=True,
    )

    # --- the lighting comparison ---
    compare_azimuths: IntProperty(
        name="Light Directions",
        description=(
            "Number of key light azimuths of the comparison sweep, evenly spaced around the canvas from its right "
            "edge; each is rendered with and without relief"
        ),
        default=8, min=1, soft_max=36, max=360,
    )
    compare_samples: IntProperty(
        name="Samples",
        description="Cycles samples per pixel of each comparison render",
        default=16, min=1, soft_max=256,
    )
    compare_output_dir: StringProperty(
        name="Comparison Folder",
        description=(
            "Folder for the comparison renders, figures and pictures. Leave empty to use a 'comparison' folder "
            "inside the painting output folder"
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
