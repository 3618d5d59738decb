# SPDX-License-Identifier: GPL-3.0-or-later
"""The Paint Relief package the sample scripts run (compare.py, animate.py, paint_object.py): the installed and
enabled extension when Blender has one, else this checkout loaded by path as the package ``paint_relief``."""

import importlib
import importlib.util
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = "paint_relief"


def extension_package(operator="PAINT_RELIEF_OT_build_canvas"):
    """The installed and enabled Paint Relief package (the one that registered the operator class named
    ``operator``), else the repository loaded as ``paint_relief``."""
    import bpy

    if hasattr(bpy.types, operator):
        module = getattr(bpy.types, operator).__module__  # "<package>.addon.<subpackage>.<module>"
        return importlib.import_module(module.rpartition(".addon.")[0])
    spec = importlib.util.spec_from_file_location(PACKAGE, ROOT / "__init__.py", submodule_search_locations=[str(ROOT)])
    package = importlib.util.module_from_spec(spec)
    sys.modules[PACKAGE] = package
    spec.loader.exec_module(package)
    return package
