"""addon/values.py loaded on its own, for tests that run without Blender (the addon package imports bpy)."""

import importlib.util
from pathlib import Path

_PATH = Path(__file__).resolve().parent.parent / "addon" / "values.py"
_spec = importlib.util.spec_from_file_location("paint_relief_addon_values", _PATH)
values = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(values)
