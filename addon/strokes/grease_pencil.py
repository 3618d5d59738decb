# SPDX-License-Identifier: GPL-3.0-or-later
"""The painting's strokes as a Grease Pencil object, and the object's strokes read back as drawn strokes.

The object (``ROLE_KEY == "grease_pencil"``) holds one layer, ``LAYER``,
with one keyframe at frame 1 whose strokes are the painting's in paint
order: one stroke per stroke of strokes.json, its points along the stroke's
path, the radius (metres) half the brush width, the vertex colour the
stroke's colour (scene-linear, mix factor 1) and the opacity its contact.
The points are in the canvas plane's own coordinates (``core``'s
``DrawnStrokes.plane_points``), ``lift`` metres above it: the object is
parented to the scene's canvas of the painting when there is one (it follows
the canvas), else it stands where a new canvas would, at the 3D cursor, at
the size a canvas ``width_cm`` wide has. A Build modifier ('SEQUENTIAL',
frames) reveals the strokes in paint order over the scene's frame range.

Each stroke carries its index in the painting's strokes.json plus one (0:
drawn anew): Grease Pencil 3 (Blender 4.3 and later) in the stroke (curve)
attribute ``INDEX_ATTRIBUTE``, which Blender keeps through moves, deletions
and recolouring; the legacy Grease Pencil of Blender 4.2 in the stroke's
``uv_translation[0]``, which only places a fill texture (the material has no
fill) and is (0, 0) on a stroke drawn anew. ``read_drawn`` reads the
strokes back, in their order, as ``core``'s drawn strokes (the stroke's
radius the mean of its points', its colour the mean of its points' vertex
colours mixed over its material's colour).

Legacy strokes keep their radius as ``line_width`` x ``pressure`` / 2000
metres (the factor Blender's conversion to Grease Pencil 3 uses), with
``line_width`` LEGACY_LINE_WIDTH.
"""

import bpy
import numpy as np

from ..scene import canvas_plane

ROLE = "grease_pencil"
LAYER = "Paint"
INDEX_ATTRIBUTE = "paint_relief_stroke"
PLANE_KEY = "paint_relief_plane"
"""On the object: (width, height) metres of the plane its points lie on."""
LIFT_KEY = "paint_relief_lift"
"""On the object: metres its strokes float above that plane."""
MATERIAL_NAME = "Paint Relief Strokes"
BUILD_MODIFIER = "Paint Relief Build"
OBJECT_NAME = "Paint Relief Strokes"
LEGACY_LINE_WIDTH = 1000
LEGACY_RADIUS_FACTOR = 1.0 / 2000.0
DEFAULT_LIFT = 0.001
"""Metres the strokes float above the highest paint, so they are drawn over the relief."""


class StrokesError(ValueError):
    """A Grease Pencil object cannot be made or read; the message is one sentence."""


def is_grease_pencil_3():
    """Whether this Blender has Grease Pencil 3 (4.3 and later) rather than the legacy one (4.2)."""
    return hasattr(bpy.types, "GreasePencilDrawing")


def _data_collection():
    """Where new Grease Pencil data goes: ``grease_pencils_v3`` in Blender 4.3 to 4.5 (``grease_pencils`` is the
    legacy kind there), ``grease_pencils`` in 4.2 (legacy) and 5.0 and later (Grease Pencil 3)."""
    found = getattr(bpy.data, "grease_pencils_v3", None)
    return found if found is not None else bpy.data.grease_pencils


def stroke_objects(scene):
    """The scene's Grease Pencil objects of paintings, in the scene's order."""
    return [obj for obj in scene.objects if obj.get(canvas_plane.ROLE_KEY) == ROLE]


def active_strokes(context):
    """The Grease Pencil object the round trip lays: the active object when it is one, else the scene's first;
    or None."""
    active = context.view_layer.objects.active if context.view_layer is not None else None
    if active is not None and active.get(canvas_plane.ROLE_KEY) == ROLE and active.name in context.scene.objects:
        return active
    found = stroke_objects(context.scene)
    return found[0] if found else None


