# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's preferences: where paintings go when the .blend file is not saved yet.

Each painting gets a folder of its own (image name and a counter). Beside a
saved .blend file that is ``//paint_relief/<image>_NNN``; for an unsaved file
it is ``<Default Output Folder>/<image>_NNN``, where the default output
folder is this preference, or ``Paint Relief`` in the user's home folder when
it is left empty. The extension's own user folder is never used: Blender
deletes it when the extension is uninstalled.
"""

import os

import bpy
from bpy.props import StringProperty
from bpy.types import AddonPreferences

# ``__name__`` here is "<extension package>.addon.settings.preferences"; the
# extension package (``bl_ext.<repository>.paint_relief`` when installed) is
# what comes before ".addon.". Blender keys preferences and per-extension user
# folders by that name.
EXTENSION_PACKAGE = __name__.rpartition(".addon.")[0]

HOME_FOLDER_NAME = "Paint Relief"


def home_default():
    """``~/Paint Relief``: the output folder of unsaved files when the preference is empty."""
    return os.path.join(os.path.expanduser("~"), HOME_FOLDER_NAME)


def default_parent(context):
    """The folder new paintings of an unsaved file go into (absolute)."""
    addon = context.preferences.addons.get(EXTENSION_PACKAGE)
    chosen = getattr(addon.preferences, "output_dir", "") if addon is not None and addon.preferences else ""
    return os.path.normpath(bpy.path.abspath(chosen)) if chosen else home_default()


class PaintReliefPreferences(AddonPreferences):
    bl_idname = EXTENSION_PACKAGE

    output_dir: StringProperty(
        name="Default Output Folder",
        description=(
            "Folder for new paintings while the .blend file is not saved (each painting gets a folder of its own "
            "inside). Empty: 'Paint Relief' in your home folder. Saved files paint beside themselves"
        ),
        subtype="DIR_PATH",
    )

    def draw(self, context):
        layout = self.layout
        layout.prop(self, "output_dir")
        if not self.output_dir:
            layout.label(text=home_default(), icon="INFO")


classes = (PaintReliefPreferences,)

register, unregister = bpy.utils.register_classes_factory(classes)
