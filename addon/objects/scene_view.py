# SPDX-License-Identifier: GPL-3.0-or-later
"""What a scene's camera sees over a frame range: which mesh objects come into its picture, and how large a
pixel of its render is on them, for Paint Scene's one set of stroke widths.

A mesh is seen when its bounding box, carried by its animation, overlaps
the camera's picture in front of the camera in some scanned frame. The
size of a pixel on a surface at depth d (metres along the view axis) is the
picture's width at d over the render's width in pixels: d times the frame's
width at depth 1 for a perspective camera, the orthographic scale for an
orthographic one. The typical depth is the median, over the scanned frames
and the objects seen in each, of the depth of the object's bounding-box
centre: the depth most of the shot looks at.
"""

import numpy as np
from mathutils import Vector

SCANNED_FRAMES = 48
"""At most this many frames, spread evenly over the range, are scanned for what the camera sees."""


def scanned_frames(first, last):
    """The frames (ints, ascending, first and last among them) of ``first``..``last`` that are scanned."""
    count = last - first + 1
    if count <= SCANNED_FRAMES:
        return list(range(first, last + 1))
    return sorted({int(round(f)) for f in np.linspace(first, last, SCANNED_FRAMES)})


def render_size(scene):
    """(width, height) in pixels of ``scene``'s render, its resolution percentage applied."""
    render = scene.render
    scale = render.resolution_percentage / 100.0
    return max(1, int(render.resolution_x * scale)), max(1, int(render.resolution_y * scale))


def _camera_points(scene, camera, obj):
    """(8, 3) the corners of ``obj``'s bounding box in ``camera``'s frame now (x right, y up, -z ahead; metres of
    the world)."""
    to_camera = camera.matrix_world.inverted() @ obj.matrix_world
    return np.array([tuple(to_camera @ Vector(corner)) for corner in obj.bound_box])


def _frame_box(scene, camera):
    """(x0, x1, y0, y1, perspective): the camera's picture at depth 1 (perspective) or its extent
    (orthographic), in the camera's frame."""
    corners = [tuple(v) for v in camera.data.view_frame(scene=scene)]
    xs, ys, zs = zip(*corners, strict=True)
    perspective = camera.data.type != "ORTHO"
    depth = -zs[0] if perspective else 1.0
    return min(xs) / depth, max(xs) / depth, min(ys) / depth, max(ys) / depth, perspective


def _in_picture(points, box, near):
    """Whether the box of ``points`` (8, 3) in the camera's frame overlaps the picture ``box`` in front of the
    camera (beyond ``near`` metres)."""
    x0, x1, y0, y1, perspective = box
    depth = -points[:, 2]
    ahead = depth > near
    if not ahead.any():
        return False
    if perspective and not ahead.all():
        # Corners behind the camera project without meaning: a box reaching behind it is seen when the part
        # ahead of it is (a conservative answer for a ground plane under the camera).
        return True
    if perspective:
        x, y = points[:, 0] / depth, points[:, 1] / depth
    else:
        x, y = points[:, 0], points[:, 1]
    return x.max() >= x0 and x.min() <= x1 and y.max() >= y0 and y.min() <= y1


def seen_meshes(scene, view_layer, frames):
    """The mesh objects of ``view_layer`` shown in renders that ``scene``'s camera sees in any of ``frames``, and
    for each the depths (metres) of its bounding-box centre in the frames it is seen: ({name: [depth, ...]},
    in name order). The scene is left at the frame it was at. ValueError (one sentence) without a camera."""
    camera = scene.camera
    if camera is None:
        raise ValueError("Scene {} has no camera: Paint Scene paints what the camera sees; add one or choose the "
                         "objects and paint the selection.".format(scene.name))
    meshes = sorted((obj for obj in view_layer.objects if obj.type == "MESH" and not obj.hide_render),
                    key=lambda obj: obj.name)
    near = camera.data.clip_start
    depths = {}
    current = scene.frame_current, scene.frame_subframe
    try:
        for frame in frames:
            scene.frame_set(frame)
            box = _frame_box(scene, camera)
            for obj in meshes:
                points = _camera_points(scene, camera, obj)
                if _in_picture(points, box, near):
                    depths.setdefault(obj.name, []).append(max(float(-points[:, 2].mean()), near))
    finally:
        scene.frame_set(current[0], subframe=current[1])
    return {name: depths[name] for name in sorted(depths)}


def pixel_mm(scene, depth):
    """Millimetres a pixel of ``scene``'s render spans on a surface facing the camera at ``depth`` metres."""
    camera = scene.camera
    x0, x1, _, _, perspective = _frame_box(scene, camera)
    width = (x1 - x0) * (depth if perspective else 1.0)
    return 1000.0 * width * scene.unit_settings.scale_length / render_size(scene)[0]


def typical_depth(depths):
    """The median (metres) of every depth of ``depths`` ({name: [depth, ...]}), or None when there is none."""
    found = [d for values in depths.values() for d in values]
    return float(np.median(found)) if found else None
