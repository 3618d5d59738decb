# SPDX-License-Identifier: GPL-3.0-or-later
"""The Grease Pencil round trip from the installed zip: a painting's strokes as Grease Pencil, laid again as they
are, with half of them deleted, and with one recoloured and one drawn anew.

Run in its own process with BLENDER_USER_RESOURCES set to a throw-away folder::

    BLENDER_USER_RESOURCES=/tmp/u python tests/shipped/grease_pencil.py PACKAGE.zip WORK_DIR

Each step records its findings under its name; the last line printed is
``RESULTS <json>``, which test_grease_pencil.py asserts on. Grease Pencil 3
(Blender 4.3 and later) and the legacy Grease Pencil (4.2) are edited each
through its own API, as an artist's tools would.
"""

import base64
import json
import os
import sys
from importlib import import_module

from steps import MODULE, REPO, RESULTS, run_op, step  # tests/shipped/steps.py, beside this script

WIDTH, HEIGHT = 64, 48


def main(zip_path, work):
    import bpy
    import numpy as np

    bpy.ops.wm.read_factory_settings(use_empty=True)
    result = bpy.ops.extensions.package_install_files(filepath=os.path.abspath(zip_path), repo=REPO,
                                                      enable_on_install=True)
    RESULTS["install"] = {"result": sorted(result), "enabled": MODULE in bpy.context.preferences.addons,
                          "blender": list(bpy.app.version)}
    ops = bpy.ops.paint_relief
    scene = bpy.context.scene
    settings = scene.paint_relief
    problem = sys.modules[MODULE + ".addon.dependencies"].problem()     # puts Blender's own modules on the path
    RESULTS["install"]["problem"] = problem
    writing = import_module(MODULE + ".core.files.writing")
    reading = import_module(MODULE + ".core.files.reading")
    gp = import_module(MODULE + ".addon.strokes.grease_pencil")
    command = import_module(MODULE + ".addon.strokes.grease_pencil_command")
    gp3 = gp.is_grease_pencil_3()

    photo = os.path.join(work, "photo.png")
    y, x = np.mgrid[0:HEIGHT, 0:WIDTH]
    image = np.stack([x / WIDTH, y / HEIGHT, 0.5 + 0.4 * np.sin(x / 3.0) * np.cos(y / 5.0)], -1)
    image[:, WIDTH // 2:] = np.random.default_rng(4).random((HEIGHT, WIDTH - WIDTH // 2, 3))
    writing.write_png(photo, image.astype(np.float32))

    def strokes_of(folder):
        with open(os.path.join(folder, "strokes.json"), encoding="utf-8") as file:
            return json.load(file)["strokes"]

    def frame_of(obj):
        return obj.data.layers[gp.LAYER].frames[0]

    def gp_strokes(obj):
        """(points per stroke, radius per point, linear RGBA per point, index attribute per stroke)."""
        counts, points, radius, colour, opacity, material, index = gp.read_arrays(obj)
        return counts, radius, colour, index

    def relief(folder):
        height = reading.read_exr(os.path.join(folder, "height.exr"))[0][..., 0]
        opacity = reading.read_exr(os.path.join(folder, "opacity.exr"))[0][..., 0]
        return height, float(opacity.mean())

    def reach(strokes):
        """Where the strokes can put paint: every pixel within a brush width of a point of a path."""
        mask = np.zeros((HEIGHT, WIDTH), bool)
        for stroke in strokes:
            for px, py in stroke["path"]:
                mask |= (x - px) ** 2 + (y - py) ** 2 <= stroke["size"] ** 2
        return mask

    @step
    def paint_and_strokes_as_grease_pencil():
        settings.image_path = photo
        settings.output_dir = os.path.join(work, "painted")
        painted, error = run_op(ops.paint)
        canvas, _ = run_op(ops.build_canvas)
        scene.frame_start, scene.frame_end = 1, 40
        made, made_error = run_op(ops.strokes_to_grease_pencil)
        obj = bpy.context.view_layer.objects.active
        strokes = strokes_of(settings.painting_dir)
        counts, radius, colour, index = gp_strokes(obj)
        starts = np.concatenate(([0], np.cumsum(counts)))
        mean_bristles = np.array([np.frombuffer(base64.b64decode(s["lay"]["bristles"]), "<f4").reshape(-1, 3)
                                  .mean(axis=0) for s in strokes])
        srgb = np.where(colour[:, :3] <= 0.0031308, colour[:, :3] * 12.92,
                        1.055 * np.power(np.maximum(colour[:, :3], 0.0031308), 1 / 2.4) - 0.055)
        colour_error = max(float(np.abs(srgb[starts[i]:starts[i + 1]] - mean_bristles[i]).max())
                           for i in range(len(counts)))
        modifiers = obj.modifiers if gp3 else obj.grease_pencil_modifiers
        visible = []
        for frame in (1, 20, 40):
            scene.frame_set(frame)
            evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
            layer = evaluated.data.layers[gp.LAYER]
            shown = layer.current_frame() if gp3 else layer.frames[0]
            visible.append(len(shown.drawing.strokes) if gp3 else len(shown.strokes))
        scene.frame_set(1)
        return {"painted": painted, "error": error, "canvas": canvas, "made": made, "made_error": made_error,
                "type": obj.type, "parent": obj.parent.get("paint_relief_role") if obj.parent else None,
                "strokes_json": len(strokes), "strokes": int(len(counts)), "min_points": int(counts.min()),
                "min_radius": float(radius.min()), "colour_error": colour_error,
                "index": index.tolist() == list(range(1, len(strokes) + 1)),
                "modifiers": [m.type for m in modifiers], "visible": visible, "grease_pencil_3": gp3}

    @step
    def laid_again_unedited():
        obj = bpy.context.view_layer.objects.active
        first = settings.painting_dir
        result, error = run_op(ops.lay_grease_pencil)
        laid = settings.painting_dir
        same = {name: open(os.path.join(first, name), "rb").read() == open(os.path.join(laid, name), "rb").read()
                for name in ("color.exr", "height.exr", "opacity.exr", "painting.png", "strokes.json")}
        canvas = obj.parent
        return {"result": result, "error": error, "new_folder": laid != first, "same": same,
                "gp_folder": obj.get("paint_relief_painting_dir") == laid,
                "canvas_folder": canvas.get("paint_relief_painting_dir") == laid if canvas else None,
                "canvases": sum(1 for o in scene.objects if o.get("paint_relief_role") == "canvas")}

    @step
    def half_deleted():
        obj = bpy.context.view_layer.objects.active
        before = settings.painting_dir
        strokes = strokes_of(before)
        right = [i for i, s in enumerate(strokes) if s["anchor"][0] >= WIDTH // 2]    # the right half's strokes
        frame = frame_of(obj)
        if gp3:
            frame.drawing.remove_strokes(indices=right)
        else:
            for i in reversed(right):
                frame.strokes.remove(frame.strokes[i])
        left = [s for i, s in enumerate(strokes) if i not in set(right)]
        result, error = run_op(ops.lay_grease_pencil)
        height, coverage = relief(settings.painting_dir)
        _, coverage_before = relief(before)
        mask = reach(left)
        return {"result": result, "error": error, "deleted": len(right), "kept": len(left),
                "laid": len(strokes_of(settings.painting_dir)), "height_max": float(height.max()),
                "outside": float(np.abs(height[~mask]).max(initial=0.0)), "outside_share": float((~mask).mean()),
                "coverage": [coverage_before, coverage]}

    @step
    def recoloured_and_drawn_anew():
        obj = bpy.context.view_layer.objects.active
        strokes = strokes_of(settings.painting_dir)
        frame = frame_of(obj)
        plane = tuple(obj["paint_relief_plane"])
        # a new stroke across the empty right half, 6 px wide, pure blue, as the Draw tool would leave it
        px = np.array([[40.0, 24.0], [60.0, 24.0]])
        points = np.stack([((px[:, 0] + 0.5) / WIDTH - 0.5) * plane[0], (0.5 - (px[:, 1] + 0.5) / HEIGHT) * plane[1],
                           np.full(2, 0.003)], axis=1).astype(np.float32)
        radius = 3.0 * plane[0] / WIDTH
        if gp3:
            drawing = frame.drawing
            drawing.add_strokes([2])
            n = len(drawing.strokes)
            new = drawing.strokes[n - 1]
            for k in range(2):
                new.points[k].position = points[k]
                new.points[k].radius = radius
                new.points[k].opacity = 1.0
                new.points[k].vertex_color = (0.0, 0.0, 1.0, 1.0)
            for point in drawing.strokes[0].points:
                point.vertex_color = (1.0, 0.0, 0.0, 1.0)
        else:
            new = frame.strokes.new()
            new.line_width = gp.LEGACY_LINE_WIDTH
            new.points.add(2)
            for k in range(2):
                new.points[k].co = points[k]
                new.points[k].pressure = radius / (gp.LEGACY_LINE_WIDTH * gp.LEGACY_RADIUS_FACTOR)
                new.points[k].vertex_color = (0.0, 0.0, 1.0, 1.0)
            for point in frame.strokes[0].points:
                point.vertex_color = (1.0, 0.0, 0.0, 1.0)
        result, error = run_op(ops.lay_grease_pencil)
        laid = strokes_of(settings.painting_dir)
        colour = reading.read_exr(os.path.join(settings.painting_dir, "color.exr"))[0]
        first = np.frombuffer(base64.b64decode(laid[0]["lay"]["bristles"]), "<f4").reshape(-1, 3).mean(axis=0)
        return {"result": result, "error": error, "before": len(strokes), "laid": len(laid),
                "new_size": laid[-1]["size"], "new_brush": laid[-1]["lay"]["brush"],
                "new_blue": colour[24, 44:57].mean(axis=0).tolist(), "first_colour": first.tolist()}

    @step
    def command_line_refusals():
        bad = command.main(["grease_pencil.py", os.path.join(work, "no_such_folder"), "-o",
                            os.path.join(work, "x.blend"), "--quiet"])
        not_blend = command.main(["grease_pencil.py", settings.painting_dir, "--lay", "-o",
                                  os.path.join(work, "laid"), "--quiet"])
        return {"bad": bad, "not_blend": not_blend, "written": os.path.exists(os.path.join(work, "laid"))}

    print("RESULTS " + json.dumps(RESULTS), flush=True)


if __name__ == "__main__":
    if not os.environ.get("BLENDER_USER_RESOURCES"):
        sys.exit("BLENDER_USER_RESOURCES is not set: refusing to touch a real user profile")
    main(sys.argv[1], sys.argv[2])