def _material():
    """The Grease Pencil material the strokes are drawn with: white strokes, no fill (vertex colours paint)."""
    material = bpy.data.materials.get(MATERIAL_NAME)
    if material is None or material.grease_pencil is None:
        material = bpy.data.materials.new(MATERIAL_NAME)
        bpy.data.materials.create_gpencil_data(material)
    style = material.grease_pencil
    style.show_stroke = True
    style.show_fill = False
    style.color = (1.0, 1.0, 1.0, 1.0)
    return material


def _attribute(drawing, name, data_type, domain):
    found = drawing.attributes.get(name)
    if found is not None and (found.data_type != data_type or found.domain != domain):
        drawing.attributes.remove(found)
        found = None
    return found if found is not None else drawing.attributes.new(name, data_type, domain)


def write_strokes(frame, drawn, plane, lift):
    """Put ``drawn`` (``DrawnStrokes``) into the Grease Pencil ``frame`` (replacing its strokes) on a plane of
    ``plane`` (width, height) metres, ``lift`` metres above it."""
    points = drawn.plane_points(plane[0], plane[1], lift)
    radius = (0.5 * drawn.width * drawn.metres_per_pixel(plane[0])).astype(np.float32)
    colour = np.concatenate([drawn.linear_colour(), np.ones((len(drawn), 1), np.float32)], axis=1)
    per_point = np.repeat(np.arange(len(drawn)), drawn.counts)
    index = (drawn.index + 1).astype(np.int32)
    if is_grease_pencil_3():
        drawing = frame.drawing
        if len(drawing.strokes):
            drawing.remove_strokes()
        if not len(drawn):
            return
        drawing.add_strokes(drawn.counts.tolist())
        drawing.attributes["position"].data.foreach_set("vector", points.ravel())
        _attribute(drawing, "radius", "FLOAT", "POINT").data.foreach_set("value", radius[per_point])
        _attribute(drawing, "opacity", "FLOAT", "POINT").data.foreach_set("value", drawn.opacity[per_point])
        _attribute(drawing, "vertex_color", "FLOAT_COLOR", "POINT").data.foreach_set(
            "color", colour[per_point].ravel())
        _attribute(drawing, INDEX_ATTRIBUTE, "INT", "CURVE").data.foreach_set("value", index)
        drawing.tag_positions_changed()
        return
    frame.clear()
    pressure = (radius / (LEGACY_LINE_WIDTH * LEGACY_RADIUS_FACTOR)).astype(np.float32)
    starts = drawn.starts
    strokes = frame.strokes
    for i in range(len(drawn)):
        first, stop = starts[i], starts[i + 1]
        stroke = strokes.new()
        stroke.display_mode = "3DSPACE"
        stroke.line_width = LEGACY_LINE_WIDTH
        stroke.material_index = 0
        stroke.uv_translation = (float(index[i]), 0.0)
        stroke.points.add(int(stop - first))
        stroke.points.foreach_set("co", points[first:stop].ravel())
        stroke.points.foreach_set("pressure", np.full(stop - first, pressure[i], np.float32))
        stroke.points.foreach_set("strength", np.full(stop - first, drawn.opacity[i], np.float32))
        stroke.points.foreach_set("vertex_color", np.tile(colour[i], stop - first))


def add_build(obj, frame_start, frame_end):
    """The object's Build modifier: the strokes appear one after another, in paint order, from ``frame_start``
    until all are drawn at ``frame_end``."""
    if is_grease_pencil_3():
        modifier = obj.modifiers.get(BUILD_MODIFIER) or obj.modifiers.new(BUILD_MODIFIER, "GREASE_PENCIL_BUILD")
    else:
        modifier = obj.grease_pencil_modifiers.get(BUILD_MODIFIER) or obj.grease_pencil_modifiers.new(
            BUILD_MODIFIER, "GP_BUILD")
    modifier.mode = "SEQUENTIAL"
    modifier.transition = "GROW"
    modifier.time_mode = "FRAMES"
    modifier.start_delay = float(max(0, frame_start - 1))
    modifier.length = float(max(1, frame_end - frame_start))
    return modifier


