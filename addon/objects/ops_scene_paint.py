# SPDX-License-Identifier: GPL-3.0-or-later
"""Paint Scene: paint the texture of every mesh object the scene's camera sees over the frame range (or of the
selected ones), each by Paint Object's rules, with one set of stroke widths in millimetres for the whole scene.

The widths are Paint Object's Stroke Widths when set; else they are read
from the camera (``scene_view``): the widths a still of the scene's render
is painted with, in pixels, times the size of a pixel at the typical depth
of the shot, so that strokes at that depth show on screen as wide as on a
painted render of the scene. Objects wearing the same pictures are painted
as one texture (``scene_jobs``). Each object's sources are gathered on the
main thread, one object per timer event with its name in the status text
(its bake may take a while); then every texture is painted in one call of
``core.paint_objects``, side by side on the machine's cores (or on the Dask
cluster of ``FARM``), in a worker thread with the progress bar and Esc; then each object gets its painted
material and relief as Paint Object gives them. Painting again into the
same folder keeps every texture whose painting is there already, from the
same sources, mesh and settings, and paints only what is missing or
changed. An object that cannot be painted is named in one sentence in the
report (and in ``paint_scene.json`` of the folder); the others are painted.
"""

import contextlib
import json
import os
import shutil
import tempfile
import time

import bpy
from bpy.types import Operator

from .. import dependencies, values
from ..modal_job import Outcome, Worker
from ..painting import jobs
from ..scene.maps import CanvasError
from ..settings import properties
from . import object_material, scene_jobs, scene_view, surface
from .ops_object import gather, object_params

WIDTH_DECIMALS = 2
"""The camera's stroke widths are rounded to hundredths of a millimetre, so that a painted scene, whose relief
moves its objects' boxes by a hair, reads the same widths again and keeps its paintings."""
REPORT_FILE = "paint_scene.json"
"""The file in the scene's folder that says what the last Paint Scene painted, kept, and could not paint."""
FARM = None
"""The ``core.farm.cluster.Farm`` (local Dask workers or a scheduler's address) Paint Scene paints its textures on,
or None to paint them on this machine's cores. The panel leaves it None; a headless script sets it
(``sample_scenes/paint_scene.py --workers N``)."""


def scene_output_dir(context):
    """The folder Paint Scene paints ``context.scene`` into: the Scene Folder when set, else ``<scene> scene``
    where paintings go (the same folder every time, so painting again goes on with it)."""
    settings = context.scene.paint_relief
    if settings.scene_output_dir:
        return os.path.normpath(bpy.path.abspath(settings.scene_output_dir))
    return os.path.join(properties.paintings_parent(context),
                        scene_jobs.folder_name("{} scene".format(context.scene.name), set()))


def scene_targets(context, selected_only):
    """(names, depths): the mesh objects to paint (names in name order: the selected meshes with
    ``selected_only``, else those the camera sees over the frame range) and the depths the camera sees each at
    (``scene_view.seen_meshes``; empty without a camera when painting the selection). ValueError (one
    sentence) when there is nothing to paint."""
    scene = context.scene
    frames = scene_view.scanned_frames(scene.frame_start, scene.frame_end)
    with contextlib.ExitStack() as originals:     # the objects' boxes without the relief of an earlier painting
        for obj in context.view_layer.objects:
            if obj.type == "MESH":
                originals.enter_context(object_material.original_shown(obj))
        depths = {} if selected_only and scene.camera is None else scene_view.seen_meshes(
            scene, context.view_layer, frames)
    if selected_only:
        names = sorted(obj.name for obj in context.selected_objects if obj.type == "MESH")
        if not names:
            raise ValueError("No mesh object is selected: select the objects to paint, or clear Selected Only to "
                             "paint what the camera sees.")
        return names, {name: depths[name] for name in names if name in depths}
    if not depths:
        raise ValueError("The camera {} of scene {} sees no mesh object over frames {} to {}: nothing to "
                         "paint.".format(scene.camera.name, scene.name, scene.frame_start, scene.frame_end))
    return list(depths), depths


