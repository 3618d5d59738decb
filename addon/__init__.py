# SPDX-License-Identifier: GPL-3.0-or-later
"""Everything that touches ``bpy``: settings, operators and panels.

Sub-packages by what they do: ``settings/`` (scene settings, preferences,
presets), ``scene/`` (canvas, camera, lights and the operators that stage
them), ``painting/`` (the Paint and Paint Animation operators), ``objects/`` (Paint Object: a mesh's
texture painted in its UV space, its relief on the object), ``strokes/`` (the painting's strokes as Grease
Pencil and laid again), ``comparison/`` (the lighting
comparison's render sweep, operator and command), ``film/`` (the relit painted film and its
command). At the top: ``values``
(pure helpers, no ``bpy``), ``dependencies`` (the painter's libraries),
``panels`` (the sidebar) and ``cli_command`` (``blender --command``).

Each module lists its classes in ``classes``; they are registered in that order
and unregistered in reverse, so enabling, disabling and enabling again leaves
no stale classes or properties behind.
"""

from . import cli_command, panels
from .comparison import ops_compare
from .objects import ops_object, ops_scene_paint
from .painting import dropped, ops_paint, ops_paint_shot
from .scene import ops_scene
from .settings import preferences, presets, properties
from .strokes import ops_strokes

# Register order matters: property groups first, panels (which name the operators) last.
_modules = (properties, preferences, ops_paint, ops_paint_shot, ops_object, ops_scene_paint, ops_scene, ops_strokes,
            ops_compare, presets, dropped, panels, cli_command)


def register():
    for module in _modules:
        module.register()


def unregister():
    for module in reversed(_modules):
        module.unregister()
