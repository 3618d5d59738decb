# SPDX-License-Identifier: GPL-3.0-or-later
"""The ``paint_relief.paint_animation`` operator: paint an image sequence, or the scene's animation, into
one folder of painted frames whose strokes live across frames.

The work is a ``ShotJob``: for the scene's animation, first its frames
rendered one by one (``scene_render.RenderedFrames``) into ``scene_render/``
inside the output folder; then one call of ``core.paint_sequence_files``,
which commits every painted frame whole and goes on after the last complete
frame when run again into the same folder. The rendered frames stay until
the last frame is painted, so a stopped run goes on with the same footage.

Headless (``bpy.app.background``) and from scripts, ``execute()`` does the
whole job. Interactively (``addon/modal_job.py``), one frame is rendered per timer event
(each render blocks Blender for that frame; between frames Blender redraws
and reads Esc), then paints in a worker thread while a timer shows the
progress (frame k of n and the stage within the frame) in the progress bar
and the status bar. Esc stops after the frame being rendered, or between the
painter's stages; complete frames stay.
"""

import os
import shutil
import threading

import bpy
from bpy.types import Operator

from .. import dependencies, values
from ..modal_job import ModalJob, Outcome, Worker
from ..settings import properties
from . import jobs, scene_render, shot_source
from .ops_paint import params_from_settings


class ShotJob:
    """One Paint Animation: what it paints, where, and how.

    inputs: the painter's ``inputs`` (files in order, or one folder or
    pattern); for the scene, ``frames`` renders them first. output_dir: the
    absolute folder of painted frames; key: ``shot_source.source_key``.
    """

    def __init__(self, scene, inputs, frames, output_dir, params, sequence_settings, key):
        self.scene_name = scene.name
        self.inputs = inputs
        self.frames = frames
        self.output_dir = output_dir
        self.params = params
        self.sequence_settings = sequence_settings
        self.key = key

    def paint(self, progress=None, cancel=None):
        """Paint the frames (``core.paint_sequence_files``); return the sequence's report. Raises
        core.Cancelled when ``cancel()`` turned True (complete frames stay) and core.PaintReliefError."""
        from ... import core

        inputs = self.frames.paths if self.frames is not None else self.inputs
        return core.paint_sequence_files(inputs, self.output_dir, self.params, self.sequence_settings,
                                         progress=progress, cancel=cancel)

    def finish(self, report):
        """After a run: remove the scene's rendered frames when every frame is painted."""
        if self.frames is not None and report.get("complete"):
            shutil.rmtree(self.frames.folder, ignore_errors=True)

    def fraction(self, painted=0.0):
        """The whole job's progress in [0, 1], ``painted`` being the painter's own."""
        if self.frames is None:
            return painted
        return values.render_progress(self.frames.done, len(self.frames.numbers), painted)


def prepare(context):
    """Check the chosen source, settings and folder; return an ShotJob. ValueError or
    core.PaintReliefError (one sentence each) when something is missing or wrong (the Paint panel's method is
    Hertzmann 1998: shots are painted with the paper's method). Renders nothing yet."""
    from ... import core

    missing = dependencies.problem()
    if missing is not None:
        raise ValueError(missing)
    scene = context.scene
    settings = scene.paint_relief
    if jobs.is_running(scene):
        raise ValueError("A painting is already running in scene {}: wait for it to finish or press Esc to "
                         "cancel it.".format(scene.name))
    params = params_from_settings(settings).validate_shot()  # the paper's method: Hertzmann 1998 paints stills
    sequence_settings = core.SequenceSettings(fade_frames=int(settings.animation_fade_frames)).validate()
    view_layer = context.view_layer
    scene_source = settings.animation_source == "SCENE"
    if scene_source:
        if scene.camera is None:
            raise ValueError("Scene {} has no active camera to render its animation with.".format(scene.name))
        inputs = None
    else:
        inputs = shot_source.sequence_inputs(settings)
    key = shot_source.source_key(settings, scene, view_layer, params)
    output_dir = properties.animation_output_dir(context, key, shot_source.source_name(settings, scene))
    properties.check_output_folder(output_dir)
    state = values.sequence_folder_state(output_dir)
    if state == "still":
        raise ValueError("The output folder {} holds a still painting: choose another folder for the "
                         "animation.".format(output_dir))
    frames = None
    if scene_source:
        frames = scene_render.RenderedFrames(scene, view_layer, os.path.join(output_dir, scene_render.RENDER_FOLDER))
        if state == "complete":
            raise ValueError("The output folder {} holds a complete painted animation: choose another folder, or "
                             "leave Output Folder empty for a new one.".format(output_dir))
        painted_from = values.sequence_folder_inputs(output_dir)
        if state == "unfinished" and painted_from is not None and _rendered_names(painted_from) != \
                _rendered_names(frames.paths):
            raise ValueError("The output folder {} holds frames painted from other footage than scene {}'s frames "
                             "{} to {}: choose another folder.".format(output_dir, scene.name, frames.numbers[0],
                                                                      frames.numbers[-1]))
    return ShotJob(scene, inputs, frames, output_dir, params, sequence_settings, key)


def _rendered_names(paths):
    """``scene_render/frame_0001.exr``, ... of input paths (the folder they sit in may have moved since)."""
    return [os.path.join(os.path.basename(os.path.dirname(path)), os.path.basename(path)) for path in paths]


def _start(context, job):
    """Record the job's folder on the scene's settings (so that a stopped run is taken up again)."""
    settings = context.scene.paint_relief
    settings.animation_dir = job.output_dir
    settings.animation_key = job.key


