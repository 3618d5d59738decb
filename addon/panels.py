# SPDX-License-Identifier: GPL-3.0-or-later
"""User interface: the Paint Relief tab of the 3D Viewport sidebar (N panel).

A parent panel shows which painting the scene uses; sub-panels Paint, Paint
Animation, Canvas, Lighting and Compare hold the settings and the operators. Buttons are greyed out by
the operators' poll() until they can run.
"""

import os

import bpy
from bpy.types import Panel

from . import values
from .painting import shot_source
from .settings import properties
from .settings.presets import PAINT_RELIEF_MT_paint_presets


def _props(layout, settings, *names):
    """A row for each of the settings ``names``, in order."""
    for name in names:
        layout.prop(settings, name)


def _note(layout, text, icon="INFO"):
    """A right-aligned line that tells something (where a painting goes, what will be rendered)."""
    row = layout.row()
    row.alignment = "RIGHT"
    row.label(text=text, icon=icon)


class _PaintReliefPanel:
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Paint Relief"

    def _layout(self):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        return layout


class VIEW3D_PT_paint_relief(_PaintReliefPanel, Panel):
    """Paint a photograph, then stage it as a canvas with relief, lights and a camera"""

    bl_label = "Paint Relief"

    def draw(self, context):
        settings = context.scene.paint_relief
        row = self.layout.row()
        if settings.painting_dir:
            row.label(text=bpy.path.basename(bpy.path.abspath(settings.painting_dir).rstrip("/\\")), icon="IMAGE_DATA")
        else:
            row.label(text="No painting yet", icon="INFO")


class VIEW3D_PT_paint_relief_paint(_PaintReliefPanel, Panel):
    """Choose a photograph and the painter's settings"""

    bl_label = "Paint"
    bl_parent_id = "VIEW3D_PT_paint_relief"

    def draw(self, context):
        layout = self._layout()
        settings = context.scene.paint_relief
        row = layout.row(align=True)
        row.menu("PAINT_RELIEF_MT_paint_presets", text=PAINT_RELIEF_MT_paint_presets.bl_label)
        row.operator("paint_relief.paint_preset_add", text="", icon="ADD")
        row.operator("paint_relief.paint_preset_add", text="", icon="REMOVE").remove_active = True
        layout.prop(settings, "source", expand=True)
        if settings.source == "BLEND_IMAGE":
            layout.prop(settings, "image")
        else:
            layout.prop(settings, "image_path")
        layout.prop(settings, "output_dir")
        if not settings.output_dir:
            _note(layout, os.path.join(properties.paintings_parent(context),
                                       values.folder_stem(properties.image_name(settings)) + "_NNN"))
        col = layout.column()
        col.prop(settings, "method")
        if settings.method == "HERTZMANN98":
            col.prop(settings, "style")
        _props(col, settings, "mask_path", "detail", "stroke_sizes", "layers", "seed", "brush")
        if settings.brush == "CUSTOM":
            col.prop(settings, "brush_path")
        col.prop(settings, "height_mode")
        col.prop(settings, "timelapse_frames")
        layout.operator("paint_relief.paint", icon="BRUSH_DATA")


class VIEW3D_PT_paint_relief_animation(_PaintReliefPanel, Panel):
    """Paint an image sequence or the scene's animation with strokes that follow the motion"""

    bl_label = "Paint Animation"
    bl_parent_id = "VIEW3D_PT_paint_relief"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = self._layout()
        scene = context.scene
        settings = scene.paint_relief
        layout.prop(settings, "animation_source", expand=True)
        source = settings.animation_source
        if source == "SCENE" and scene.camera is None:
            layout.label(text="The scene has no active camera to render", icon="ERROR")
        elif source == "SCENE":
            render = scene.render
            scale = render.resolution_percentage / 100.0
            _note(layout, "Frames {} to {}, {} x {} px, {}, view layer {}".format(
                scene.frame_start, scene.frame_end, int(render.resolution_x * scale),
                int(render.resolution_y * scale), render.engine.replace("BLENDER_", "").title(),
                context.view_layer.name), icon="RENDER_ANIMATION")
        elif source == "IMAGE":
            layout.prop(settings, "animation_image")
        elif source == "FOLDER":
            layout.prop(settings, "animation_folder")
        else:
            layout.prop(settings, "animation_pattern")
        _props(layout, settings, "animation_fade_frames", "animation_output_dir")
        if not settings.animation_output_dir:
            if settings.animation_key and settings.animation_dir:
                layout.prop(settings, "animation_dir", text="Stopped Run")
            else:
                _note(layout, os.path.join(properties.paintings_parent(context), values.folder_stem(
                    shot_source.source_name(settings, scene)) + "_NNN"))
        if settings.method == "HERTZMANN98":
            layout.label(text="Shots are painted with the paper's method: choose Huang 2011 in Paint",
                         icon="ERROR")
        else:
            layout.label(text="The Paint panel's painter settings apply", icon="BRUSH_DATA")
        layout.operator("paint_relief.paint_animation", icon="RENDER_ANIMATION")


