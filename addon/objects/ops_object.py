# SPDX-License-Identifier: GPL-3.0-or-later
"""The Paint Object operators: paint the active mesh's texture in its UV space, unwrap a mesh that has no UV
map, and switch between the painted material and the one the object had.

Paint Object gathers on the main thread what the painter needs: the mesh's
triangles and the texture set's sources, one per material slot
(``sources.texture_sources``, which may bake; an object painted before shows
its original materials meanwhile, so its sources are theirs, never the
painting). The work is one call of
``core.paint_object``, in a worker thread with the progress bar and Esc
interactively, or at once headless (``modal_job``). Once it is done, the object gets its painted material and
relief (``object_material``).
"""

import dataclasses
import os
import shutil
import tempfile

import bpy
from bpy.types import Operator

from .. import dependencies, values
from ..modal_job import Outcome, Worker
from ..painting import jobs
from ..painting.ops_paint import params_from_settings
from ..scene.maps import CanvasError
from ..settings import properties
from . import object_material, sources, surface

OBJECT_SOURCE_MEGAPIXELS = max(values.TEXTURE_SIZE_CHOICES) ** 2 / 1e6
"""Megapixels an object's source may hold: as many as the largest texture Paint Object paints (8192 x 8192)."""


def object_output_dir(context, obj):
    """The folder the painting of ``obj`` goes into: the Paint Object folder when set, else a new folder named
    after the object where paintings go."""
    settings = context.scene.paint_relief
    if settings.object_output_dir:
        return os.path.normpath(bpy.path.abspath(settings.object_output_dir))
    return values.next_painting_folder(properties.paintings_parent(context), obj.name)


class ObjectJob:
    """What Paint Object hands its worker and its finish: ``work(progress, cancel)``, the sentence of an
    unexpected ``failure``, the object, its texture's size, ``scratch``, a folder of its own holding the
    texture's sources when Blender had them only in memory or baked them (the painter keeps a copy with the maps
    as source.png; the folder is removed either way) and its sources (``sources.SourceSet``)."""

    def __init__(self, work, failure, obj, size, scratch, source_set):
        self.work, self.failure, self.obj, self.size, self.scratch = work, failure, obj, size, scratch
        self.source_set = source_set
        self.stopped = "Painting {} was stopped: its maps were not written and the object is as it was.".format(
            obj.name)
        """The sentence of a run stopped by Esc or Ctrl-C (the painter commits all or nothing)."""

    def finish(self, operator, context, report):
        """Give the object its painting, tell the user."""
        _finish(operator, context, self, report)

    def clean(self):
        """Remove the scratch folder."""
        shutil.rmtree(self.scratch, ignore_errors=True)


def object_params(settings):
    """The painter's ``core.Params`` of the panel's ``settings`` for an object's texture: the paper's method
    (``Params.validate_object``; ParameterError otherwise, Hertzmann 1998 paints stills), its source resampled to
    the texture, so it may hold as many pixels as the largest texture offered."""
    params = params_from_settings(settings).validate_object()
    return dataclasses.replace(params, max_megapixels=max(params.max_megapixels, OBJECT_SOURCE_MEGAPIXELS))


def gather(context, obj, file_path, size, scratch):
    """(``sources.SourceSet``, ``core.SurfaceMesh``): what the painter needs of ``obj``: its texture set's sources
    (``file_path`` for slots without an image, else bakes ``size`` texels square; pictures Blender holds only in
    memory are written into ``scratch``) and its triangles, their UVs where the sources are read. An object
    painted before gives its original materials' sources, never the painting. ValueError or RuntimeError (one
    sentence) when it cannot be painted."""
    from ... import core

    with object_material.original_shown(obj):
        source_set = sources.texture_sources(context, obj, file_path, size, scratch)
        uv, position, material_index = surface.mesh_triangles(context, obj, source_set.slot_uv_maps())
    triangle_source = sources.triangle_sources(material_index, source_set.slot_source)
    mesh = core.SurfaceMesh(sources.read_where_sampled(uv, triangle_source, source_set.transforms), position,
                            triangle_source)
    return source_set, mesh


def _prepare(operator, context):
    """Check the object and the settings (the paper's method: ``Params.validate_object``), find the texture's
    source; return an ``ObjectJob`` or None after reporting the problem in one sentence."""
    missing = dependencies.problem()
    if missing is not None:
        operator.report({"ERROR"}, missing)
        return None
    from ... import core

    obj, settings = context.active_object, context.scene.paint_relief
    problem = surface.mesh_problem(obj, context)
    if problem is None and jobs.is_running(context.scene):
        problem = ("A painting is already running in scene {}: wait for it to finish or press Esc to cancel "
                   "it.".format(context.scene.name))
    if problem is not None:
        operator.report({"ERROR"}, problem)
        return None
    size = getattr(operator, "texture_size", 0)        # a script's choice, else the panel's
    size = size if isinstance(size, int) and size > 0 else int(settings.object_texture_size)
    scratch = tempfile.mkdtemp(prefix="paint_relief_object_")
    try:
        params = object_params(settings)
        widths = values.parse_widths(settings.object_stroke_mm)
        folder = object_output_dir(context, obj)
        properties.check_output_folder(folder)
        source_set, mesh = gather(context, obj, settings.object_texture_path, size, scratch)
    except (ValueError, RuntimeError, core.PaintReliefError) as error:
        shutil.rmtree(scratch, ignore_errors=True)
        operator.report({"ERROR"}, str(error))
        return None
    except KeyboardInterrupt:       # Ctrl-C while the sources are read or baked (a bake puts the object back)
        shutil.rmtree(scratch, ignore_errors=True)
        raise
    paths = source_set.paths
    normal_map = settings.object_relief == "NORMAL_MAP"
    keep_source = any(os.path.dirname(path) == scratch for path in paths)

    def work(progress, cancel):
        return core.paint_object(paths[0] if len(paths) == 1 else paths, mesh, folder, params, size, widths,
                                 progress=progress, cancel=cancel, normal_map=normal_map, keep_source=keep_source,
                                 extensions=source_set.extensions)

    return ObjectJob(work, lambda error: "Painting {} failed: {}".format(obj.name, error), obj, size, scratch,
                     source_set)


