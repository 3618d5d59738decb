# SPDX-License-Identifier: GPL-3.0-or-later
"""Images dropped on the 3D Viewport become the picture to paint (a FileHandler, Blender 4.1+)."""

import os

import bpy
from bpy.props import CollectionProperty, StringProperty
from bpy.types import FileHandler, Operator, OperatorFileListElement

# Extensions offered for dropping: the common photograph formats OpenImageIO reads.
IMAGE_EXTENSIONS = ".png;.jpg;.jpeg;.tif;.tiff;.exr;.webp;.bmp;.tga;.hdr"


class PAINT_RELIEF_OT_use_image(Operator):
    """Use an image file as the picture Paint Relief paints"""

    bl_idname = "paint_relief.use_image"
    bl_label = "Paint with Paint Relief"
    bl_options = {"REGISTER", "UNDO"}

    filepath: StringProperty(subtype="FILE_PATH", options={"SKIP_SAVE"})
    directory: StringProperty(subtype="DIR_PATH", options={"SKIP_SAVE", "HIDDEN"})
    files: CollectionProperty(type=OperatorFileListElement, options={"SKIP_SAVE", "HIDDEN"})

    @classmethod
    def poll(cls, context):
        return getattr(context.scene, "paint_relief", None) is not None

    def execute(self, context):
        path = self.filepath
        if self.directory and len(self.files):
            path = os.path.join(self.directory, self.files[0].name)
        if not path or not os.path.isfile(bpy.path.abspath(path)):
            self.report({"ERROR"}, "Image file {} does not exist.".format(path or "(none)"))
            return {"CANCELLED"}
        settings = context.scene.paint_relief
        settings.source = "FILE"
        settings.image_path = path
        self.report({"INFO"}, "Paint Relief will paint {}; press Paint in the sidebar's Paint Relief tab".format(
            os.path.basename(path)))
        return {"FINISHED"}

    def invoke(self, context, event):
        if self.filepath or len(self.files):
            return self.execute(context)
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}


class PAINT_RELIEF_FH_image(FileHandler):
    bl_idname = "PAINT_RELIEF_FH_image"
    bl_label = "Paint with Paint Relief"
    bl_import_operator = "paint_relief.use_image"
    bl_file_extensions = IMAGE_EXTENSIONS

    @classmethod
    def poll_drop(cls, context):
        return context.area is not None and context.area.type == "VIEW_3D"


classes = (PAINT_RELIEF_OT_use_image, PAINT_RELIEF_FH_image)

register, unregister = bpy.utils.register_classes_factory(classes)
