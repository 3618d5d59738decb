# SPDX-License-Identifier: GPL-3.0-or-later
"""What the scenes paint_object.py saved hold, for tests/test_model_files.py.

    BLENDER_USER_RESOURCES=/tmp/x python tests/blender/model_checks.py OUT_DIR...

For each OUT_DIR, its scene.blend and original.blend opened in turn: each mesh object's material slots (the
materials' names), whether it holds a painted material (the ``paint_relief_painted_material`` pointer) and its
modifiers. Prints ``RESULTS <json>``: {OUT_DIR: {"scene": {object: {...}}, "original": {...}}}.
"""

import json
import sys
from pathlib import Path

import bpy


def meshes():
    return {obj.name: {"slots": [slot.material.name if slot.material else None for slot in obj.material_slots],
                       "painted": obj.get("paint_relief_painted_material") is not None,
                       "modifiers": [modifier.name for modifier in obj.modifiers]}
            for obj in bpy.data.objects if obj.type == "MESH"}


found = {}
for folder in sys.argv[1:]:
    found[folder] = {}
    for name in ("scene", "original"):
        path = Path(folder) / f"{name}.blend"
        if path.is_file():
            bpy.ops.wm.open_mainfile(filepath=str(path))
            found[folder][name] = meshes()
print("RESULTS " + json.dumps(found))
