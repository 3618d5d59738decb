# SPDX-License-Identifier: GPL-3.0-or-later
"""User interface: the Paint Relief tab of the 3D Viewport sidebar (N panel)."""

import bpy
from bpy.types import Panel

from . import properties


class VIEW3D_PT_paint_relief(Panel):
    """Choose a photograph and where the painted maps go."""

    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Paint Relief"
    bl_label = "Paint Relief"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.paint_relief

        layout.prop(settings, "image_path")
        layout.prop(settings, "output_dir")
        if not settings.output_dir:
            row = layout.row()
            row.alignment = "RIGHT"
            row.label(text=properties.default_output_dir(context, create=False), icon="INFO")


classes = (VIEW3D_PT_paint_relief,)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