def _finish(operator, context, job, report):
    """Give the object its painting; report how many strokes went where (or why the maps cannot be shown)."""
    settings, obj = context.scene.paint_relief, job.obj
    try:
        object_material.paint_object_look(context.scene, obj, report["output_dir"], settings.thickness_mm / 1000.0,
                                          settings.object_relief, job.size, job.source_set.slot_source,
                                          job.source_set.extensions, job.source_set.uv_maps,
                                          job.source_set.feeds, job.source_set.transforms)
    except CanvasError as error:
        operator.report({"ERROR"}, str(error))
        return
    operator.report({"INFO"}, "Painted {} strokes on {} into {}".format(report.get("strokes", "the"), obj.name,
                                                                        report["output_dir"]))


def mesh_in_object_mode(context):
    """Whether the active object is a mesh and Blender is in Object Mode."""
    obj = context.active_object
    return obj is not None and obj.type == "MESH" and context.mode == "OBJECT"


class PAINT_RELIEF_OT_paint_object(jobs.SceneJob, Operator):
    """Paint the active mesh's texture in its UV space and give the object the painting and its relief"""

    bl_idname = "paint_relief.paint_object"
    bl_label = "Paint Object"
    bl_options = {"REGISTER", "UNDO"}

    texture_size: bpy.props.IntProperty(
        name="Texture Size", description="Texels a side of the painted texture (0: the Paint Object panel's Texture "
        "Size)", default=0, min=0, options={"HIDDEN", "SKIP_SAVE"})

    @classmethod
    def poll(cls, context):
        # Any active object, or none: the operator names what is wrong with it in one sentence, as the panel does.
        return context.scene is not None

    def execute(self, context):
        try:
            job = _prepare(self, context)
        except KeyboardInterrupt:   # Ctrl-C in a headless run before the painter starts: nothing was written
            self.report({"ERROR"}, "Painting {} was stopped: its maps were not written and the object is as it "
                        "was.".format(getattr(context.active_object, "name", "the object")))
            return {"CANCELLED"}
        if job is None:
            return {"CANCELLED"}
        jobs.begin(context.scene)
        try:
            try:
                outcome = Outcome().run(job.work, job.failure)
            except KeyboardInterrupt:   # Ctrl-C in a headless run
                self.report({"ERROR"}, job.stopped)
                return {"CANCELLED"}
            return self.report_outcome(outcome, lambda report: job.finish(self, context, report), False)
        finally:
            jobs.end(context.scene)
            job.clean()

    def begin_modal(self, context):
        self._job = _prepare(self, context)
        if self._job is None:
            return {"CANCELLED"}
        self._scene = context.scene
        jobs.begin(context.scene)
        self.start_timer(context)
        self._worker = Worker(self._job.work, self._job.failure)
        return {"RUNNING_MODAL"}

    def step(self, context):
        if self.show_worker(context):
            return {"RUNNING_MODAL"}
        worker = self._worker
        if worker.stopped:
            worker.error = self._job.stopped
        try:
            return self.report_outcome(worker, lambda report: self._job.finish(self, context, report),
                                       worker.cancel.is_set())
        finally:
            self._end(context)

    def clean(self):
        self._job.clean()


class PAINT_RELIEF_OT_smart_uv_project(Operator):
    """Unwrap the active mesh with Smart UV Project, so that its texture can be painted"""

    bl_idname = "paint_relief.smart_uv_project"
    bl_label = "Smart UV Project"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return mesh_in_object_mode(context)

    def execute(self, context):
        obj = context.active_object
        if not obj.data.polygons:
            self.report({"ERROR"}, "Object {} has no faces to unwrap.".format(obj.name))
            return {"CANCELLED"}
        bpy.ops.object.mode_set(mode="EDIT")
        try:
            bpy.ops.mesh.select_all(action="SELECT")
            bpy.ops.uv.smart_project(island_margin=0.02)
        finally:
            bpy.ops.object.mode_set(mode="OBJECT")
        self.report({"INFO"}, "Unwrapped {} into UV map {}".format(obj.name, surface.uv_map_name(obj)))
        return {"FINISHED"}


class PAINT_RELIEF_OT_object_painting(Operator):
    """Show the painting on the active object, or the material it had before Paint Object"""

    bl_idname = "paint_relief.object_painting"
    bl_label = "Show Painting"
    bl_options = {"REGISTER", "UNDO"}

    show: bpy.props.BoolProperty(name="Show Painting", description="Show the painting (else the original "
                                 "material)", default=True)

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and bool(obj.get(object_material.PAINTED_KEY))

    def execute(self, context):
        object_material.show_painting(context.active_object, self.show)
        return {"FINISHED"}


classes = (PAINT_RELIEF_OT_paint_object, PAINT_RELIEF_OT_smart_uv_project, PAINT_RELIEF_OT_object_painting)

register, unregister = bpy.utils.register_classes_factory(classes)
