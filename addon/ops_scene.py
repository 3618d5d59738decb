# SPDX-License-Identifier: GPL-3.0-or-later
"""Operators that stage the painting in the scene: canvas, lights, camera.

Each finds the objects it made before (by their role property) and updates
them, so running an operator again never adds a second canvas, light or
camera. Problems are reported in one sentence and the operator returns
{'CANCELLED'} with the scene unchanged.
"""

import bpy
from bpy.types import Operator

from . import canvas, camera, lighting


class PAINT_RELIEF_OT_build_canvas(Operator):
    """Build (or update) a canvas of the chosen physical size from the painted maps, with paint relief"""

    bl_idname = "paint_relief.build_canvas"
    bl_label = "Build Canvas"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        settings = getattr(context.scene, "paint_relief", None)
        return settings is not None and bool(settings.painting_dir)

    def execute(self, context):
        settings = context.scene.paint_relief
        try:
            obj = canvas.build_canvas(context, settings.painting_dir, settings.canvas_width_cm,
                                      settings.thickness_mm, settings.displacement_method)
        except canvas.CanvasError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        except Exception as error:  # an unexpected failure still reaches the user as one line
            self.report({"ERROR"}, "Building the canvas from {} failed: {}".format(settings.painting_dir, error))
            return {"CANCELLED"}
        self.report({"INFO"}, "Canvas {} is {:.1f} x {:.1f} cm".format(
            obj.name, 100 * obj.dimensions[0], 100 * obj.dimensions[1]))
        return {"FINISHED"}


class PAINT_RELIEF_OT_add_lights(Operator):
    """Add (or update) a raking key light, an optional soft fill light and a dim world background"""

    bl_idname = "paint_relief.add_lights"
    bl_label = "Add Lights"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return getattr(context.scene, "paint_relief", None) is not None

    def execute(self, context):
        settings = context.scene.paint_relief
        lighting.add_lights(context, settings.light_azimuth, settings.light_elevation,
                            settings.light_strength, settings.fill_light)
        return {"FINISHED"}


class PAINT_RELIEF_OT_add_camera(Operator):
    """Add (or update) an orthographic camera that frames the canvas exactly, render size = map size"""

    bl_idname = "paint_relief.add_camera"
    bl_label = "Add Camera"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return canvas.find_role(context.scene, "canvas") is not None

    def execute(self, context):
        target = canvas.find_role(context.scene, "canvas")
        if canvas.MAP_SIZE_KEY not in target:
            self.report({"ERROR"}, "Canvas {} has no map size: build the canvas again.".format(target.name))
            return {"CANCELLED"}
        camera.frame_canvas(context, target)
        return {"FINISHED"}


classes = (PAINT_RELIEF_OT_build_canvas, PAINT_RELIEF_OT_add_lights, PAINT_RELIEF_OT_add_camera)

register, unregister = bpy.utils.register_classes_factory(classes)
