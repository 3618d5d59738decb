# SPDX-License-Identifier: GPL-3.0-or-later
"""Operators of the Grease Pencil round trip (``round_trip``): Strokes as Grease Pencil, Lay Grease Pencil Strokes.

Strokes as Grease Pencil runs whole in ``execute()``; Lay Grease Pencil
Strokes is a long operator (``jobs.SceneJob``): headless whole, interactively
laying in a worker thread with a progress bar, a status text and Esc. Both
report a problem in one sentence, returning {'CANCELLED'} with the scene
unchanged.
"""

import bpy
from bpy.types import Operator

from .. import dependencies
from ..modal_job import Outcome, Worker
from ..painting import jobs
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


class PAINT_RELIEF_OT_lay_grease_pencil(jobs.SceneJob, Operator):
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
        started = self._checked_work(context)
        if started is None:
            return {"CANCELLED"}
        outcome = Outcome().run(*started, sentences=_user_errors())
        jobs.end(context.scene)
        return self.report_outcome(outcome, lambda report: self._finish(context, report), False)

    def begin_modal(self, context):
        """Read the strokes, then lay them in a worker thread while the timer shows its progress."""
        started = self._checked_work(context)
        if started is None:
            return {"CANCELLED"}
        self._scene = context.scene
        self.start_timer(context)
        self._worker = Worker(*started)
        return {"RUNNING_MODAL"}

    def step(self, context):
        if self.show_worker(context):
            return {"RUNNING_MODAL"}
        self._end(context)
        worker = self._worker
        return self.report_outcome(worker, lambda report: self._finish(context, report), worker.cancel.is_set())

    def _checked_work(self, context):
        """Read the active object's strokes and record that the scene paints; (work, failure), or None after
        reporting the problem."""
        missing = dependencies.problem()
        if missing is not None:
            self.report({"ERROR"}, missing)
            return None
        obj = grease_pencil.active_strokes(context)
        try:
            folder, drawn, out = round_trip.prepare_lay(obj)
            jobs.begin(context.scene)
        except _user_errors() as error:
            self.report({"ERROR"}, str(error))
            return None
        self._object_name, self._folder = obj.name, folder
        return round_trip.lay_work(folder, drawn, out), lambda error: "Laying {}'s strokes failed: {}".format(
            obj.name, error)

    def _finish(self, context, report):
        obj = bpy.data.objects.get(self._object_name)
        if obj is None:
            self.report({"WARNING"}, "{} was removed while its strokes were laid; the painting is in {}".format(
                self._object_name, report["output_dir"]))
            return
        try:
            round_trip.show_laid(context, obj, self._folder, report)
        except _user_errors() as error:
            self.report({"WARNING"}, "The strokes were laid into {}, but {}".format(report["output_dir"], error))
            return
        self.report({"INFO"}, "Laid {} strokes into {}".format(report.get("strokes"), report["output_dir"]))


classes = (PAINT_RELIEF_OT_strokes_to_grease_pencil, PAINT_RELIEF_OT_lay_grease_pencil)

register, unregister = bpy.utils.register_classes_factory(classes)