def _finish(operator, context, job, report):
    """Tell the user where the painted frames went; a complete sequence becomes the painting the canvas shows."""
    job.finish(report)
    settings = context.scene.paint_relief
    settings.animation_dir = report["output_dir"]
    if report.get("complete"):
        settings.painting_dir = report["output_dir"]
        settings.animation_key = ""  # nothing left to go on with: the next run gets a folder of its own
    operator.report({"INFO"}, "Painted {} frames ({}) into {}".format(
        len(report.get("frames", ())), report.get("motion", "motion"), report["output_dir"]))


def _render_and_paint(job):
    """The whole job at once: the scene's frames rendered (when it paints the scene), then painted; returns the
    painter's report."""
    if job.frames is not None:
        try:
            while job.frames.render_next():
                pass
        finally:
            job.frames.close()
    return job.paint()


def _failure(error, job):
    """The one line for an unexpected failure."""
    return "Paint Animation into {} failed: {}".format(job.output_dir, error)


class PAINT_RELIEF_OT_paint_animation(ModalJob, Operator):
    """Paint an image sequence, or render the scene's animation and paint it, with strokes that follow the \
motion from frame to frame"""

    bl_idname = "paint_relief.paint_animation"
    bl_label = "Paint Animation"
    bl_options = {"REGISTER"}
    status_title = "Paint Animation"

    @classmethod
    def poll(cls, context):
        settings = getattr(context.scene, "paint_relief", None)
        if settings is None:
            return False
        return {"SCENE": lambda: True,  # a scene without a camera is refused with a sentence saying so
                "IMAGE": lambda: settings.animation_image is not None,
                "FOLDER": lambda: bool(settings.animation_folder),
                "PATTERN": lambda: bool(settings.animation_pattern)}[settings.animation_source]()

    def _prepared(self, context):
        from ... import core

        try:
            return prepare(context)
        except (ValueError, core.PaintReliefError) as error:
            self.report({"ERROR"}, str(error))
            return None

    def execute(self, context):
        job = self._prepared(context)
        if job is None:
            return {"CANCELLED"}
        jobs.begin(context.scene)
        _start(context, job)
        outcome = Outcome().run(lambda progress, cancel: _render_and_paint(job), lambda error: _failure(error, job),
                                sentences=(RuntimeError, ValueError))
        jobs.end(context.scene)
        return self.report_outcome(outcome, lambda report: _finish(self, context, job, report), outcome.stopped)

    def begin_modal(self, context):
        """Check, then start the timer that renders frame by frame and watches the painting."""
        job = self._prepared(context)
        if job is None:
            return {"CANCELLED"}
        self._job_key = jobs.begin(context.scene)
        _start(context, job)
        self._job = job
        self._cancel = threading.Event()
        self._worker = None
        self.start_timer(context)
        if job.frames is None or job.frames.next_number() is None:
            self._start_painting()
        else:
            self.show(context, job.fraction(), self._render_text(job.frames))
        return {"RUNNING_MODAL"}

    @staticmethod
    def _render_text(frames):
        number = frames.next_number()
        return "rendering frame {} ({}/{}); Esc stops after it".format(
            number, frames.numbers.index(number) + 1, len(frames.numbers))

    def _start_painting(self):
        job = self._job
        if job.frames is not None:
            job.frames.close()

        def work(progress, cancel):
            return job.paint(progress=lambda fraction, message: progress(job.fraction(fraction), message),
                             cancel=cancel)

        self._worker = Worker(work, lambda error: _failure(error, job), name="paint_relief_animation",
                              cancel=self._cancel)

    def escape(self, context):
        self._cancel.set()
        return {"RUNNING_MODAL"}

    def step(self, context):
        if self._worker is None:
            return self._render_step(context)
        return self._paint_step(context)

    def _render_step(self, context):
        """One timer event of the render: stop when asked, else render the next frame (blocking)."""
        frames = self._job.frames
        if self._cancel.is_set():
            done, count = frames.done, len(frames.numbers)
            self._end(context)
            self.report({"WARNING"}, "Rendering stopped after {} of {} frames; they are kept in {}, and Paint "
                                     "Animation into {} goes on from there.".format(done, count, frames.folder,
                                                                                   self._job.output_dir))
            return {"CANCELLED"}
        try:
            frames.render_next()
        except (RuntimeError, OSError, ValueError) as error:
            self._end(context)
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        if frames.next_number() is None:
            self._start_painting()
            self.show(context, self._job.fraction(), "painting")
        else:
            self.show(context, self._job.fraction(), self._render_text(frames))
        return {"RUNNING_MODAL"}

    def _paint_step(self, context):
        worker = self._worker
        if worker.is_alive():
            text = "{} (Esc to cancel)".format(worker.message)
            if worker.cancel.is_set():
                text = "cancelling after the painter's current stage..."
            self.show(context, worker.fraction, text)
            return {"RUNNING_MODAL"}
        self._end(context)
        return self.report_outcome(worker, lambda report: _finish(self, context, self._job, report), worker.stopped)

    def cancel(self, context):
        """Blender ends the operator (another file is opened, or Blender quits): stop the worker, clean up."""
        self._cancel.set()
        if self._worker is not None:
            self._worker.stop()
        self._end(context, closing=True)

    def _end(self, context, closing=False):
        if self._job.frames is not None:
            self._job.frames.close(restore_frame=not closing)
        jobs.end(self._job_key)
        self.end_modal(context)


classes = (PAINT_RELIEF_OT_paint_animation,)

register, unregister = bpy.utils.register_classes_factory(classes)
