# SPDX-License-Identifier: GPL-3.0-or-later
"""Renders of the lighting comparison inside Blender (the bpy module); prints what they show.

Run in its own process (``bpy`` can be imported once per process), with
``BLENDER_USER_RESOURCES`` pointing at a throw-away folder::

    BLENDER_USER_RESOURCES=/tmp/x python tests/blender/compare_checks.py WORK_DIR

The repository is loaded as the package ``paint_relief`` (as
sample_scenes/compare.py loads it) and registered. Checks:

calibration  a painted canvas with its relief switched off
             (``canvas_plane.set_relief``), its surface a Lambertian Diffuse BSDF of
             the colour map, lit only by a uniform white world of radiance 1:
             the outgoing radiance is then exactly the albedo, so the render
             must reproduce color.exr. Rendered with the comparison's own
             render settings (``compare.configure_render``).
ramp         a painted folder written here: mid-grey colour, opacity 1,
             orientation 0 and a height field that falls towards +x (rises
             towards -x) with a slope that grows down the image; rendered by
             ``compare.render_sweep`` with the light at painter azimuths 0
             (right) and 180 (left), then compared by core.evaluation.comparison.
operator     paint_relief.render_comparison on the ramp scene, headless, and
             its one-sentence error for a comparison folder it cannot write.

The last line printed is ``RESULTS <json>``; tests/test_compare.py asserts on
it. A check that raises records its traceback instead.
"""

import importlib.util
import json
import math
import os
import sys

from recorder import RESULTS, check, shade_colour_map

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

CALIBRATION_SIZE = (256, 192)
CALIBRATION_SAMPLES = 64
RAMP_SIZE = (128, 96)
RAMP_CANVAS_CM = 10.0
RAMP_THICKNESS_MM = 2.0
RAMP_SLOPES = (0.05, 0.2)  # physical rise over run, top row to bottom row: 3 to 11 degrees
RAMP_SAMPLES = 16
RAMP_ELEVATION = 30.0
BORDER = 4  # pixels left out at the edges of the ramp



def run_op(op, **kwargs):
    """Call an operator; return (result set or None, error text)."""
    try:
        return sorted(op(**kwargs)), ""
    except RuntimeError as error:  # an operator's ERROR report raises in background mode
        return None, str(error)


def load_package():
    spec = importlib.util.spec_from_file_location("paint_relief", os.path.join(REPO, "__init__.py"),
                                                  submodule_search_locations=[REPO])
    package = importlib.util.module_from_spec(spec)
    sys.modules["paint_relief"] = package
    spec.loader.exec_module(package)
    package.register()
    return package


def empty_scene(bpy):
    scene = bpy.context.scene
    for obj in list(scene.objects):
        bpy.data.objects.remove(obj)
    return scene


