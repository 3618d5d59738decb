# SPDX-License-Identifier: GPL-3.0-or-later
"""The ``paint_relief.paint`` operator: paint the chosen photograph into maps.

The work is one call of ``core.paint_file``, which records in strokes.json
what laying each stroke again needs (Lay Grease Pencil Strokes lays them). Headless (``bpy.app.background``)
and from scripts, ``execute()`` runs it synchronously. Interactively, the
same call runs in a worker thread and a modal timer shows its progress in
the window manager's progress bar and the status bar; Esc asks the painter
to stop (``addon/modal_job.py``). The painter is imported only when the
operator runs.
"""

import os

import bpy
from bpy.types import Operator

from .. import dependencies, values
from ..modal_job import Outcome, Worker
from ..settings import properties
from . import jobs


def params_from_settings(settings):
    """Return ``core.Params`` made from the scene settings; raise ValueError with a sentence.

    Imports the painter (core) lazily: call only while an operator runs.
    """
    from ... import core

    sizes = values.parse_sizes(settings.stroke_sizes)
    if settings.brush == "CUSTOM":
        brush = bpy.path.abspath(settings.brush_path) if settings.brush_path else ""
        if not brush:
            raise ValueError("Brush is Custom but no brush image is chosen.")
        if not os.path.isfile(brush):
            raise ValueError("Brush image {} does not exist.".format(brush))
    else:
        brush = settings.brush.lower()
    return core.Params(
        stroke_sizes=sizes,
        detail=float(settings.detail),
        layers=int(settings.layers),
        seed=int(settings.seed),
        brush=brush,
        height_mode=settings.height_mode.lower(),
        method=settings.method.lower(),
        style=settings.style.lower(),
    )


def source_path(settings):
    """Absolute path of the picture to paint (the file, or the chosen .blend image's file); ValueError otherwise."""
    if settings.source == "BLEND_IMAGE":
        image = settings.image
        if image is None:
            raise ValueError("Choose an image of this .blend file to paint.")
        path = os.path.normpath(bpy.path.abspath(image.filepath, library=image.library))
        if image.packed_file is not None and not os.path.isfile(path) or not image.filepath:
            raise ValueError("Image {} has no file on disk (it is packed or generated): unpack or save it "
                             "first.".format(image.name))
    else:
        path = os.path.normpath(bpy.path.abspath(settings.image_path))
    if not os.path.isfile(path):
        raise ValueError("Photograph {} does not exist.".format(path))
    return path


def mask_path(settings):
    """Absolute path of the importance mask, or None; ValueError when it is set but missing."""
    if not settings.mask_path:
        return None
    path = os.path.normpath(bpy.path.abspath(settings.mask_path))
    if not os.path.isfile(path):
        raise ValueError("Importance mask {} does not exist.".format(path))
    return path


def _prepare(operator, context):
    """Check the inputs; return (image_path, output_dir, params, mask) or None after reporting the problem."""
    missing = dependencies.problem()
    if missing is not None:
        operator.report({"ERROR"}, missing)
        return None
    from ... import core

    settings = context.scene.paint_relief
    if jobs.is_running(context.scene):
        operator.report({"ERROR"}, "A painting is already running in scene {}: wait for it to finish or press Esc "
                                   "to cancel it.".format(context.scene.name))
        return None
    try:
        image_path = source_path(settings)
        mask = mask_path(settings)
        params = params_from_settings(settings).validate()
        out_dir = properties.output_dir(context)
        properties.check_output_folder(out_dir)
    except (ValueError, core.PaintReliefError) as error:
        operator.report({"ERROR"}, str(error))
        return None
    return image_path, out_dir, params, mask


def _finish(operator, context, report):
    """Record a finished painting on the settings and tell the user where it went."""
    settings = context.scene.paint_relief
    settings.painting_dir = report["output_dir"]
    operator.report({"INFO"}, "Painted {} strokes into {}".format(report.get("strokes", "the"), report["output_dir"]))


class PAINT_RELIEF_OT_paint(jobs.SceneJob, Operator):
    """Paint the photograph stroke by stroke into colour, height and opacity maps"""

    bl_idname = "paint_relief.paint"
    bl_label = "Paint"
    bl_options = {"REGISTER"}

    @classmethod
    def poll(cls, context):
        settings = getattr(context.scene, "paint_relief", None)
        if settings is None:
            return False
        return bool(settings.image if settings.source == "BLEND_IMAGE" else settings.image_path)

    def execute(self, context):
        started = self._checked_work(context)
        if started is None:
            return {"CANCELLED"}
        outcome = Outcome().run(*started)
        jobs.end(context.scene)
        return self.report_outcome(outcome, lambda report: _finish(self, context, report), False)

    def begin_modal(self, context):
        """Check, then paint in a worker thread while the timer shows its progress."""
        started = self._checked_work(context)
        if started is None:
            return {"CANCELLED"}
        self._scene = context.scene
        self.start_timer(context)
        self._worker = Worker(*started)
        return {"RUNNING_MODAL"}

    def _checked_work(self, context):
        """Check the inputs and record that the scene paints; return (work, failure) or None after reporting
        the problem."""
        from ... import core

        prepared = _prepare(self, context)
        if prepared is None:
            return None
        image_path, out_dir, params, mask = prepared
        frames = int(context.scene.paint_relief.timelapse_frames)
        jobs.begin(context.scene)

        def work(progress, cancel):
            return core.paint_file(image_path, out_dir, params, progress=progress, cancel=cancel, mask_path=mask,
                                   timelapse=frames, strokes_to_lay=True)

        return work, lambda error: "Painting {} failed: {}".format(image_path, error)

    def step(self, context):
        if self.show_worker(context):
            return {"RUNNING_MODAL"}
        self._end(context)
        worker = self._worker
        return self.report_outcome(worker, lambda report: _finish(self, context, report), worker.cancel.is_set())


classes = (PAINT_RELIEF_OT_paint,)

register, unregister = bpy.utils.register_classes_factory(classes)
