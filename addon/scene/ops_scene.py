# SPDX-License-Identifier: GPL-3.0-or-later
"""Operators that stage the painting in the scene: canvas, lights, camera.

Build Canvas makes a new canvas for a painting no canvas of the scene shows
yet, and rebuilds in place the canvas that shows it otherwise; on a folder
holding a painted sequence it builds the animated canvas (``animated``), whose
maps follow the scene's frame. Reload Maps reads the active canvas's maps
again (a sequence's frames painted since included). Lights and
camera are found again by their role property and updated, so running those
again never adds a second light or camera. Problems are reported in one sentence and the operator returns
{'CANCELLED'} with the scene unchanged.
"""

import bpy
from bpy.props import BoolProperty, StringProperty
from bpy.types import Operator

from . import animated, camera, canvas_plane, lighting


class _CanvasOperator:
    """What the operators that change the scene's canvas share: undoable, available when the scene has one."""

    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return canvas_plane.find_role(context.scene, "canvas") is not None


class PAINT_RELIEF_OT_build_canvas(Operator):
    """Build (or update) a canvas of the chosen physical size from the painted maps, with paint relief; an animated
    canvas, whose maps follow the scene's frame, from a painted sequence"""

    bl_idname = "paint_relief.build_canvas"
    bl_label = "Build Canvas"
    bl_options = {"REGISTER", "UNDO"}

    frame_range: BoolProperty(
        name="Set Frame Range",
        description="For a painted sequence, also set the scene's frame range to the sequence's frames",
        default=False)

    @classmethod
    def poll(cls, context):
        settings = getattr(context.scene, "paint_relief", None)
        return settings is not None and bool(settings.painting_dir)

    def execute(self, context):
        settings = context.scene.paint_relief
        sequence = animated.is_sequence_folder(settings.painting_dir)
        try:
            if sequence:
                obj = animated.build_animated_canvas(context, settings.painting_dir, settings.canvas_width_cm,
                                                     settings.thickness_mm, settings.displacement_method,
                                                     frame_range=self.frame_range)
            else:
                obj = canvas_plane.build_canvas(context, settings.painting_dir, settings.canvas_width_cm,
                                                settings.thickness_mm, settings.displacement_method)
        except canvas_plane.CanvasError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        except Exception as error:  # an unexpected failure still reaches the user as one line
            self.report({"ERROR"}, "Building the canvas from {} failed: {}".format(settings.painting_dir, error))
            return {"CANCELLED"}
        frames = ""
        if sequence:
            first, count = (int(v) for v in obj[animated.SEQUENCE_KEY])
            frames = ", frames {} to {}".format(first, first + count - 1)
        self.report({"INFO"}, "Canvas {} is {:.1f} x {:.1f} cm{}".format(
            obj.name, 100 * obj.dimensions[0], 100 * obj.dimensions[1], frames))
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


class PAINT_RELIEF_OT_add_camera(_CanvasOperator, Operator):
    """Add (or update) an orthographic camera that frames the canvas exactly, render size = map size"""

    bl_idname = "paint_relief.add_camera"
    bl_label = "Add Camera"

    def execute(self, context):
        target = canvas_plane.find_role(context.scene, "canvas")
        if canvas_plane.MAP_SIZE_KEY not in target:
            self.report({"ERROR"}, "Canvas {} has no map size: build the canvas again.".format(target.name))
            return {"CANCELLED"}
        settings = context.scene.paint_relief
        camera.frame_canvas(context, target, match_resolution=settings.camera_match_resolution,
                            standard_view=settings.camera_standard_view)
        return {"FINISHED"}


class PAINT_RELIEF_OT_reload_maps(_CanvasOperator, Operator):
    """Read the active canvas's painted maps from disk again (after repainting its folder)"""

    bl_idname = "paint_relief.reload_maps"
    bl_label = "Reload Maps"

    def execute(self, context):
        target = canvas_plane.find_role(context.scene, "canvas")
        try:
            count = (animated.reload_maps if animated.is_animated(target) else canvas_plane.reload_maps)(target)
        except canvas_plane.CanvasError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        self.report({"INFO"}, "Reloaded {} maps of {}".format(count, target.name))
        return {"FINISHED"}


class PAINT_RELIEF_OT_add_canvas(Operator):
    """Add a Paint Relief canvas from a painted folder (color.exr, height.exr, opacity.exr)"""

    bl_idname = "paint_relief.add_canvas"
    bl_label = "Paint Relief Canvas"
    bl_options = {"REGISTER", "UNDO"}

    directory: StringProperty(name="Painted Folder", subtype="DIR_PATH")

    @classmethod
    def poll(cls, context):
        return getattr(context.scene, "paint_relief", None) is not None

    def execute(self, context):
        settings = context.scene.paint_relief
        if self.directory:
            settings.painting_dir = self.directory
        if not settings.painting_dir:
            self.report({"ERROR"}, "Choose a painted folder (one with color.exr, height.exr and opacity.exr).")
            return {"CANCELLED"}
        return bpy.ops.paint_relief.build_canvas()

    def invoke(self, context, event):
        if context.scene.paint_relief.painting_dir:
            return self.execute(context)
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}


def menu_add_canvas(self, context):
    """Add → Paint Relief Canvas in the 3D Viewport's Add menu."""
    self.layout.operator(PAINT_RELIEF_OT_add_canvas.bl_idname, icon="IMAGE_PLANE")


classes = (PAINT_RELIEF_OT_build_canvas, PAINT_RELIEF_OT_add_lights, PAINT_RELIEF_OT_add_camera,
           PAINT_RELIEF_OT_reload_maps, PAINT_RELIEF_OT_add_canvas)

_register, _unregister = bpy.utils.register_classes_factory(classes)


def register():
    _register()
    bpy.types.VIEW3D_MT_add.append(menu_add_canvas)


def unregister():
    bpy.types.VIEW3D_MT_add.remove(menu_add_canvas)
    _unregister()
