# SPDX-License-Identifier: GPL-3.0-or-later
"""An orthographic camera that frames the canvas exactly; render size and colour management on request.

The camera looks straight at the canvas's front, following the canvas's
location and rotation. On request (``match_resolution``) the render is the
painting's map size, so each map pixel lands on one render pixel at 100 %;
on request (``standard_view``) the view transform is 'Standard' with no
look, exposure 0 and gamma 1, so renders compare pixel by pixel with the
painter's own images. Without those requests the scene's render size and
colour management (AgX, Filmic, a look...) stay as the user set them.
"""

import bpy
from mathutils import Vector

from .canvas_plane import MAP_SIZE_KEY, ROLE_KEY, find_role, link_new_object

CAMERA_NAME = "Paint Relief Camera"
# Height of the camera above the canvas (metres beyond the canvas's larger side).
CAMERA_CLEARANCE = 1.0


def frame_canvas(context, canvas, match_resolution=False, standard_view=False):
    """Create or update the orthographic camera over ``canvas`` and make it the scene's camera; return it.

    match_resolution: set the render size to the map size; standard_view:
    set 'Standard' colour management. Otherwise neither is touched.
    """
    scene = context.scene
    width, height = canvas.dimensions[0], canvas.dimensions[1]
    map_w, map_h = (int(v) for v in canvas[MAP_SIZE_KEY])

    obj = find_role(scene, "camera")
    if obj is None or obj.type != "CAMERA":
        if obj is not None:
            bpy.data.objects.remove(obj)
        obj = bpy.data.objects.new(CAMERA_NAME, bpy.data.cameras.new(CAMERA_NAME))
        obj[ROLE_KEY] = "camera"
        link_new_object(context, obj)
    larger = max(width, height)
    camera = obj.data
    camera.type = "ORTHO"
    camera.ortho_scale = larger
    camera.sensor_fit = "HORIZONTAL" if map_w >= map_h else "VERTICAL"
    camera.shift_x = camera.shift_y = 0.0
    camera.clip_start = 0.01
    camera.clip_end = larger + 2.0 * CAMERA_CLEARANCE
    # A camera looks along its local -z with +y up: turned as the canvas, it looks straight at its front.
    turn = canvas.matrix_world.to_quaternion()
    obj.rotation_mode = "QUATERNION"
    obj.rotation_quaternion = turn
    obj.location = canvas.matrix_world.translation + turn @ Vector((0.0, 0.0, larger + CAMERA_CLEARANCE))
    scene.camera = obj

    if match_resolution:
        render = scene.render
        render.resolution_x, render.resolution_y = map_w, map_h
        render.pixel_aspect_x = render.pixel_aspect_y = 1.0
    if standard_view:
        view = scene.view_settings
        view.view_transform = "Standard"
        view.look = "None"
        view.exposure = 0.0
        view.gamma = 1.0
    return obj
