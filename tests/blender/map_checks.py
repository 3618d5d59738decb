# SPDX-License-Identifier: GPL-3.0-or-later
"""Build Canvas on broken painted folders inside Blender (the bpy module); print what happened.

    BLENDER_USER_RESOURCES=/tmp/x python tests/blender/map_checks.py WORK_DIR

WORK_DIR holds one folder per fault (truncated, NaN, infinite, wrong size
maps), each a painted folder with one map broken, and ``good``. For each the
Build Canvas operator runs; the findings (result, error text, whether any
image or object was added) are printed as the last line ``RESULTS <json>``
for tests/test_faults_blender.py.
"""

import json
import os
import sys

from recorder import load_extension


def main(work):
    bpy = load_extension(work)
    settings = bpy.context.scene.paint_relief
    results = {}
    for name in sorted(os.listdir(work)):
        folder = os.path.join(work, name)
        if name == "pkg" or not os.path.isdir(folder):
            continue
        before = (len(bpy.data.images), len(bpy.data.objects), len(bpy.data.meshes))
        settings.painting_dir = folder
        try:
            result, error = sorted(bpy.ops.paint_relief.build_canvas()), ""
        except RuntimeError as exc:  # an operator's ERROR report raises in background mode
            result, error = None, str(exc)
        after = (len(bpy.data.images), len(bpy.data.objects), len(bpy.data.meshes))
        results[name] = {"result": result, "error": error, "changed": before != after}
    print("RESULTS " + json.dumps(results))


if __name__ == "__main__":
    main(sys.argv[1])