def plane_of(width_cm, size, canvas):
    """(width, height) metres and the lift of the plane the strokes go on: ``canvas``'s own (its mesh's extent
    in x and y, and a lift above twice its paint thickness) when given, else a canvas ``width_cm`` wide of the
    painting's ``size`` (W, H) px and None."""
    if canvas is not None:
        corners = np.array([tuple(corner) for corner in canvas.bound_box])
        width, height = float(np.ptp(corners[:, 0])), float(np.ptp(corners[:, 1]))
        return (width, height), 2.0 * canvas_plane.canvas_thickness(canvas) + DEFAULT_LIFT
    width = width_cm / 100.0
    return (width, width * size[1] / size[0]), None


def strokes_object(context, folder, drawn, width_cm, thickness, frame_start, frame_end):
    """Make (or update) the Grease Pencil object of painted ``folder`` holding ``drawn`` (its strokes,
    ``core.drawn_strokes``); returns the object.

    It sits on the scene's canvas of ``folder`` when there is one, else at
    the 3D cursor on a plane ``width_cm`` wide; paint ``thickness`` metres
    thick sets how high above the plane its strokes float. An object of the
    scene made from ``folder`` already is updated in place (its strokes
    replaced). The Build modifier reveals the strokes from ``frame_start`` to
    ``frame_end``.
    """
    import os

    scene = context.scene
    folder = os.path.normpath(bpy.path.abspath(folder))
    canvas = canvas_plane.canvas_for_folder(scene, folder)
    plane, lift = plane_of(width_cm, drawn.size, canvas)
    lift = 2.0 * thickness + DEFAULT_LIFT if lift is None else lift
    obj = next((o for o in stroke_objects(scene) if o.get(canvas_plane.PAINTING_DIR_KEY) == folder), None)
    if obj is None:
        data = _data_collection().new(OBJECT_NAME)
        obj = bpy.data.objects.new(OBJECT_NAME, data)
        obj[canvas_plane.ROLE_KEY] = ROLE
        canvas_plane.link_new_object(context, obj, select=True)
        if canvas is not None:
            obj.parent = canvas
        else:
            obj.location = scene.cursor.location
    data = obj.data
    if MATERIAL_NAME not in [m.name for m in data.materials if m is not None]:
        data.materials.append(_material())
    layer = data.layers.get(LAYER) or data.layers.new(LAYER)
    frame = next((f for f in layer.frames if f.frame_number == 1), None) or layer.frames.new(1)
    write_strokes(frame, drawn, plane, lift)
    obj[canvas_plane.PAINTING_DIR_KEY] = folder
    obj[canvas_plane.MAP_SIZE_KEY] = (int(drawn.size[0]), int(drawn.size[1]))
    obj[PLANE_KEY] = (float(plane[0]), float(plane[1]))
    obj[LIFT_KEY] = float(lift)
    add_build(obj, frame_start, frame_end)
    return obj


def _shown_frame(layer):
    """The layer's keyframe shown at the scene's frame, else its first; or None."""
    frame = layer.current_frame() if hasattr(layer, "current_frame") else getattr(layer, "active_frame", None)
    if frame is None and len(layer.frames):
        frame = layer.frames[0]
    return frame


def paint_frame(obj):
    """The keyframe of the object's ``LAYER`` whose strokes are laid (``_shown_frame``); one at frame 1 when the
    layer or its keyframes are gone."""
    layer = obj.data.layers.get(LAYER) or obj.data.layers.new(LAYER)
    return _shown_frame(layer) or layer.frames.new(1)


def lift_of(obj):
    """Metres the object's strokes float above their plane."""
    return float(obj.get(LIFT_KEY, DEFAULT_LIFT))


def _material_colours(data):
    """(M, 4) float32 linear RGBA: the stroke colour of each of the object data's material slots (white where a
    slot is empty or holds no Grease Pencil material)."""
    colours = [tuple(m.grease_pencil.color) if m is not None and m.grease_pencil is not None else (1, 1, 1, 1)
               for m in data.materials]
    return np.array(colours or [(1.0, 1.0, 1.0, 1.0)], np.float32).reshape(-1, 4)


def _get(collection, name, count, width, dtype=np.float32):
    values = np.empty(count * width, dtype)
    collection.foreach_get(name, values)
    return values.reshape(count, width) if width > 1 else values


