# SPDX-License-Identifier: GPL-3.0-or-later
"""Scene settings of Paint Relief: ``bpy.types.Scene.paint_relief``."""

import math
import os

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty
from bpy.types import PropertyGroup

from .. import values

# Sub-folder of the saved .blend file's folder used for outputs by default.
BLEND_RELATIVE_OUTPUT_DIR = "//paint_relief/"

# Blender 4.5+ can mark path properties as accepting "//" (relative to the .blend).
_PATH_OPTIONS = (
    {"PATH_SUPPORTS_BLEND_RELATIVE"}
    if "is_path_supports_blend_relative" in bpy.types.Property.bl_rna.properties
    else set()
)


def _path(name, description, subtype="DIR_PATH"):
    """A folder (or, with ``subtype="FILE_PATH"``, a file) setting; "//" paths, relative to the .blend file, are
    accepted where Blender marks them."""
    return StringProperty(name=name, description=description, subtype=subtype, options=_PATH_OPTIONS)


def paintings_parent(context):
    """The absolute folder that holds one folder per painting when ``output_dir`` is left empty.

    ``paint_relief/`` beside the saved .blend file, else the add-on
    preferences' default output folder (``~/Paint Relief`` when that is empty).
    Never the extension's own user folder, which uninstalling deletes.
    """
    if context.blend_data.filepath:
        return os.path.normpath(bpy.path.abspath(BLEND_RELATIVE_OUTPUT_DIR))
    from .preferences import default_parent

    return default_parent(context)


def output_dir(context):
    """Return the absolute folder the next painting goes into.

    The user's ``output_dir`` when set (the painting replaces what is there);
    else a new folder ``<image name>_<counter>`` inside :func:`paintings_parent`,
    so every painting keeps its own files.
    """
    settings = context.scene.paint_relief
    if settings.output_dir:
        return os.path.normpath(bpy.path.abspath(settings.output_dir))
    return values.next_painting_folder(paintings_parent(context), image_name(settings))


def image_name(settings):
    """The name the painting's folder is made from: the chosen .blend image's name, else the photograph's file."""
    if settings.source == "BLEND_IMAGE" and settings.image is not None:
        return settings.image.name
    return settings.image_path


def comparison_dir(context, painting_dir):
    """Return the absolute folder the lighting comparison writes into.

    The user's ``compare_output_dir`` when set, else ``comparison`` inside
    the painted folder the canvas shows; blend-relative paths are made absolute.
    """
    settings = context.scene.paint_relief
    if settings.compare_output_dir:
        return os.path.normpath(bpy.path.abspath(settings.compare_output_dir))
    return os.path.join(painting_dir, "comparison")


def animation_output_dir(context, key, name):
    """Return the absolute folder the next Paint Animation paints into.

    The user's ``animation_output_dir`` when set (a run into a folder that
    holds an unfinished sequence goes on with it). Else the folder of the
    scene's last Paint Animation when that run stopped before its last frame
    (or before its first, when only the scene's rendered frames are there)
    and ran with ``key`` (``shot_source.source_key``: the source, the
    painter's parameters and the fade), so that pressing Paint Animation
    again goes on with it. Else a new folder ``<name>_<counter>`` (``name``:
    the source's) inside :func:`paintings_parent`.
    """
    settings = context.scene.paint_relief
    if settings.animation_output_dir:
        return os.path.normpath(bpy.path.abspath(settings.animation_output_dir))
    last = os.path.normpath(bpy.path.abspath(settings.animation_dir)) if settings.animation_dir else ""
    if last and settings.animation_key == key and values.sequence_folder_state(last) in ("empty", "unfinished"):
        return last
    return values.next_painting_folder(paintings_parent(context), name)


def extension_repositories():
    """The folders of Blender's extension repositories (Preferences > Get Extensions > Repositories) and the user's
    extensions folder that holds them by default: Blender installs packages there and deletes them on update or
    removal."""
    folders = [repo.directory for repo in bpy.context.preferences.extensions.repos]
    try:
        folders.append(bpy.utils.user_resource("EXTENSIONS"))
    except (ValueError, TypeError):
        pass  # a Blender that names no extensions folder
    return [folder for folder in folders if folder]