def main(work):
    import bpy
    import numpy as np

    load_package()
    from paint_relief import core
    from paint_relief.addon.comparison import compare
    from paint_relief.addon.scene import canvas_plane
    from paint_relief.core.colour import linear_to_srgb, luminance, srgb_to_linear
    from paint_relief.core.files import reading, writing
    from paint_relief.core.lighting import bump_lighting
    from paint_relief.core.measures.metrics import pearson

    ops = bpy.ops.paint_relief
    scene = empty_scene(bpy)
    settings = scene.paint_relief

    @check
    def calibration():
        w, h = CALIBRATION_SIZE
        y, x = np.mgrid[0:h, 0:w]
        photo = np.stack([x / w, y / h, 0.5 + 0.4 * np.sin(x / 5.0) * np.cos(y / 7.0)], axis=-1).astype(np.float32)
        photo_path = os.path.join(work, "calibration_photo.png")
        writing.write_png(photo_path, photo)
        painted = os.path.join(work, "calibration_painting")
        core.paint_file(photo_path, painted, core.Params())
        settings.painting_dir = painted
        settings.displacement_method = "MESH"
        assert ops.build_canvas() == {"FINISHED"}
        settings.camera_match_resolution = settings.camera_standard_view = True
        assert ops.add_camera() == {"FINISHED"}
        obj = canvas_plane.find_role(scene, "canvas")
        canvas_plane.set_relief(obj, False)
        modifier_strength = obj.modifiers[canvas_plane.DISPLACE_MODIFIER].strength
        # A Lambertian surface of the colour map (no specular at all) ...
        diffuse = shade_colour_map(obj.active_material, "ShaderNodeBsdfDiffuse", "Color", "BSDF")
        diffuse.inputs["Roughness"].default_value = 0.0
        # ... lit only by a uniform white world of radiance 1: outgoing radiance = albedo.
        world = bpy.data.worlds.new("white")
        if world.node_tree is None:
            world.use_nodes = True
        background = next(n for n in world.node_tree.nodes if n.type == "BACKGROUND")
        background.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        background.inputs["Strength"].default_value = 1.0
        scene.world = world
        previous = compare.configure_render(scene, CALIBRATION_SAMPLES)
        path = os.path.join(work, "calibration.exr")
        compare.render_still(scene, path)
        compare.restore(previous)
        canvas_plane.set_relief(obj, True)

        rendered = reading.read_exr(path)[0][..., :3]
        expected = reading.read_exr(os.path.join(painted, "color.exr"))[0][..., :3]
        out = {"size": [rendered.shape[1], rendered.shape[0]], "map_size": [expected.shape[1], expected.shape[0]],
               "flat_displace_strength": modifier_strength,
               "relief_back_on": obj.modifiers[canvas_plane.DISPLACE_MODIFIER].strength}
        if rendered.shape == expected.shape:
            a, b = linear_to_srgb(rendered), linear_to_srgb(expected)
            out["psnr_srgb"] = float(10 * np.log10(1.0 / max(float(np.mean((a - b) ** 2)), 1e-12)))
            out["psnr_linear"] = float(10 * np.log10(1.0 / max(float(np.mean((rendered - expected) ** 2)), 1e-12)))
            out["psnr_srgb_upside_down"] = float(10 * np.log10(1.0 / max(float(np.mean((a[::-1] - b) ** 2)), 1e-12)))
            out["mean_ratio"] = float(rendered.mean() / expected.mean())
        return out

    @check
    def ramp():
        w, h = RAMP_SIZE
        folder = os.path.join(work, "ramp_painting")
        os.makedirs(folder, exist_ok=True)
        pixel_mm = 10.0 * RAMP_CANVAS_CM / w
        y, x = np.mgrid[0:h, 0:w].astype(np.float32)
        slope = RAMP_SLOPES[0] + (RAMP_SLOPES[1] - RAMP_SLOPES[0]) * y / (h - 1)
        # Height falls with the column: the slope faces +x (image right), where painter azimuth 0 puts the light.
        height = (slope * (w - 1 - x) * pixel_mm / RAMP_THICKNESS_MM).astype(np.float32)
        grey = np.full((h, w, 3), srgb_to_linear(np.float32(0.5)), dtype=np.float32)
        writing.write_exr(os.path.join(folder, "color.exr"), grey)
        writing.write_exr(os.path.join(folder, "height.exr"), height, channels=("Y",))
        writing.write_exr(os.path.join(folder, "opacity.exr"), np.ones((h, w), np.float32), channels=("Y",))
        writing.write_exr(os.path.join(folder, "orientation.exr"), np.zeros((h, w), np.float32), channels=("Y",))

        empty_scene(bpy)
        settings.painting_dir = folder
        settings.canvas_width_cm = RAMP_CANVAS_CM
        settings.thickness_mm = RAMP_THICKNESS_MM
        settings.displacement_method = "MESH"
        settings.light_strength = 1.0
        settings.fill_light = False
        settings.light_elevation = math.radians(RAMP_ELEVATION)
        assert ops.build_canvas() == {"FINISHED"}
        assert ops.add_lights() == {"FINISHED"}
        settings.camera_match_resolution = settings.camera_standard_view = True
        assert ops.add_camera() == {"FINISHED"}
        obj = canvas_plane.find_role(scene, "canvas")
        renders = os.path.join(work, "ramp_renders")
        azimuths = [0.0, 180.0]
        key = canvas_plane.find_role(scene, "key_light")
        key_before = list(key.rotation_quaternion)
        compare.render_sweep(bpy.context, obj, azimuths, RAMP_ELEVATION, renders, RAMP_SAMPLES)
        relief_px = compare.relief_pixels(obj)
        result = compare.compare(core, folder, renders, azimuths, RAMP_ELEVATION, os.path.join(work, "ramp_compare"),
                                 relief_px=relief_px)
        inner = (slice(BORDER, h - BORDER), slice(BORDER, w - BORDER))
        out = {"relief_px": relief_px, "expected_relief_px": RAMP_THICKNESS_MM / pixel_mm,
               "key_restored": key_before == list(key.rotation_quaternion),
               "engine_after": scene.render.engine, "azimuths": {}}
        for az in azimuths:
            relief = reading.read_exr(os.path.join(renders, "relief_{:03.0f}.exr".format(az)))[0][..., :3]
            flat = reading.read_exr(os.path.join(renders, "flat_{:03.0f}.exr".format(az)))[0][..., :3]
            s3d = (luminance(relief) / luminance(flat) - 1.0)[inner]
            lit = bump_lighting(np.full((h, w, 3), 0.5, np.float32), height, math.radians(az),
                                math.radians(RAMP_ELEVATION), relief=relief_px)
            s2d = (luminance(srgb_to_linear(lit)) / luminance(grey) - 1.0)[inner]
            entry = next(e for e in result["azimuths"] if e["azimuth_deg"] == az)
            out["azimuths"]["{:g}".format(az)] = {
                "s3d_mean": float(s3d.mean()), "s3d_positive": float(np.mean(s3d > 0)),
                "s3d_negative": float(np.mean(s3d < 0)),
                "s3d_top_rows": float(s3d[:8].mean()), "s3d_bottom_rows": float(s3d[-8:].mean()),
                "flat_mean": float(luminance(flat).mean()),
                "bump_pearson_here": pearson(s3d, s2d),
                "json": entry["models"]}
        return out

    @check
    def operator():
        """paint_relief.render_comparison on the ramp scene (headless: execute), and its errors."""
        out_dir = os.path.join(work, "operator_compare")
        settings.compare_azimuths = 1
        settings.compare_samples = 2
        settings.compare_output_dir = out_dir
        result, error = run_op(ops.render_comparison)
        files = sorted(os.listdir(out_dir)) if os.path.isdir(out_dir) else []
        renders = sorted(os.listdir(os.path.join(out_dir, "renders"))) if "renders" in files else []
        blocker = os.path.join(work, "a_file")
        with open(blocker, "w") as f:
            f.write("a file where a folder should be")
        settings.compare_output_dir = os.path.join(blocker, "comparison")
        bad_result, bad_error = run_op(ops.render_comparison)
        settings.compare_output_dir = out_dir
        obj = canvas_plane.find_role(scene, "canvas")
        bpy.data.objects.remove(obj)
        poll_without_canvas = ops.render_comparison.poll()
        return {"result": result, "error": error, "files": files, "renders": renders,
                "bad_result": bad_result, "bad_error": bad_error, "blocker": blocker,
                "poll_without_canvas": poll_without_canvas}

    RESULTS["blender_version"] = list(bpy.app.version)
    print("RESULTS " + json.dumps(RESULTS), flush=True)


if __name__ == "__main__":
    if not os.environ.get("BLENDER_USER_RESOURCES"):
        sys.exit("BLENDER_USER_RESOURCES is not set: refusing to touch a real user profile")
    main(sys.argv[1])
