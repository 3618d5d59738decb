# SPDX-License-Identifier: GPL-3.0-or-later
"""Everything that touches ``bpy``: settings, operators and panels.

Each module lists its classes in ``classes``; they are registered in that order
and unregistered in reverse, so enabling, disabling and enabling again leaves
no stale classes or properties behind.
"""

from . import cli_command, dropped, ops_compare, ops_paint, ops_scene, panels, preferences, presets, properties

# Register order matters: property groups first, panels (which name the operators) last.
_modules = (properties, preferences, ops_paint, ops_scene, ops_compare, presets, dropped, panels, cli_command)


def register():
    for module in _modules:
        module.register()


def unregister():
    for module in reversed(_modules):
        module.unregister()