def check_output_folder(folder):
    """Raise ValueError (one sentence) when ``folder`` lies inside the installed extension's own folder or its user
    folder, which Blender replaces or deletes when the extension is updated or uninstalled
    (:func:`values.guarded_folders`: a checkout loaded by path guards neither)."""
    from .preferences import EXTENSION_PACKAGE

    package_folder = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    try:
        user_folder = bpy.utils.extension_path_user(EXTENSION_PACKAGE, create=False)
    except (ValueError, RuntimeError, AttributeError):
        user_folder = None  # not loaded as an extension (a checkout loaded by path): it has no user folder
    for parent in values.guarded_folders(package_folder, extension_repositories(), user_folder):
        if values.is_inside(folder, parent):
            raise ValueError("The output folder {} is inside the extension's folder {}, which Blender deletes when "
                             "the extension is updated or removed: choose another folder.".format(folder, parent))


def _update_relief(self, context):
    """Live update: the scene's canvases and painted objects take the new paint thickness at once (no rebuild)."""
    from ..scene import canvas_plane

    painted = [obj for obj in context.scene.objects if obj.get(values.PAINTED_MATERIAL_KEY)]
    for obj in canvas_plane.canvases(context.scene) + painted:
        canvas_plane.set_thickness(obj, self.thickness_mm / 1000.0)


def _update_lights(self, context):
    """Live update: the key and fill lights follow the azimuth and elevation at once (when they exist)."""
    from ..scene import canvas_plane, lighting

    if canvas_plane.find_role(context.scene, "key_light") is not None:
        lighting.aim_lights(context.scene, self.light_azimuth, self.light_elevation, self.light_strength)


