# SPDX-License-Identifier: GPL-3.0-or-later
"""Pure helpers of the add-on: settings text to values, physical sizes, grids, directions.

Nothing here imports ``bpy`` (NumPy, the painter's naming rules in
``core.files.folders`` and ``core.files.shot_files`` and its limits in
``core.params``, imported where needed), so these functions are tested without Blender. Lengths are metres
unless a name says otherwise; angles are radians.
"""

import math

# Files of a painted folder the canvas needs (written by core.files.export.write_painting).
COLOR_MAP = "color.exr"
HEIGHT_MAP = "height.exr"
OPACITY_MAP = "opacity.exr"
CANVAS_MAPS = (COLOR_MAP, HEIGHT_MAP, OPACITY_MAP)
# Tangent-space normals, n * 0.5 + 0.5 (the Normal Map canvas).
NORMAL_MAP = "normal.exr"


def parse_sizes(text):
    """Parse stroke sizes such as ``"64, 32,16 8"`` into a tuple of positive ints.

    Commas and/or spaces separate the sizes. Raises ValueError with a sentence
    naming the bad entry; the largest size is ``core.params.MAX_STROKE_SIZE``.
    """
    from ..core.params import MAX_STROKE_SIZE

    entries = _entries(text, int, "Stroke size {!r} is not a whole number of pixels.")
    if not entries:
        raise ValueError("Stroke sizes are empty: give sizes in pixels such as 64,32,16,8,4.")
    sizes = []
    for value in entries:
        if value <= 0:
            raise ValueError("Stroke size {} must be positive.".format(value))
        if value > MAX_STROKE_SIZE:
            raise ValueError("Stroke size {} is larger than {} px, a brush as wide as a 1-megapixel "
                             "photograph.".format(value, MAX_STROKE_SIZE))
        if value in sizes:
            raise ValueError("Stroke size {} is given twice: give each size once.".format(value))
        sizes.append(value)
    return tuple(sizes)


def _entries(text, convert, not_one):
    """The entries of ``text``, separated by commas and/or spaces, each converted by ``convert``; ValueError with
    the sentence ``not_one`` (formatted with the entry) for an entry ``convert`` refuses."""
    values = []
    for part in text.replace(",", " ").split():
        try:
            values.append(convert(part))
        except ValueError:
            raise ValueError(not_one.format(part)) from None
    return values


def canvas_size(map_width, map_height, width_cm):
    """Physical canvas size (width, height) in metres for a map of ``map_width`` x ``map_height`` px.

    The width is ``width_cm`` centimetres; the height follows the map's aspect.
    """
    if map_width <= 0 or map_height <= 0:
        raise ValueError("The map size must be positive, got {} x {}.".format(map_width, map_height))
    width = width_cm / 100.0
    return width, width * map_height / map_width


def grid_resolution(map_width, map_height, pixels_per_vertex=2.0, max_vertices=300_000):
    """Vertices (nx, ny) along x and y of a grid for a map of ``map_width`` x ``map_height`` px.

    One vertex per ``pixels_per_vertex`` map pixels, plus one for the far edge,
    reduced evenly so that ``nx * ny <= max_vertices``; at least 2 x 2.
    """
    nx = map_width / pixels_per_vertex + 1.0
    ny = map_height / pixels_per_vertex + 1.0
    if nx * ny > max_vertices:
        scale = math.sqrt(max_vertices / (nx * ny))
        nx, ny = nx * scale, ny * scale
    return max(2, int(nx)), max(2, int(ny))


def grid_arrays(nx, ny, width, height):
    """Arrays of a flat ``width`` x ``height`` grid centred on the origin, in the XY plane.

    Returns (co, loops, loop_starts, uv):
    co          float32 (nx*ny*3,) vertex positions, row by row from -y to +y
    loops       int32 (F*4,) vertex indices of the quads, counter-clockwise seen from +z
    loop_starts int32 (F,) first loop of each quad (F = (nx-1)*(ny-1))
    uv          float32 (F*4*2,) per-loop UVs: (0, 0) at the -x -y corner, (1, 1) at +x +y
    """
    import numpy as np

    u = np.linspace(0.0, 1.0, nx, dtype=np.float64)
    v = np.linspace(0.0, 1.0, ny, dtype=np.float64)
    uu, vv = np.meshgrid(u, v)  # (ny, nx)
    co = np.stack([(uu - 0.5) * width, (vv - 0.5) * height, np.zeros_like(uu)], axis=-1)
    index = np.arange(nx * ny, dtype=np.int32).reshape(ny, nx)
    quads = np.stack([index[:-1, :-1], index[:-1, 1:], index[1:, 1:], index[1:, :-1]], axis=-1).reshape(-1)
    uv_vertex = np.stack([uu, vv], axis=-1).reshape(-1, 2)
    faces = (nx - 1) * (ny - 1)
    return (co.astype(np.float32).reshape(-1), quads.astype(np.int32),
            (np.arange(faces, dtype=np.int32) * 4), uv_vertex[quads].astype(np.float32).reshape(-1))