def scene_stroke_mm(context, params, depths):
    """(stroke widths in mm, descending; {"chosen_by", "typical_depth_m", "pixel_mm", "render_px"}): Paint
    Object's Stroke Widths when set, else the camera's (module docstring). ValueError (one sentence) when
    neither can be had."""
    from ... import core

    scene, settings = context.scene, context.scene.paint_relief
    widths = values.parse_widths(settings.object_stroke_mm)
    if widths is not None:
        return widths, {"chosen_by": "Stroke Widths"}
    depth = scene_view.typical_depth(depths)
    if depth is None:
        raise ValueError("The camera of scene {} sees none of the objects to paint, so it cannot size their "
                         "strokes: give Stroke Widths in millimetres.".format(scene.name))
    width, height = scene_view.render_size(scene)
    pixel = scene_view.pixel_mm(scene, depth)
    widths = tuple(round(width_mm, WIDTH_DECIMALS) for width_mm in core.screen_stroke_mm(params, width, height, pixel))
    return widths, {
        "chosen_by": "camera", "camera": scene.camera.name, "typical_depth_m": depth, "pixel_mm": pixel,
        "render_px": [width, height]}


class ScenePaint:
    """One Paint Scene run: what it paints, where, and what it has gathered so far."""

    def __init__(self, context, names, depths, selected_only, size):
        from ... import core

        settings = context.scene.paint_relief
        self.started = time.perf_counter()
        self.seconds = {}
        self.names, self.index = names, 0
        self.params = object_params(settings)
        self.size = size if size > 0 else int(settings.object_texture_size)
        self.stroke_mm, self.how = scene_stroke_mm(context, self.params, depths)
        self.folder = scene_output_dir(context)
        properties.check_output_folder(self.folder)
        self.normal_map = settings.object_relief == "NORMAL_MAP"
        self.selected_only = selected_only
        self.gathered, self.refused, self.paintings = [], {}, []
        self.scratch = tempfile.mkdtemp(prefix="paint_relief_scene_")
        self.core = core
        self.stopped = "Paint Scene was stopped: the textures painted so far are kept in {}, and painting again " \
                       "goes on with the others.".format(self.folder)

    def gather_next(self, context):
        """Gather the sources and triangles of the next object (or name in ``refused`` why it cannot be
        painted); return False once every object is gathered."""
        if self.index >= len(self.names):
            return False
        name = self.names[self.index]
        self.index += 1
        obj = context.scene.objects.get(name)
        problem = surface.mesh_problem(obj, context)
        if problem is not None:
            self.refused[name] = problem
            return True
        scratch = os.path.join(self.scratch, str(self.index))
        os.makedirs(scratch)
        try:
            source_set, mesh = gather(context, obj, None, self.size, scratch)
        except (ValueError, RuntimeError, self.core.PaintReliefError) as error:
            self.refused[name] = str(error)
            return True
        self.gathered.append(scene_jobs.Gathered(name, source_set, mesh))
        return True

    def begin_painting(self):
        """The textures to paint, once every object is gathered; ValueError (one sentence) when none is left."""
        self.seconds["gather"] = time.perf_counter() - self.started
        if not self.gathered:
            raise ValueError("Paint Scene could paint none of the {} objects: {}".format(
                len(self.names), " ".join(self.refused.values())))
        self.paintings = scene_jobs.scene_paintings(self.gathered, self.core.SurfaceMesh)

    def work(self, progress, cancel):
        """Paint every texture side by side (``core.paint_objects``); the outcomes in the paintings' order."""
        started = time.perf_counter()
        requests = [dict(texture_path=p.paths[0] if len(p.paths) == 1 else p.paths, mesh=p.mesh,
                         output_dir=os.path.join(self.folder, p.folder), params=self.params, texture_size=self.size,
                         stroke_mm=self.stroke_mm, normal_map=self.normal_map,
                         keep_source=scene_jobs.keeps_source(p.paths, self.scratch), extensions=p.extensions)
                    for p in self.paintings]
        outcomes = self.core.paint_objects(requests, progress=progress, cancel=cancel, farm=FARM)
        self.seconds["paint"] = time.perf_counter() - started
        return outcomes

    def finish(self, context, outcomes, relief, thickness):
        """Give every object of a painted texture its look; write ``REPORT_FILE``; return the report."""
        started = time.perf_counter()
        gathered = {item.name: item for item in self.gathered}
        painted = {}
        for painting, outcome in zip(self.paintings, outcomes, strict=True):
            if outcome.error is not None:
                for name in painting.names:
                    self.refused[name] = str(outcome.error)
                continue
            for name in painting.names:
                source_set = gathered[name].source_set
                try:
                    object_material.paint_object_look(
                        context.scene, context.scene.objects[name], outcome.report["output_dir"], thickness, relief,
                        self.size, source_set.slot_source, source_set.extensions, source_set.uv_maps,
                        source_set.feeds, source_set.transforms)
                except CanvasError as error:
                    self.refused[name] = str(error)
                    continue
                painted[name] = {"folder": painting.folder, "shares_with": [n for n in painting.names if n != name],
                                 "kept": _kept(outcome)}
        self.seconds["looks"] = time.perf_counter() - started
        reports = {p.folder: o.report for p, o in zip(self.paintings, outcomes, strict=True) if o.error is None}
        report = {"scene": context.scene.name, "frames": [context.scene.frame_start, context.scene.frame_end],
                  "selected_only": self.selected_only, "texture_size": self.size, "stroke_mm": list(self.stroke_mm),
                  "stroke_mm_from": self.how, "painted": painted, "refused": self.refused,
                  "paintings": {folder: {"objects": p.names, "strokes": reports[folder].get("strokes"),
                                         "kept": _kept(o), "seconds": reports[folder].get("seconds")}
                                for p, o in zip(self.paintings, outcomes, strict=True)
                                for folder in [p.folder] if folder in reports},
                  "seconds": dict(self.seconds, total=time.perf_counter() - self.started)}
        _write_json(os.path.join(self.folder, REPORT_FILE), report)
        return report

    def clean(self):
        shutil.rmtree(self.scratch, ignore_errors=True)