class PaintReliefSettings(PropertyGroup):
    """Per-scene settings of Paint Relief."""

    source: EnumProperty(
        name="Source",
        description="Where the picture to paint comes from",
        items=(
            ("FILE", "File", "An image file on disk"),
            ("BLEND_IMAGE", "Image", "An image of this .blend file (loaded from a file on disk)"),
        ),
        default="FILE",
    )
    image: PointerProperty(
        name="Image",
        description="Image of this .blend file to paint; it must have a file on disk",
        type=bpy.types.Image,
    )
    image_path: _path(
        "Photograph",
        "Image file to paint (PNG, JPEG, TIFF, EXR and other formats OpenImageIO reads)",
        subtype="FILE_PATH",
    )
    output_dir: _path(
        "Output Folder",
        (
            "Folder for the painted colour, height and opacity maps and the stroke list (a new painting replaces "
            "what is there). Leave empty to give every painting a new folder named after its image, in a "
            "'paint_relief' folder beside the saved .blend file, or in the add-on preferences' default output "
            "folder while the file is not saved"
        ),
    )

    # --- painter parameters (defaults equal core.Params's) ---
    method: EnumProperty(
        name="Method",
        description="The painting algorithm",
        items=(
            ("HUANG11", "Huang 2011", "Content-dependent strokes after Huang, Fu and Li (2011): large strokes in "
             "smooth areas, small ones where detail is"),
            ("HERTZMANN98", "Hertzmann 1998", "Hertzmann's layered curved brush strokes in one of his styles"),
        ),
        default="HUANG11",
    )
    style: EnumProperty(
        name="Style",
        description="Hertzmann 1998 style (used by the Hertzmann 1998 method)",
        items=(
            ("IMPRESSIONIST", "Impressionist", "Medium strokes following the image's edges"),
            ("EXPRESSIONIST", "Expressionist", "Long, loose strokes"),
            ("COLORIST_WASH", "Colorist Wash", "Thin, transparent washes of colour"),
            ("POINTILLIST", "Pointillist", "Dense dabs of pure colour"),
        ),
        default="IMPRESSIONIST",
    )
    mask_path: _path(
        "Importance Mask",
        "Optional grayscale image of the photograph's size: white areas get smaller, more detailed strokes",
        subtype="FILE_PATH",
    )
    detail: FloatProperty(
        name="Detail",
        description="How finely detailed areas of the photograph are split into small strokes (0 coarse, 1 fine)",
        default=0.9, min=0.0, max=1.0, subtype="FACTOR",
    )
    stroke_sizes: StringProperty(
        name="Stroke Sizes",
        description=(
            "Brush widths in pixels for a 1-megapixel photograph, largest first, separated by commas "
            "(they scale with the square root of the photograph's size), each from 1 px to the width of a "
            "1-megapixel photograph"
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
    timelapse_frames: IntProperty(
        name="Time-lapse frames",
        description="Also write the painting being painted, stroke after stroke, as this many frames into the "
                    "painting's timelapse folder (Build Canvas on it gives an animated relief canvas); 0: none",
        default=0, min=0, max=1000,  # core.files.timelapse.MAX_FRAMES
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
    brush_path: _path(
        "Brush Image",
        "Grayscale PNG brush map used when Brush is Custom (white = bristle, black = no paint)",
        subtype="FILE_PATH",
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
    painting_dir: _path(
        "Painting",
        (
            "Folder of painted maps (color.exr, height.exr, opacity.exr) the canvas is built from. "
            "Paint fills it in; choose any earlier painted folder to use that one"
        ),
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
        update=_update_relief,
    )
    canvas_frame_range: BoolProperty(
        name="Set Frame Range",
        description="Building a canvas of a painted sequence sets the scene's frame range to the sequence's frames",
        default=False,
    )
    displacement_method: EnumProperty(
        name="Displacement",
        description="How the paint's relief becomes geometry",
        items=(
            ("CYCLES_ADAPTIVE", "Cycles Adaptive",
             "Cycles adaptive subdivision with material displacement: finest relief, Cycles renders only"),
            ("MESH", "Mesh",
             "A finely subdivided mesh with a Displace modifier: works in Cycles, EEVEE and Workbench"),
            ("NORMAL_MAP", "Normal Map",
             "A flat plane shaded with the painting's normal map: no displacement, for EEVEE and game export"),
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
        update=_update_lights,
    )
    light_elevation: FloatProperty(
        name="Elevation",
        description="Angle of the key light above the canvas plane: low angles rake across the paint and show its relief",
        default=math.radians(30.0), min=math.radians(1.0), max=math.radians(90.0), subtype="ANGLE",
        update=_update_lights,
    )
    light_strength: FloatProperty(
        name="Brightness",
        description="Brightness of the key light on a flat canvas: 1 makes white paint render white",
        default=0.8, min=0.0, soft_max=5.0,
        update=_update_lights,
    )
    camera_match_resolution: BoolProperty(
        name="Match Render Size",
        description="Add Camera also sets the render size to the painting's map size (one map pixel per render pixel)",
        default=False,
    )
    camera_standard_view: BoolProperty(
        name="Standard View",
        description=(
            "Add Camera also sets colour management to 'Standard' (no look, exposure 0) so renders compare pixel by "
            "pixel with the painting; off keeps the scene's view transform (AgX, Filmic, ...)"
        ),
        default=False,
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
    compare_output_dir: _path(
        "Comparison Folder",
        (
            "Folder for the comparison renders, figures and pictures. Leave empty to use a 'comparison' folder "
            "inside the painting output folder"
        ),
    )


    # --- Paint Animation ---
    animation_source: EnumProperty(
        name="Source",
        description="What Paint Animation paints",
        items=(
            ("SCENE", "Scene", "This scene's animation over its frame range, rendered with its own engine and "
             "painted with the motion Blender renders (the Vector pass)"),
            ("IMAGE", "Image", "An image sequence of this .blend file (an image whose source is Image Sequence)"),
            ("FOLDER", "Folder", "A folder of numbered frames (PNG, JPEG, TIFF or EXR, multilayer EXR included)"),
            ("PATTERN", "Pattern", "Frame files named by a pattern whose '#' stand for the frame number, such as "
             "//render/frame_####.exr"),
        ),
        default="SCENE",
    )
    animation_image: PointerProperty(
        name="Image Sequence",
        description="Image sequence of this .blend file to paint (frames on disk)",
        type=bpy.types.Image,
        poll=lambda self, image: image.source == "SEQUENCE",
    )
    animation_folder: _path(
        "Frames Folder",
        "Folder of the frames to paint, in the order of the frame numbers in their names",
    )
    animation_pattern: _path(
        "Frame Pattern",
        "Path of the frames with '#' for the zero-padded frame number, such as //render/frame_####.exr",
        subtype="FILE_PATH",
    )
    animation_fade_frames: IntProperty(
        name="Fade",
        description="Frames a stroke takes to fade in when it is born and to fade out when it dies",
        default=3, min=1, max=100,
    )
    animation_output_dir: _path(
        "Output Folder",
        (
            "Folder for the painted frames (a run into a folder holding an unfinished painted animation goes on "
            "with it). Leave empty to give every animation a new folder named after its source, where still "
            "paintings go"
        ),
    )
    animation_dir: _path(
        "Animation",
        (
            "Folder of the frames the last Paint Animation of this scene painted. While that run is stopped "
            "before its last frame, Paint Animation with the same source and settings goes on with it: clear "
            "this to start a new folder instead"
        ),
    )
    animation_key: StringProperty(
        name="Animation Run",
        description="What the last Paint Animation painted and how (so that pressing it again goes on with it)",
        options={"HIDDEN"},
    )

    # --- Paint Object ---
    object_texture_size: EnumProperty(
        name="Texture Size",
        description="Texels a side of the texture Paint Object paints in the object's UV space",
        items=tuple((str(size), "{}K".format(size // 1024), "{0} x {0} texels".format(size))
                    for size in values.TEXTURE_SIZE_CHOICES),
        default="2048",
    )
    object_texture_path: _path(
        "Texture File",
        "The picture to paint when the object's material has no image feeding its Base Color (else its diffuse "
        "colour is baked)",
        subtype="FILE_PATH",
    )
    object_stroke_mm: StringProperty(
        name="Stroke Widths",
        description="Stroke widths in millimetres on the surface, such as 32,16,8,4 (empty: the widths a still of "
                    "the texture's size gets, at the size of its median texel)",
        default="",
    )
    object_relief: EnumProperty(
        name="Relief",
        description="How the paint's thickness shows on the object",
        items=(
            ("DISPLACE", "Displace", "Modifiers after the object's own subdivide it and move the surface along "
             "its normals by the paint's height, keeping its shape and its smooth or flat shading"),
            ("NORMAL_MAP", "Normal Map", "The painter's normal map shades the surface (over a material's own "
             "normal map, the paint's height as a bump); its geometry stays"),
            ("CYCLES_ADAPTIVE", "Cycles Displacement", "Cycles moves the surface along its normals by the "
             "material's Displacement at render time, subdivided adaptively (renders in Cycles only)"),
        ),
        default="DISPLACE",
    )
    object_output_dir: _path(
        "Output Folder",
        "Folder for the object's painted maps. Leave empty to give every painting a new folder named after the "
        "object, where still paintings go",
    )

    # --- Paint Scene (Texture Size, Stroke Widths and Relief are Paint Object's) ---
    scene_selected_only: BoolProperty(
        name="Selected Only",
        description="Paint the selected mesh objects (else every mesh object the scene's camera sees over the "
                    "frame range)",
        default=False,
    )
    scene_output_dir: _path(
        "Scene Folder",
        "Folder holding a folder of painted maps for each texture of the scene. Leave empty for a folder named "
        "after the scene where paintings go; painting again keeps every texture already painted there",
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
