"""addon/values.py loaded on its own, for tests that run without Blender (the addon package imports bpy).

values reaches the painter as ``..core`` (the extension's root package holds both addon and core). Here it is
loaded as ``paint_relief_addon_values.addon.values``, and the repository's core modules it reaches stand under
that root's name, so ``values`` and the tests share one core.
"""

import importlib.util
import sys
from pathlib import Path

import core.files.folders  # noqa: F401  (the core modules values imports, loaded before they are named below)
import core.files.shot_files  # noqa: F401
import core.params  # noqa: F401

_ROOT = "paint_relief_addon_values"
_PATH = Path(__file__).resolve().parent.parent / "addon" / "values.py"
for _name, _module in list(sys.modules.items()):
    if _name == "core" or _name.startswith("core."):
        sys.modules.setdefault("{}.{}".format(_ROOT, _name), _module)
_spec = importlib.util.spec_from_file_location(_ROOT + ".addon.values", _PATH)
values = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(values)