def light_direction(azimuth, elevation):
    """Unit vector (x, y, z) from the canvas towards a light.

    The canvas lies in the XY plane facing +z, the image's right along +x and
    its top along +y. ``azimuth`` follows the painter's convention: measured
    in the image from its right edge towards its bottom edge (clockwise as
    seen from the camera above: 0 right, 90 bottom, 180 left, 270 top);
    ``elevation`` is the angle above the canvas plane.
    """
    c = math.cos(elevation)
    return (c * math.cos(azimuth), -c * math.sin(azimuth), math.sin(elevation))


def wave_scale_for_period(period):
    """Scale of Blender's Wave Texture (bands, sine profile) giving ``period`` object units between bands.

    The bands are sin(20 * scale * coordinate), so the period is 2 pi / (20 scale).
    """
    return 2.0 * math.pi / (20.0 * period)


# --- the lighting comparison (addon/comparison/, sample_scenes/compare.py) ---------

def sweep_azimuths(count):
    """``count`` light azimuths in degrees, evenly spaced from 0: [0, 360/count, ...].

    Raises ValueError (one sentence) when ``count`` is below 1.
    """
    count = int(count)
    if count < 1:
        raise ValueError("The light sweep needs at least one azimuth, got {}.".format(count))
    return [360.0 * i / count for i in range(count)]


def render_file_name(kind, azimuth_deg):
    """File name of a sweep render: ``relief_045.exr`` / ``flat_045.exr`` (azimuth in the painter's degrees)."""
    if kind not in ("relief", "flat"):
        raise ValueError("A sweep render is 'relief' or 'flat', not {!r}.".format(kind))
    return "{}_{:03.0f}.exr".format(kind, azimuth_deg)


def check_render_names(azimuths_deg):
    """Raise ValueError (one sentence) when two azimuths would share one render file name."""
    seen = {}
    for azimuth in azimuths_deg:
        name = render_file_name("relief", azimuth)
        if name in seen:
            raise ValueError("Light azimuths {:g} and {:g} degrees would share the render {}: "
                             "use fewer azimuths.".format(seen[name], azimuth, name))
        seen[name] = azimuth


def relief_pixels(thickness_mm, width_cm, map_width):
    """The canvas relief in the 2-D bump model's unit: pixel widths per height unit.

    Paint of height 1 stands ``thickness_mm`` high on a canvas ``width_cm``
    wide that holds ``map_width`` map pixels.
    """
    pixel_mm = 10.0 * width_cm / map_width
    return thickness_mm / pixel_mm


def film_size(map_width, map_height, longest):
    """(width, height) in px of renders of a ``map_width`` x ``map_height`` map whose longer side is at most
    ``longest`` px (never enlarged), keeping the aspect."""
    scale = min(1.0, longest / max(map_width, map_height))
    return max(1, round(map_width * scale)), max(1, round(map_height * scale))


# --- painted shots (addon/scene/animated.py, Paint Animation) -----------------------
# The folder's files and report.json follow core.files.shot_files, imported inside the functions.

def _shot_report(folder):
    """The report.json of the shot painted in ``folder``; None when it holds none, a still's, or one that cannot
    be read."""
    from ..core.files import shot_files

    try:
        report = shot_files.read_report(folder)
    except (OSError, ValueError):
        return None
    return report if report is not None and shot_files.is_shot_report(report) else None


def sequence_frames(folder):
    """The frame numbers painted in ``folder`` when it holds a painted shot, else None.

    A painted shot's report.json (``python -m core sequence``) lists its
    committed frames under "frames", in order and running up by 1. None for
    a folder without report.json, with one that cannot be read, or with a
    still painting's report.
    """
    report = _shot_report(folder)
    if report is None or not isinstance(report.get("frames"), list):
        return None
    return [int(number) for number in report["frames"]]


def sequence_folder_state(folder):
    """What a painted folder holds, from its report.json: ``"empty"`` (no report: nothing painted yet, or no
    folder), ``"still"`` (a still painting), ``"unfinished"`` or ``"complete"`` (a painted shot), or
    ``"unreadable"`` (a report that cannot be read)."""
    from ..core.files import shot_files

    try:
        report = shot_files.read_report(folder)
    except (OSError, ValueError):
        return "unreadable"
    if report is None:
        return "empty"
    if not shot_files.is_shot_report(report):
        return "still"
    return "complete" if report.get("complete") else "unfinished"


