# SPDX-License-Identifier: GPL-3.0-or-later
"""Everything that touches ``bpy``: settings, panels and (later) operators.

Each module lists its classes in ``classes``; they are registered in that order
and unregistered in reverse, so enabling, disabling and enabling again leaves
no stale classes or properties behind.
"""

from . import panels, properties

# Register order matters: property groups before the panels that draw them.
_modules = (properties, panels)


def register():
    for module in _modules:
        module.register()


def unregister():
    for module in reversed(_modules):
        module.unregister()
