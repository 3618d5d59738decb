# SPDX-License-Identifier: GPL-3.0-or-later
"""The extension as an artist gets it: installed from the built zip, driven headless step by step.

Run in its own process with BLENDER_USER_RESOURCES set to a throw-away folder::

    BLENDER_USER_RESOURCES=/tmp/u python tests/shipped/flow.py PACKAGE.zip WORK_DIR

Blender installs the zip (and the wheels it declares) with
``package_install_files``, exactly as *Install from Disk* does; nothing of
the checkout is imported. Each step records its findings under its name (a
step that raises records its traceback); the last line printed is
``RESULTS <json>``, which test_flow.py asserts on.
"""

import json
import os
import sys
import traceback

REPO = "user_default"
MODULE = "bl_ext.{}.paint_relief".format(REPO)
RESULTS = {}


def step(function):
    try:
        RESULTS[function.__name__] = function()
    except Exception:
        RESULTS[function.__name__] = {"exception": traceback.format_exc()}
    return function


def run_op(op, **kwargs):
    """Call an operator; return (sorted result or None, error text)."""
    try:
        return sorted(op(**kwargs)), ""
    except RuntimeError as error:  # an ERROR report raises in background mode
        return None, str(error)


def main(zip_path, work):
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    result = bpy.ops.extensions.package_install_files(filepath=os.path.abspath(zip_path), repo=REPO,
                                                      enable_on_install=True)
    RESULTS["install"] = {"result": sorted(result), "enabled": MODULE in bpy.context.preferences.addons,
                          "imported_at_enable": [m for m in ("scipy", "OpenImageIO") if m in sys.modules],
                          "blender": list(bpy.app.version)}
    package = sys.modules[MODULE]
    dependencies = sys.modules[MODULE + ".addon.dependencies"]
    ops = bpy.ops.paint_relief
    scene = bpy.context.scene
    settings = scene.paint_relief

    @step
    def libraries():
        problem = dependencies.problem()
        import numpy
        import OpenImageIO
        import scipy

        return {"problem": problem, "openimageio": OpenImageIO.__file__,
                "openimageio_source": dependencies.openimageio_source(OpenImageIO),
                "openimageio_version": OpenImageIO.VERSION_STRING, "numpy": numpy.__version__,
                "scipy": scipy.__version__, "scipy_file": scipy.__file__,
                "user_resources": os.environ["BLENDER_USER_RESOURCES"]}

    from importlib import import_module

    core = import_module(MODULE + ".core")
    io = import_module(MODULE + ".core.io")
    import numpy as np

    photo = os.path.join(work, "photo.png")
    y, x = np.mgrid[0:48, 0:64]
    io.write_png(photo, np.stack([x / 64, y / 48, 0.5 + 0.4 * np.sin(x / 3.0) * np.cos(y / 5.0)], -1)
                 .astype(np.float32))

    @step
    def paint():
        settings.image_path = photo
        settings.output_dir = os.path.join(work, "painted")
        settings.stroke_sizes = "400,200"
        result, error = run_op(ops.paint)
        folder = settings.painting_dir
        return {"result": result, "error": error, "painting_dir": folder,
                "files": sorted(os.listdir(folder)) if folder and os.path.isdir(folder) else []}

    @step
    def stage():
        results = {name: run_op(getattr(ops, name)) for name in ("build_canvas", "add_lights", "add_camera")}
        canvas = [o for o in scene.objects if o.get("paint_relief_role") == "canvas"]
        return {"results": results, "canvas_dimensions": list(canvas[0].dimensions[:2]) if canvas else None,
                "resolution": [scene.render.resolution_x, scene.render.resolution_y]}

    @step
    def cycles_render():
        scene.render.engine = "CYCLES"
        scene.cycles.device = "CPU"
        scene.cycles.samples = 4
        scene.cycles.use_denoising = False
        settings_image = scene.render.image_settings
        if hasattr(settings_image, "media_type"):
            settings_image.media_type = "IMAGE"
        settings_image.file_format = "PNG"
        path = os.path.join(work, "render.png")
        scene.render.filepath = path
        bpy.ops.render.render(write_still=True)
        pixels = io.read_image(path)
        return {"exists": os.path.isfile(path), "size": list(pixels.shape[:2]), "mean": float(pixels.mean()),
                "std": float(pixels.std())}

    @step
    def comparison():
        settings.compare_azimuths = 2
        settings.compare_samples = 2
        settings.compare_output_dir = os.path.join(work, "comparison")
        result, error = run_op(ops.render_comparison)
        folder = settings.compare_output_dir
        sheet_path = os.path.join(folder, "comparison.png")
        found = {"result": result, "error": error, "files": sorted(os.listdir(folder)) if os.path.isdir(folder) else []}
        if os.path.isfile(sheet_path):
            sheet_module = import_module(MODULE + ".core.sheet")
            sheet = io.read_image(sheet_path)
            # The first row of labels: the strip between the top gap and the first pictures.
            strip = sheet[6:6 + 24, 6:200]
            found["label_pixels"] = int((np.abs(strip - np.asarray(sheet_module.BACKGROUND)).max(axis=2) > 0.3).sum())
            chart = io.read_image(os.path.join(folder, "correlation.png"))
            found["chart_title_dark_pixels"] = int((chart[5:30, 70:400].max(axis=2) < 0.5).sum())
        return found

    print("RESULTS " + json.dumps(RESULTS), flush=True)


if __name__ == "__main__":
    if not os.environ.get("BLENDER_USER_RESOURCES"):
        sys.exit("BLENDER_USER_RESOURCES is not set: refusing to touch a real user profile")
    main(sys.argv[1], sys.argv[2])