def sequence_folder_inputs(folder):
    """The input frame files (as written in its report.json) of the shot painted in ``folder``; None when it
    holds no readable shot report."""
    report = _shot_report(folder)
    inputs = report.get("input") if report is not None else None
    return [str(path) for path in inputs] if isinstance(inputs, list) else None


# --- where paintings go --------------------------------------------------------

def folder_stem(image_path):
    """A folder-name-safe stem of an image file name: ``"My photo (1).JPG"`` -> ``"My_photo_1"``
    (core.files.folders.folder_stem, the painter's one naming rule)."""
    from ..core.files import folders

    return folders.folder_stem(image_path)


def next_painting_folder(parent, image_path, digits=3):
    """The first ``parent/<stem>_<counter>`` (counter from 1, ``digits`` wide) that does not exist yet
    (core.files.folders.next_painting_folder, as ``python -m core`` names its folders). Nothing is created."""
    from ..core.files import folders

    return folders.next_painting_folder(parent, image_path, digits)


# --- image sequences and the scene's render (Paint Animation) ----------------------

def render_file_stem(number):
    """The scene render's file name of frame ``number`` without its extension: ``frame_0012`` (the painter
    numbers the painted frames from it). ValueError (one sentence) for a negative frame."""
    if number < 0:
        raise ValueError("Frame {} is negative: Paint Animation renders frames from 0 on; move the scene's "
                         "frame range.".format(number))
    from ..core.files import shot_files

    return "frame" + shot_files.frame_suffix(number)


def escape_render_path(path, templates):
    """``path`` as a literal render output path: with ``templates`` (Blender 5.0 and later read ``{name}`` in
    output paths as a variable) every brace is doubled, so a folder named ``a{b}`` stays ``a{b}``."""
    path = str(path)
    return path.replace("{", "{{").replace("}", "}}") if templates else path


def render_progress(rendered, count, painted):
    """The whole run's progress in [0, 1] for the scene's animation: rendering ``rendered`` of ``count``
    frames fills the first half, painting (``painted`` in [0, 1]) the second."""
    if count <= 0:
        return painted
    return 0.5 * min(rendered, count) / count + 0.5 * painted


def is_inside(path, parent):
    """True when the folder or file ``path`` is ``parent`` or lies inside it (symbolic links resolved)."""
    import os

    path, parent = os.path.realpath(str(path)), os.path.realpath(str(parent))
    try:
        return os.path.commonpath([path, parent]) == parent
    except ValueError:  # different drives
        return False


def guarded_folders(package_folder, repositories, user_folder=None):
    """The folders an output folder must stay out of, for the extension whose package is ``package_folder``.

    Its package folder when that lies in one of Blender's extension ``repositories`` (their folders): Blender
    installed it there and deletes it when the extension is updated or removed. A checkout loaded by path is not
    such a folder, nor one linked into a repository, whose link alone Blender removes (symbolic links resolved,
    as :func:`is_inside` does). Its ``user_folder`` (``bpy.utils.extension_path_user``) when given: Blender
    deletes it with the extension.
    """
    guarded = [package_folder] if any(is_inside(package_folder, folder) for folder in repositories if folder) else []
    return guarded + ([user_folder] if user_folder else [])


PAINTED_MATERIAL_KEY = "paint_relief_painted_material"
"""The custom property holding a painted object's own material (Paint Object; a file painted before names it)."""

TEXTURE_SIZE_CHOICES = (1024, 2048, 4096, 8192)
"""The texture sizes (texels a side) Paint Object offers, within ``core.params.TEXTURE_SIZE_RANGE``."""


def relief_levels(faces, texture_size, most=6):
    """Subdivision levels (0 .. ``most``) that give a mesh of ``faces`` faces about one vertex for every 4 x 4
    texels of a ``texture_size`` texture, enough for the displaced relief to show each stroke."""
    import math

    wanted = (texture_size / 4.0) ** 2 / max(1, faces)
    return max(0, min(most, int(round(math.log(max(wanted, 1.0), 4)))))


def parse_widths(text):
    """Stroke widths in millimetres such as ``"32, 16 8"`` as a tuple of positive floats, or None for an empty
    text (the painter's default). Raises ValueError with a sentence naming the bad entry."""
    widths = _entries(text, float, "Stroke width {!r} is not a number of millimetres.")
    for value in widths:
        if not value > 0 or value != value or value == float("inf"):
            raise ValueError("Stroke width {:g} must be a positive number of millimetres.".format(value))
    return tuple(widths) or None
