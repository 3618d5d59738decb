# SPDX-License-Identifier: GPL-3.0-or-later
"""Paint Relief: the Blender extension entry point.

The repository root is the extension package. Blender imports it as
``bl_ext.<repository>.paint_relief`` and calls :func:`register` and
:func:`unregister`. Nothing heavy is imported here: the painter in ``core``
(NumPy, SciPy, OpenImageIO) is imported by the operators only when they run,
so enabling the extension stays quick.
"""


def register():
    from . import addon

    addon.register()


def unregister():
    from . import addon

    addon.unregister()
