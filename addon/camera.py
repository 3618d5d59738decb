# SPDX-License-Identifier: GPL-3.0-or-later
"""An orthographic camera that frames the canvas exactly, and pixel-true colour management.

The render is the painting's map size (times the scene's render percentage),
so each map pixel lands on one render pixel at 100 %; the view transform is
'Standard' with no look, exposure 0 and gamma 1, so renders compare pixel by
pixel with the painter's own images.
"""

import bpy

from .canvas import MAP_SIZE_KEY, ROLE_KEY, find_role

CAMERA_NAME = "Paint Relief Camera"
# Height of the camera above the canvas (metres beyond the canvas's larger side).
CAMERA_CLEARANCE = 1.0


def frame_canvas(context, canvas):
    """Create or update the orthographic camera over ``canvas``; set render size and colour management."""
    scene = context.scene
    width, height = canvas.dimensions[0], canvas.dimensions[1]
    map_w, map_h = (int(v) for v in canvas[MAP_SIZE_KEY])

    obj = find_role(scene, "camera")
    if obj is None or obj.type != "CAMERA":
        if obj is not None:
            bpy.data.objects.remove(obj)
        obj = bpy.data.objects.new(CAMERA_NAME, bpy.data.cameras.new(CAMERA_NAME))
        obj[ROLE_KEY] = "camera"
        scene.collection.objects.link(obj)
    larger = max(width, height)
    camera = obj.data
    camera.type = "ORTHO"
    camera.ortho_scale = larger
    camera.sensor_fit = "HORIZONTAL" if map_w >= map_h else "VERTICAL"
    camera.shift_x = camera.shift_y = 0.0
    camera.clip_start = 0.01
    camera.clip_end = larger + 2.0 * CAMERA_CLEARANCE
    # A camera looks along its local -z with +y up: unrotated, it looks straight down at the canvas.
    obj.rotation_mode = "XYZ"
    obj.rotation_euler = (0.0, 0.0, 0.0)
    obj.location = (canvas.location.x, canvas.location.y, canvas.location.z + larger + CAMERA_CLEARANCE)
    scene.camera = obj

    render = scene.render
    render.resolution_x, render.resolution_y = map_w, map_h
    render.pixel_aspect_x = render.pixel_aspect_y = 1.0
    view = scene.view_settings
    view.view_transform = "Standard"
    view.look = "None"
    view.exposure = 0.0
    view.gamma = 1.0
    return obj
