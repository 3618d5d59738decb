# SPDX-License-Identifier: GPL-3.0-or-later
"""Launch the Grease Pencil round trip from a checkout (addon/strokes/grease_pencil_command.py has the whole run).

    .venv/bin/python sample_scenes/grease_pencil.py PAINTED_DIR -o OUT.blend [--width-cm 40] [--frames 1-250]
    .venv/bin/python sample_scenes/grease_pencil.py SCENE.blend --lay -o OUTDIR [--object NAME] [--reference PHOTO]
    blender -b --python-exit-code 1 --python sample_scenes/grease_pencil.py -- PAINTED_DIR -o OUT.blend

The first builds the canvas of a painted folder and a Grease Pencil object of
its strokes on it, revealed in paint order over the frame range, and saves
the scene; the second lays the Grease Pencil strokes of a saved scene, as the
artist left them, into a new painted folder. When the extension is installed
and enabled, its package is used; otherwise the repository root is loaded as
the package ``paint_relief``. Exit codes: 0 done, 1 a bad input or a failed
step (one sentence on stderr), 2 a malformed command line.
"""

import importlib
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from extension import extension_package  # noqa: E402 (the launcher's folder first)

if __name__ == "__main__":
    package = extension_package()
    command = importlib.import_module(package.__name__ + ".addon.strokes.grease_pencil_command")
    sys.exit(command.main(sys.argv))