def read_arrays(obj):
    """The object's ``LAYER`` strokes (its keyframe at the scene's frame) as arrays, in stroke order:
    (counts (N,), points (P, 3) metres, radius (P,) metres, colour (P, 4) linear RGBA as vertex colours
    give it, opacity (P,), material (N,), index (N,) plus one, 0 for a stroke drawn anew). StrokesError when it
    has no such layer or keyframe."""
    layer = obj.data.layers.get(LAYER)
    frame = _shown_frame(layer) if layer is not None else None
    if frame is None:
        raise StrokesError("The Grease Pencil object {} has no layer {} with strokes to lay: draw the painting's "
                           "strokes in that layer.".format(obj.name, LAYER))
    if is_grease_pencil_3():
        drawing = frame.drawing
        n = len(drawing.strokes)
        offsets = _get(drawing.curve_offsets, "value", n + 1, 1, np.int32)
        total = int(offsets[-1]) if n else 0
        attrs = drawing.attributes

        def attribute(name, key, width, default, dtype=np.float32, domain="POINT"):
            found = attrs.get(name)
            size = total if domain == "POINT" else n
            if found is None or found.domain != domain:
                return np.full((size, width) if width > 1 else size, default, dtype)
            return _get(found.data, key, size, width, dtype)

        return (np.diff(offsets).astype(np.int64), attribute("position", "vector", 3, 0.0),
                attribute("radius", "value", 1, 0.01), attribute("vertex_color", "color", 4, 0.0),
                attribute("opacity", "value", 1, 1.0), attribute("material_index", "value", 1, 0, np.int32, "CURVE"),
                attribute(INDEX_ATTRIBUTE, "value", 1, 0, np.int32, "CURVE"))
    strokes = list(frame.strokes)
    counts = np.array([len(s.points) for s in strokes], np.int64)
    parts = {"co": [], "pressure": [], "vertex_color": [], "strength": []}
    for stroke in strokes:
        k = len(stroke.points)
        for name, width in (("co", 3), ("pressure", 1), ("vertex_color", 4), ("strength", 1)):
            parts[name].append(_get(stroke.points, name, k, width))
    join = lambda name, width: (np.concatenate(parts[name]) if strokes else np.zeros((0, width) if width > 1 else 0,  # noqa: E731
                                                                                     np.float32))
    widths = np.repeat(np.array([s.line_width for s in strokes], np.float32), counts)
    return (counts, join("co", 3), join("pressure", 1) * widths * LEGACY_RADIUS_FACTOR, join("vertex_color", 4),
            join("strength", 1), np.array([s.material_index for s in strokes], np.int32),
            np.array([int(round(s.uv_translation[0])) for s in strokes], np.int32))


def read_drawn(obj, core):
    """The object's strokes as ``core``'s drawn strokes (``DrawnStrokes``), in their order, on the plane the
    object was made on; StrokesError when it is no Grease Pencil object of a painting or has no strokes layer."""
    if obj.get(canvas_plane.ROLE_KEY) != ROLE or PLANE_KEY not in obj or canvas_plane.MAP_SIZE_KEY not in obj:
        raise StrokesError("{} is no Grease Pencil object of a painting: make one with Strokes as Grease "
                           "Pencil.".format(obj.name))
    counts, points, radius, colour, opacity, material, index = read_arrays(obj)
    keep = counts > 0
    starts = np.concatenate(([0], np.cumsum(counts)))
    n = len(counts)
    materials = _material_colours(obj.data)
    mix = colour[:, 3:4]
    slot = np.repeat(np.clip(material, 0, len(materials) - 1), counts)
    seen = materials[slot, :3] * (1.0 - mix) + colour[:, :3] * mix
    per_stroke = np.repeat(np.arange(n), counts)
    sums = np.zeros((n, 5))
    np.add.at(sums, per_stroke, np.concatenate([seen, radius[:, None], opacity[:, None]], axis=1))
    means = sums / np.maximum(counts, 1)[:, None]
    plane = tuple(obj[PLANE_KEY])
    size = tuple(int(v) for v in obj[canvas_plane.MAP_SIZE_KEY])
    chosen = np.concatenate([np.arange(starts[i], starts[i + 1]) for i in np.flatnonzero(keep)]) if keep.any() \
        else np.zeros(0, np.int64)
    index = index.astype(np.int64) - 1
    return core.DrawnStrokes.from_plane(counts[keep], points[chosen], means[keep, 3], means[keep, :3],
                                        means[keep, 4], index[keep], size, plane[0], plane[1])