def _kept(outcome):
    """Whether ``core.paint_objects`` kept the painting of ``outcome`` (an ``ObjectOutcome`` with a report) from
    an earlier run."""
    return outcome.report.get("batch") == "kept"


def _write_json(path, document):
    """Write ``document`` as JSON to ``path`` through a temporary name, renamed over it."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    partial = path + ".partial"
    with open(partial, "w", encoding="utf-8") as file:
        json.dump(document, file, indent=2)
        file.write("\n")
    os.replace(partial, path)


def _start(operator, context):
    """A ``ScenePaint`` for ``context``'s scene, or None after reporting in one sentence why it cannot start."""
    missing = dependencies.problem()
    if missing is not None:
        operator.report({"ERROR"}, missing)
        return None
    from ... import core

    if context.mode != "OBJECT":
        operator.report({"ERROR"}, "Paint Scene works in Object Mode: switch to it, then paint.")
        return None
    if jobs.is_running(context.scene):
        operator.report({"ERROR"}, "A painting is already running in scene {}: wait for it to finish or press Esc "
                        "to cancel it.".format(context.scene.name))
        return None
    selected_only = context.scene.paint_relief.scene_selected_only or operator.selected_only
    try:
        names, depths = scene_targets(context, selected_only)
        return ScenePaint(context, names, depths, selected_only, operator.texture_size)
    except (ValueError, core.PaintReliefError) as error:
        operator.report({"ERROR"}, str(error))
        return None


def _report(operator, report):
    """Tell the user what was painted, and name every object that was not, each in its sentence."""
    kept = sum(1 for entry in report["paintings"].values() if entry["kept"])
    operator.report({"INFO"}, "Paint Scene painted {} objects of scene {} into {} ({} textures, {} kept from "
                    "before)".format(len(report["painted"]), report["scene"], report.get("folder", ""),
                                     len(report["paintings"]), kept))
    for sentence in report["refused"].values():
        operator.report({"WARNING"}, sentence)