class VIEW3D_PT_paint_relief_object(_PaintReliefPanel, Panel):
    """Paint the active mesh's texture in its UV space, with the paint's relief on the object itself"""

    bl_label = "Paint Object"
    bl_parent_id = "VIEW3D_PT_paint_relief"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        from .objects import object_material, surface

        layout = self._layout()
        settings = context.scene.paint_relief
        obj = context.active_object
        problem = surface.mesh_problem(obj, context)
        if problem is not None:
            layout.label(text=problem, icon="ERROR")
            if obj is not None and obj.type == "MESH" and obj.data.polygons:
                layout.operator("paint_relief.smart_uv_project", icon="UV")
        else:
            image = surface.base_color_image(obj, object_material.source_materials(obj))
            _note(layout, "Source: {}".format(
                "Base Color image {}".format(image.name) if image is not None else
                "texture file" if settings.object_texture_path else "bake of the diffuse colour"), icon="IMAGE_DATA")
        _props(layout, settings, "object_texture_size", "object_texture_path", "object_stroke_mm",
               "object_relief", "thickness_mm", "object_output_dir")
        if not settings.object_output_dir and obj is not None:
            _note(layout, os.path.join(properties.paintings_parent(context), values.folder_stem(obj.name) + "_NNN"))
        if settings.method == "HERTZMANN98":
            layout.label(text="Objects are painted with the paper's method: choose Huang 2011 in Paint",
                         icon="ERROR")
        else:
            layout.label(text="The Paint panel's painter settings apply", icon="BRUSH_DATA")
        layout.operator("paint_relief.paint_object", icon="BRUSH_DATA")
        if obj is not None and obj.get(object_material.PAINTED_KEY):
            painted = object_material.shows_painting(obj)
            layout.operator("paint_relief.object_painting", text="Show Original Material" if painted else
                            "Show Painting", icon="MATERIAL").show = not painted


class VIEW3D_PT_paint_relief_scene(_PaintReliefPanel, Panel):
    """Paint every object the camera sees, with one stroke size for the whole scene"""

    bl_label = "Paint Scene"
    bl_parent_id = "VIEW3D_PT_paint_relief"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        from .objects import ops_scene_paint

        layout = self._layout()
        settings, scene = context.scene.paint_relief, context.scene
        if settings.scene_selected_only:
            count = sum(1 for obj in context.selected_objects if obj.type == "MESH")
            _note(layout, "{} selected mesh objects".format(count), icon="RESTRICT_SELECT_OFF")
        elif scene.camera is None:
            layout.label(text="The scene has no camera: add one, or paint the selection", icon="ERROR")
        else:
            _note(layout, "What {} sees over frames {} to {}".format(scene.camera.name, scene.frame_start,
                                                                     scene.frame_end), icon="CAMERA_DATA")
        _props(layout, settings, "scene_selected_only", "scene_output_dir")
        if not settings.scene_output_dir:
            _note(layout, ops_scene_paint.scene_output_dir(context))
        _note(layout, "Stroke Widths: {}".format(
            "{} mm".format(settings.object_stroke_mm) if settings.object_stroke_mm.strip() else
            "from the camera"), icon="BRUSH_DATA")
        layout.label(text="Texture Size, Stroke Widths and Relief are Paint Object's", icon="INFO")
        layout.operator("paint_relief.paint_scene", icon="SCENE_DATA")


class VIEW3D_PT_paint_relief_canvas(_PaintReliefPanel, Panel):
    """The canvas object: physical size, paint thickness and how the relief is made"""

    bl_label = "Canvas"
    bl_parent_id = "VIEW3D_PT_paint_relief"

    def draw(self, context):
        layout = self._layout()
        settings = context.scene.paint_relief
        _props(layout, settings,
               "painting_dir", "canvas_width_cm", "thickness_mm", "displacement_method", "canvas_frame_range")
        row = layout.row(align=True)
        row.operator("paint_relief.build_canvas", icon="MESH_PLANE").frame_range = settings.canvas_frame_range
        row.operator("paint_relief.reload_maps", icon="FILE_REFRESH")
        row = layout.row(align=True)
        row.operator("paint_relief.strokes_to_grease_pencil", icon="OUTLINER_OB_GREASEPENCIL")
        row.operator("paint_relief.lay_grease_pencil", icon="BRUSH_DATA")
        col = layout.column(heading="Add Camera Sets")
        _props(col, settings, "camera_match_resolution", "camera_standard_view")
        layout.operator("paint_relief.add_camera", icon="OUTLINER_OB_CAMERA")


class VIEW3D_PT_paint_relief_lighting(_PaintReliefPanel, Panel):
    """A raking key light that shows the paint's relief, and a soft fill"""

    bl_label = "Lighting"
    bl_parent_id = "VIEW3D_PT_paint_relief"

    def draw(self, context):
        layout = self._layout()
        settings = context.scene.paint_relief
        _props(layout, settings, "light_azimuth", "light_elevation", "light_strength", "fill_light")
        layout.operator("paint_relief.add_lights", icon="LIGHT_SUN")


class VIEW3D_PT_paint_relief_compare(_PaintReliefPanel, Panel):
    """Render the canvas under a sweep of key lights with and without relief and compare with the 2-D lighting"""

    bl_label = "Compare"
    bl_parent_id = "VIEW3D_PT_paint_relief"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = self._layout()
        settings = context.scene.paint_relief
        _props(layout, settings, "compare_azimuths", "compare_samples", "light_elevation", "compare_output_dir")
        if not settings.compare_output_dir and settings.painting_dir:
            _note(layout, os.path.join(bpy.path.abspath(settings.painting_dir), "comparison"))
        layout.operator("paint_relief.render_comparison", icon="RENDER_STILL")


classes = (
    VIEW3D_PT_paint_relief,
    VIEW3D_PT_paint_relief_paint,
    VIEW3D_PT_paint_relief_animation,
    VIEW3D_PT_paint_relief_object,
    VIEW3D_PT_paint_relief_scene,
    VIEW3D_PT_paint_relief_canvas,
    VIEW3D_PT_paint_relief_lighting,
    VIEW3D_PT_paint_relief_compare,
)

register, unregister = bpy.utils.register_classes_factory(classes)
