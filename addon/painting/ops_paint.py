# SPDX-License-Identifier: GPL-3.0-or-later
"""The ``paint_relief.paint`` operator: paint the chosen photograph into maps.

The work is one call of ``core.paint_file``. Headless (``bpy.app.background``)
and from scripts, ``execute()`` runs it synchronously. Interactively,
``invoke()`` runs the same call in a worker thread and a modal timer shows its
progress in the window manager's progress bar and the status bar; Esc asks
the painter to stop (its cancel callback reads a ``threading.Event``). The
painter is imported only when the operator runs.
"""

import os
import threading

import bpy
from bpy.types import Operator

from .. import dependencies, values
from ..settings import properties
from . import jobs

# Seconds between the modal operator's progress updates.
TIMER_INTERVAL = 0.1


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


class PAINT_RELIEF_OT_paint(Operator):
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
        from ... import core

        prepared = _prepare(self, context)
        if prepared is None:
            return {"CANCELLED"}
        image_path, out_dir, params, mask = prepared
        jobs.begin(context.scene)
        try:
            report = core.paint_file(image_path, out_dir, params, mask_path=mask)
        except core.PaintReliefError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        except Exception as error:  # an unexpected failure still reaches the user as one line
            self.report({"ERROR"}, "Painting {} failed: {}".format(image_path, error))
            return {"CANCELLED"}
        finally:
            jobs.end(context.scene)
        _finish(self, context, report)
        return {"FINISHED"}

    def invoke(self, context, event):
        if bpy.app.background:
            return self.execute(context)
        prepared = _prepare(self, context)
        if prepared is None:
            return {"CANCELLED"}
        image_path, out_dir, params, mask = prepared
        jobs.begin(context.scene)
        self._scene = context.scene

        self._cancel = threading.Event()
        self._state = {"fraction": 0.0, "message": "Starting", "report": None, "error": None}
        self._thread = threading.Thread(
            target=self._work, args=(image_path, out_dir, params, mask), name="paint_relief", daemon=True)
        wm = context.window_manager
        self._timer = wm.event_timer_add(TIMER_INTERVAL, window=context.window)
        wm.progress_begin(0, 100)
        wm.modal_handler_add(self)
        self._thread.start()
        return {"RUNNING_MODAL"}

    def _work(self, image_path, out_dir, params, mask):
        """Worker thread: the painter only; never touches bpy data."""
        from ... import core

        state = self._state

        def progress(fraction, message):
            state["fraction"], state["message"] = fraction, message

        try:
            state["report"] = core.paint_file(image_path, out_dir, params,
                                              progress=progress, cancel=self._cancel.is_set,
                                              mask_path=mask)
        except core.PaintReliefError as error:
            state["error"] = str(error)
        except Exception as error:
            state["error"] = "Painting {} failed: {}".format(image_path, error)

    def modal(self, context, event):
        if event.type == "ESC":
            self._cancel.set()
            return {"RUNNING_MODAL"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}

        state = self._state
        if self._thread.is_alive():
            context.window_manager.progress_update(int(100 * state["fraction"]))
            text = "Paint Relief: {:.0f}% {} (Esc to cancel)".format(100 * state["fraction"], state["message"])
            if self._cancel.is_set():
                text = "Paint Relief: cancelling..."
            context.workspace.status_text_set(text)
            return {"RUNNING_MODAL"}

        self._end(context)
        if state["error"] is not None:
            level = {"WARNING"} if self._cancel.is_set() else {"ERROR"}
            self.report(level, state["error"])
            return {"CANCELLED"}
        _finish(self, context, state["report"])
        return {"FINISHED"}

    def cancel(self, context):
        """Blender ends the operator (e.g. the file closes): stop the worker and clean up."""
        self._cancel.set()
        self._thread.join()
        self._end(context)

    def _end(self, context):
        jobs.end(self._scene)
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        context.workspace.status_text_set(None)


classes = (PAINT_RELIEF_OT_paint,)

register, unregister = bpy.utils.register_classes_factory(classes)
