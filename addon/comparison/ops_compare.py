# SPDX-License-Identifier: GPL-3.0-or-later
"""The ``paint_relief.render_comparison`` operator: the lighting comparison of the scene's canvas.

It renders the canvas under a sweep of the key light (the scene's light
elevation, ``compare_azimuths`` directions), with and without relief
(addon/comparison/compare.py, shared with sample_scenes/compare.py), then has
``core.evaluation.comparison.run_comparison`` compare the renders with the painter's
2-D lighting models. Outputs go to the comparison folder: renders/,
comparison.json, comparison.md, comparison.png, correlation.png,
light_sweep.gif.

Headless (``bpy.app.background``) and from scripts, ``execute()`` does the
whole job. Interactively (``addon/modal_job.py``), one image is rendered per
modal timer step, so the window manager's progress bar and the status bar move between
renders and Esc stops the sweep (the scene is restored either way).
Problems are reported in one sentence, never as a traceback.
"""

import math
import os

import bpy
from bpy.types import Operator

from .. import dependencies, values
from ..modal_job import ModalJob
from ..scene import camera, canvas_plane, lighting
from ..settings import properties
from . import compare

SWEEP_SHARE = 0.9
"""The share of the progress bar the renders fill; comparing them fills the rest."""
# Files of a painted folder the comparison reads.
COMPARISON_MAPS = ("color.exr", "height.exr", "orientation.exr")


class _Job:
    """Everything one comparison run needs, checked before anything is rendered."""

    def __init__(self, canvas_obj, painting_dir, out_dir, azimuths, elevation_deg, samples):
        self.canvas = canvas_obj
        self.painting_dir = painting_dir
        self.out_dir = out_dir
        self.renders_dir = os.path.join(out_dir, "renders")
        self.azimuths = azimuths
        self.elevation_deg = elevation_deg
        self.samples = samples


def _writable(folder):
    """Create ``folder`` and check a file can be written there; ValueError (one sentence) otherwise."""
    try:
        os.makedirs(folder, exist_ok=True)
        probe = os.path.join(folder, ".paint-relief-probe-{}".format(os.getpid()))
        with open(probe, "wb"):
            pass
        os.remove(probe)
    except OSError as error:
        raise ValueError("Cannot write to the comparison folder {}: {}.".format(
            folder, (error.strerror or str(error)).lower())) from None


def prepare(context):
    """Check the scene and settings, frame the camera and make sure a key light exists; return a _Job.

    Raises ValueError or compare.SweepError with one sentence. The painter's
    libraries are checked first, so nothing is rendered when one is missing.
    """
    missing = dependencies.problem()
    if missing is not None:
        raise ValueError(missing)
    scene = context.scene
    settings = scene.paint_relief
    canvas_obj = canvas_plane.find_role(scene, "canvas")
    if canvas_obj is None:
        raise compare.SweepError("The scene has no Paint Relief canvas: build the canvas first.")
    if canvas_plane.MAP_SIZE_KEY not in canvas_obj:
        raise compare.SweepError("Canvas {} has no map size: build the canvas again.".format(canvas_obj.name))
    painting_dir = (canvas_obj.get(canvas_plane.PAINTING_DIR_KEY)
                    or os.path.normpath(bpy.path.abspath(settings.painting_dir)))
    for name in COMPARISON_MAPS:
        path = os.path.join(painting_dir, name)
        if not os.path.isfile(path):
            raise ValueError("Painted map {} does not exist; the comparison needs the folder the canvas was "
                             "built from.".format(path))
    out_dir = properties.comparison_dir(context, painting_dir)
    _writable(out_dir)
    azimuths = values.sweep_azimuths(settings.compare_azimuths)
    values.check_render_names(azimuths)
    camera.frame_canvas(context, canvas_obj)
    if canvas_plane.find_role(scene, "key_light") is None:
        lighting.add_lights(context, settings.light_azimuth, settings.light_elevation, settings.light_strength,
                            settings.fill_light)
    return _Job(canvas_obj, painting_dir, out_dir, azimuths, math.degrees(settings.light_elevation),
                settings.compare_samples)