class PAINT_RELIEF_OT_paint_scene(jobs.SceneJob, Operator):
    """Paint the texture of every mesh the scene's camera sees over the frame range (or of the selection), with
    one stroke size for the whole scene, and give each object its painting and relief"""

    bl_idname = "paint_relief.paint_scene"
    bl_label = "Paint Scene"
    bl_options = {"REGISTER", "UNDO"}

    texture_size: bpy.props.IntProperty(
        name="Texture Size", description="Texels a side of each painted texture (0: the Paint Object panel's "
        "Texture Size)", default=0, min=0, options={"HIDDEN", "SKIP_SAVE"})
    selected_only: bpy.props.BoolProperty(
        name="Selected Only", description="Paint the selected mesh objects (else as the panel's Selected Only)",
        default=False, options={"HIDDEN", "SKIP_SAVE"})

    @classmethod
    def poll(cls, context):
        return context.scene is not None

    def execute(self, context):
        run = _start(self, context)
        if run is None:
            return {"CANCELLED"}
        jobs.begin(context.scene)
        try:
            try:
                while run.gather_next(context):
                    pass
                run.begin_painting()
                outcome = Outcome().run(run.work, lambda error: "Paint Scene failed: {}".format(error),
                                        sentences=(ValueError,))
            except KeyboardInterrupt:   # Ctrl-C in a headless run
                self.report({"ERROR"}, run.stopped)
                return {"CANCELLED"}
            except ValueError as error:
                self.report({"ERROR"}, str(error))
                return {"CANCELLED"}
            return self.report_outcome(outcome, lambda outcomes: self._finish(context, run, outcomes), False)
        finally:
            jobs.end(context.scene)
            run.clean()

    def _finish(self, context, run, outcomes):
        settings = context.scene.paint_relief
        report = run.finish(context, outcomes, settings.object_relief, settings.thickness_mm / 1000.0)
        report["folder"] = run.folder
        _report(self, report)

    def begin_modal(self, context):
        self._run = _start(self, context)
        if self._run is None:
            return {"CANCELLED"}
        self._scene = context.scene
        self._worker = None
        jobs.begin(context.scene)
        self.start_timer(context)
        return {"RUNNING_MODAL"}

    def escape(self, context):
        if self._worker is None:        # still gathering: stop at once, nothing was painted
            self.report({"WARNING"}, "Paint Scene was stopped before painting: nothing was written.")
            self._end(context)
            return {"CANCELLED"}
        return super().escape(context)

    def step(self, context):
        run = self._run
        if self._worker is None:
            if run.index < len(run.names):
                name = run.names[run.index]
                self.show(context, 0.0, "reading the sources of {} ({}/{}) (Esc to cancel)".format(
                    name, run.index + 1, len(run.names)), percent=False)
                run.gather_next(context)
                return {"RUNNING_MODAL"}
            try:
                run.begin_painting()
            except ValueError as error:
                self.report({"ERROR"}, str(error))
                self._end(context)
                return {"CANCELLED"}
            self._worker = Worker(run.work, lambda error: "Paint Scene failed: {}".format(error))
            return {"RUNNING_MODAL"}
        if self.show_worker(context):
            return {"RUNNING_MODAL"}
        worker = self._worker
        if worker.stopped:
            worker.error = run.stopped
        try:
            return self.report_outcome(worker, lambda outcomes: self._finish(context, run, outcomes),
                                       worker.cancel.is_set())
        finally:
            self._end(context)

    def cancel(self, context):
        if self._worker is not None:
            self._worker.stop()
        self._end(context)

    def clean(self):
        self._run.clean()


classes = (PAINT_RELIEF_OT_paint_scene,)

register, unregister = bpy.utils.register_classes_factory(classes)
