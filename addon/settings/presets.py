# SPDX-License-Identifier: GPL-3.0-or-later
"""Presets of the painter's settings with Blender's preset menu (add, apply, remove).

Presets are small Python files Blender keeps in the user's scripts folder
under ``presets/paint_relief/paint/`` (not in the extension's folder, so
they survive updating or uninstalling the extension).
"""

import bpy
from bl_operators.presets import AddPresetBase
from bpy.types import Menu, Operator

PRESET_SUBDIR = "paint_relief/paint"
# The settings a preset stores: everything of the Paint panel except the picture and the output folder.
PRESET_VALUES = [
    "settings.method", "settings.style", "settings.detail", "settings.stroke_sizes", "settings.layers",
    "settings.seed", "settings.brush", "settings.brush_path", "settings.height_mode", "settings.mask_path",
]


class PAINT_RELIEF_MT_paint_presets(Menu):
    bl_label = "Paint Presets"
    preset_subdir = PRESET_SUBDIR
    preset_operator = "script.execute_preset"
    draw = Menu.draw_preset


class PAINT_RELIEF_OT_paint_preset_add(AddPresetBase, Operator):
    """Add or remove a preset of the painter's settings"""

    bl_idname = "paint_relief.paint_preset_add"
    bl_label = "Add Paint Preset"
    preset_menu = "PAINT_RELIEF_MT_paint_presets"
    preset_defines = ["settings = bpy.context.scene.paint_relief"]
    preset_values = PRESET_VALUES
    preset_subdir = PRESET_SUBDIR


classes = (PAINT_RELIEF_MT_paint_presets, PAINT_RELIEF_OT_paint_preset_add)

register, unregister = bpy.utils.register_classes_factory(classes)
