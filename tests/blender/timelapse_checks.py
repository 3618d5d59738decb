# SPDX-License-Identifier: GPL-3.0-or-later
"""The time-lapse inside Blender (the bpy module): the Paint panel's Time-lapse frames, then Build Canvas on it.

    BLENDER_USER_RESOURCES=/tmp/x python tests/blender/timelapse_checks.py WORK_DIR

WORK_DIR/photo.png is painted by the Paint operator with the scene's
"Time-lapse frames" set, into WORK_DIR/painted; Build Canvas on
WORK_DIR/painted/timelapse builds the animated canvas, whose evaluated relief
is read at the first and the last frame. The last line printed is
``RESULTS <json>`` for tests/test_timelapse.py.
"""

import json
import os
import sys

from recorder import RESULTS, check, load_extension

FRAMES = 3


def main(work):
    import numpy as np

    bpy = load_extension(work)
    from paint_relief.addon.scene import animated, canvas_plane

    ops = bpy.ops.paint_relief
    scene = bpy.context.scene
    settings = scene.paint_relief
    painted = os.path.join(work, "painted")

    @check
    def paint():
        settings.source = "FILE"
        settings.image_path = os.path.join(work, "photo.png")
        settings.output_dir = painted
        settings.timelapse_frames = FRAMES
        result = sorted(ops.paint())
        return {"result": result, "files": sorted(os.listdir(os.path.join(painted, "timelapse")))}

    @check
    def build():
        settings.painting_dir = os.path.join(painted, "timelapse")
        settings.displacement_method = "MESH"
        result = sorted(ops.build_canvas(frame_range=True))
        obj = canvas_plane.find_role(scene, "canvas")
        heights = {}
        for frame in (1, FRAMES):
            scene.frame_set(frame)
            evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
            mesh = evaluated.to_mesh()
            co = np.empty(len(mesh.vertices) * 3)
            mesh.vertices.foreach_get("co", co)
            evaluated.to_mesh_clear()
            heights[str(frame)] = float(co.reshape(-1, 3)[:, 2].mean())
        return {"result": result, "sequence": list(obj[animated.SEQUENCE_KEY]),
                "frame_range": [scene.frame_start, scene.frame_end], "heights": heights}

    RESULTS["blender_version"] = list(bpy.app.version)
    print("RESULTS " + json.dumps(RESULTS), flush=True)


if __name__ == "__main__":
    if not os.environ.get("BLENDER_USER_RESOURCES"):
        sys.exit("BLENDER_USER_RESOURCES is not set: refusing to touch a real user profile")
    main(sys.argv[1])
