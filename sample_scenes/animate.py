# SPDX-License-Identifier: GPL-3.0-or-later
"""Launch the relit painted film from a checkout (addon/film/film_command.py has the whole run and its options).

    blender -b --python-exit-code 1 --python sample_scenes/animate.py -- FRAMES -o OUTDIR [options]
    .venv/bin/python sample_scenes/animate.py FRAMES -o OUTDIR [options]

FRAMES is footage (a folder of frames or a ``#`` pattern) or a folder painted
by ``python -m core sequence``. The installed extension runs the same with
``blender --command paint_relief animate FRAMES -o OUTDIR``. When the
extension is installed and enabled, its package is used; otherwise the
repository root is loaded as the package ``paint_relief``. Exit codes: 0
done, 1 a bad input or a failed step (one sentence on stderr), 2 a
malformed command line.
"""

import importlib
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from extension import extension_package  # noqa: E402 (the launcher's folder first)

if __name__ == "__main__":
    package = extension_package()
    command = importlib.import_module(package.__name__ + ".addon.film.film_command")
    sys.exit(command.main(sys.argv))
