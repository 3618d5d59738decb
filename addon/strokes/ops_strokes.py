# SPDX-License-Identifier: GPL-3.0-or-later
"""Operators of the Grease Pencil round trip (``round_trip``): Strokes as Grease Pencil, Lay Grease Pencil Strokes.

Both run whole in ``execute()`` (headless too) and report a problem in one
sentence, returning {'CANCELLED'} with the scene unchanged.
"""

import bpy
from bpy.types import Operator

from .. import dependencies
from ..scene import canvas_plane
from . import grease_pencil, round_trip


def _user_errors():
    from ... import core

    return (core.PaintReliefError, grease_pencil.StrokesError, canvas_plane.CanvasError, ValueError, OSError)


class PAINT_RELIEF_OT_strokes_to_grease_pencil(Operator):
    """Make a Grease Pencil object of the painting's strokes over its canvas, one stroke per stroke in paint order,
    revealed over the scene's frame range by a Build modifier"""

    bl_idname = "paint_relief.strokes_to_grease_pencil"
    bl_label = "Strokes as Grease Pencil"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        settings = getattr(context.scene, "paint_relief", None)
        return settings is not None and bool(settings.painting_dir)

    def execute(self, context):
        missing = dependencies.problem()
        if missing is not None:
            self.report({"ERROR"}, missing)
            return {"CANCELLED"}
        scene = context.scene
        settings = scene.paint_relief
        try:
            obj, count = round_trip.make_strokes(context, settings.painting_dir, settings.canvas_width_cm,
                                                 settings.thickness_mm, scene.frame_start, scene.frame_end)
        except _user_errors() as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        self.report({"INFO"}, "{} holds {} strokes, drawn over frames {} to {}".format(
            obj.name, count, scene.frame_start, scene.frame_end))
        return {"FINISHED"}


class PAINT_RELIEF_OT_lay_grease_pencil(Operator):
    """Lay the strokes of the painting's Grease Pencil object, as they are now (moved, deleted, recoloured, drawn
    anew in its Paint layer), into a new painting, and show it on the canvas"""

    bl_idname = "paint_relief.lay_grease_pencil"
    bl_label = "Lay Grease Pencil Strokes"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return getattr(context.scene, "paint_relief", None) is not None and \
            grease_pencil.active_strokes(context) is not None

    def execute(self, context):
        missing = dependencies.problem()
        if missing is not None:
            self.report({"ERROR"}, missing)
            return {"CANCELLED"}
        obj = grease_pencil.active_strokes(context)
        try:
            report = round_trip.lay_strokes(context, obj)
        except _user_errors() as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        self.report({"INFO"}, "Laid {} strokes into {}".format(report.get("strokes"), report["output_dir"]))
        return {"FINISHED"}


classes = (PAINT_RELIEF_OT_strokes_to_grease_pencil, PAINT_RELIEF_OT_lay_grease_pencil)

register, unregister = bpy.utils.register_classes_factory(classes)