def finish(job, progress=None):
    """Compare the renders of ``job`` with the 2-D models; return the comparison's dict."""
    from ... import core

    return compare.compare(core, job.painting_dir, job.renders_dir, job.azimuths, job.elevation_deg, job.out_dir,
                           relief_px=compare.relief_pixels(job.canvas), progress=progress)


def _message(error, doing):
    """One line for an exception: the sentence our own errors carry, else what was being done."""
    from ... import core

    if isinstance(error, (compare.SweepError, canvas_plane.CanvasError, core.PaintReliefError, ValueError)):
        return " ".join(str(error).split())
    return "{} failed: {}".format(doing, " ".join(str(error).split()) or type(error).__name__)


def _summary(job, result):
    best = result.get("best_azimuth_deg")
    text = "Comparison of {} light directions written to {}".format(len(job.azimuths), job.out_dir)
    if best is not None:
        text += "; the paper's lighting matches best at {:g} degrees (r = {:+.2f})".format(
            best, result.get("best_pearson", float("nan")))
    return text


class PAINT_RELIEF_OT_render_comparison(ModalJob, Operator):
    """Render the canvas under a sweep of key light directions with and without relief, and compare the renders
    with the painter's 2-D lighting (figures, charts and an animated sweep)"""

    bl_idname = "paint_relief.render_comparison"
    bl_label = "Render Comparison"
    bl_options = {"REGISTER"}
    timer_interval = 0.05  # one render per timer event

    @classmethod
    def poll(cls, context):
        return (getattr(context.scene, "paint_relief", None) is not None
                and canvas_plane.find_role(context.scene, "canvas") is not None)

    def execute(self, context):
        try:
            job = prepare(context)
            compare.render_sweep(context, job.canvas, job.azimuths, job.elevation_deg, job.renders_dir, job.samples)
            result = finish(job)
        except Exception as error:  # every failure reaches the user as one line
            self.report({"ERROR"}, _message(error, "Rendering the comparison"))
            return {"CANCELLED"}
        self.report({"INFO"}, _summary(job, result))
        return {"FINISHED"}

    def begin_modal(self, context):
        """Check, then start the timer that renders one image of the sweep per event."""
        try:
            self._job = prepare(context)
            self._steps = compare.sweep_steps(context, self._job.canvas, self._job.azimuths, self._job.elevation_deg,
                                              self._job.renders_dir, self._job.samples)
        except Exception as error:
            self.report({"ERROR"}, _message(error, "Preparing the comparison"))
            return {"CANCELLED"}
        self.start_timer(context)
        context.workspace.status_text_set("Paint Relief: preparing the light sweep (Esc to cancel)")
        return {"RUNNING_MODAL"}

    def escape(self, context):
        self._steps.close()  # restores the scene
        self.end_modal(context)
        self.report({"WARNING"}, "The comparison was cancelled; the renders made so far are in {}.".format(
            self._job.renders_dir))
        return {"CANCELLED"}

    def step(self, context):
        try:
            done, total, message = next(self._steps)  # renders the previous step's image
        except StopIteration:
            return self._compare(context)
        except Exception as error:
            self._steps.close()
            return self._fail(context, error, "Rendering the comparison")
        self.show(context, SWEEP_SHARE * done / total, "{} (Esc to cancel)".format(message), percent=False)
        return {"RUNNING_MODAL"}

    def _compare(self, context):
        """All renders are done: compare them (NumPy, a few seconds)."""
        self.show(context, SWEEP_SHARE, "comparing the renders with the 2-D lighting", percent=False)
        try:
            result = finish(self._job)
        except Exception as error:
            return self._fail(context, error, "Comparing the renders")
        self.end_modal(context)
        self.report({"INFO"}, _summary(self._job, result))
        return {"FINISHED"}

    def _fail(self, context, error, doing):
        self.end_modal(context)
        self.report({"ERROR"}, _message(error, doing))
        return {"CANCELLED"}

    def cancel(self, context):
        """Blender ends the operator (e.g. the file closes): stop the sweep and clean up."""
        self._steps.close()
        self.end_modal(context)


classes = (PAINT_RELIEF_OT_render_comparison,)

register, unregister = bpy.utils.register_classes_factory(classes)
