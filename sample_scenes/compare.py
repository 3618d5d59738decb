# SPDX-License-Identifier: GPL-3.0-or-later
"""Launch the lighting comparison from a checkout (addon/comparison/compare_command.py has the whole run and its options).

    blender -b --python-exit-code 1 --python sample_scenes/compare.py -- INPUT -o OUTDIR [options]
    .venv/bin/python sample_scenes/compare.py INPUT -o OUTDIR [options]

The installed extension runs the same with ``blender --command paint_relief compare INPUT -o OUTDIR``.
When the extension is installed and enabled, its package is used; otherwise
the repository root is loaded as the package ``paint_relief``. Exit codes:
0 done, 1 a bad input or a failed step (one sentence on stderr), 2 a
malformed command line.
"""

import importlib
import importlib.util
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = "paint_relief"


def extension_package():
    """The installed and enabled Paint Relief package, else the repository loaded as ``paint_relief``."""
    import bpy

    if hasattr(bpy.types, "PAINT_RELIEF_OT_build_canvas"):
        module = bpy.types.PAINT_RELIEF_OT_build_canvas.__module__  # "<package>.addon.scene.ops_scene"
        return importlib.import_module(module.rpartition(".addon.")[0])
    spec = importlib.util.spec_from_file_location(PACKAGE, ROOT / "__init__.py", submodule_search_locations=[str(ROOT)])
    package = importlib.util.module_from_spec(spec)
    sys.modules[PACKAGE] = package
    spec.loader.exec_module(package)
    return package


if __name__ == "__main__":
    package = extension_package()
    command = importlib.import_module(package.__name__ + ".addon.comparison.compare_command")
    sys.exit(command.main(sys.argv))
