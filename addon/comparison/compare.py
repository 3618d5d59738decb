# SPDX-License-Identifier: GPL-3.0-or-later
"""The lighting comparison's Blender half: render the canvas with and without relief under a light sweep.

For every light azimuth (degrees, the painter's convention: from the image's
right edge towards its bottom edge) the key light is turned there and the
canvas is rendered twice with Cycles: with its paint relief
(``relief_AAA.exr``) and with the relief switched off (``flat_AAA.exr``),
scene-linear float RGB OpenEXR at exactly the map's pixel size, 'Standard'
view transform. ``core.evaluation.comparison.run_comparison`` then compares them with
the painter's 2-D lighting models.

The same code serves the ``paint_relief.render_comparison`` operator and
``sample_scenes/compare.py``. The sweep is a generator (:func:`sweep_steps`)
that renders one image per step, so the interactive operator can advance it
from a modal timer, update the progress bar between renders and stop on Esc;
:func:`render_sweep` runs it to the end. Every render setting, the key
light, the other lights' visibility and the relief are restored afterwards,
also when the sweep fails or is cancelled.
"""

import math
import os

import bpy
from mathutils import Vector

from .. import values
from ..scene import canvas_plane, lighting

# Cycles settings of the comparison renders.
PIXEL_FILTER = "BOX"
"""A box pixel filter one pixel wide: each render pixel is the mean over its own map pixel's area."""
PIXEL_FILTER_WIDTH = 1.0
RENDER_SEED = 0


class SweepError(Exception):
    """The sweep cannot run or a render failed; the message is one sentence."""


def cycles_attributes(scene, denoise=False):
    """(owner, attribute, value) of the Cycles, film and view settings of a pixel-true render (the comparison's
    and the relit film's): CPU, no adaptive sampling, ``denoise`` or not, a fixed seed, a one-pixel box filter,
    100 % size, no border, compositing or sequencer, the 'Standard' view with no look, exposure or curve."""
    render, cycles = scene.render, scene.cycles
    view = scene.view_settings
    return [
        (render, "engine", "CYCLES"),
        (cycles, "device", "CPU"),
        (cycles, "use_adaptive_sampling", False),
        (cycles, "use_denoising", bool(denoise)),
        (cycles, "seed", RENDER_SEED),
        (cycles, "use_animated_seed", False),
        (cycles, "pixel_filter_type", PIXEL_FILTER),
        (cycles, "filter_width", PIXEL_FILTER_WIDTH),
        (render, "resolution_percentage", 100),
        (render, "pixel_aspect_x", 1.0),
        (render, "pixel_aspect_y", 1.0),
        (render, "film_transparent", False),
        (render, "use_border", False),
        (render, "use_compositing", False),
        (render, "use_sequencer", False),
        (view, "view_transform", "Standard"),
        (view, "look", "None"),
        (view, "exposure", 0.0),
        (view, "gamma", 1.0),
        (view, "use_curve_mapping", False),
    ]


def _render_attributes(scene):
    """(owner, attribute, value) of every setting :func:`configure_render` sets, in the order it sets them."""
    image = scene.render.image_settings
    settings = cycles_attributes(scene)
    if hasattr(image, "media_type"):  # Blender 5.0: choose the media type before the format
        settings.append((image, "media_type", "IMAGE"))
    settings += [
        (image, "file_format", "OPEN_EXR"),
        (image, "color_mode", "RGB"),
        (image, "color_depth", "32"),
        (image, "exr_codec", "ZIP"),
    ]
    if hasattr(image, "color_management"):
        settings.append((image, "color_management", "FOLLOW_SCENE"))
    return [(owner, name, value) for owner, name, value in settings if hasattr(owner, name)]


def configure_render(scene, samples):
    """Set Cycles (CPU, ``samples`` samples, no denoising, fixed seed) and pixel-true EXR output.

    Render size 100 % of the resolution (the camera sets it to the map size),
    'Standard' view transform, look None, exposure 0, gamma 1, float RGB
    OpenEXR (scene-linear). Returns the previous values for :func:`restore`.
    """
    previous = []
    for owner, name, value in _render_attributes(scene):
        previous.append((owner, name, getattr(owner, name)))
        setattr(owner, name, value)
    previous.append((scene.cycles, "samples", scene.cycles.samples))
    scene.cycles.samples = int(samples)
    return previous


def restore(previous):
    """Put back values saved as (owner, attribute, value), in their order; skip any that no longer apply."""
    for owner, name, value in previous:
        try:
            setattr(owner, name, value)
        except (AttributeError, TypeError, ValueError):
            pass


def key_brightness(key):
    """The key Sun's brightness on a flat canvas now (the inverse of lighting.sun_strength)."""
    towards = key.matrix_world.to_3x3() @ Vector((0.0, 0.0, 1.0))
    return key.data.energy * max(towards.normalized().z, lighting.MIN_SINE) / math.pi


def aim_key(key, azimuth_deg, elevation_deg, brightness, distance):
    """Turn the key Sun to ``azimuth_deg`` (the painter's convention) and ``elevation_deg``."""
    elevation = math.radians(elevation_deg)
    lighting.aim_sun(key, math.radians(azimuth_deg), elevation, distance)
    key.data.energy = lighting.sun_strength(brightness, elevation)


def render_still(scene, path, error=SweepError):
    """Render the scene's camera at its current frame to ``path``, in the scene's file format (written under a
    temporary name with the same extension, then renamed); ``error`` (one sentence) when Cycles writes nothing."""
    folder, name = os.path.split(path)
    stem, extension = os.path.splitext(name)
    temp = os.path.join(folder, ".{}.tmp-{}{}".format(stem, os.getpid(), extension))
    scene.render.filepath = temp
    try:
        bpy.ops.render.render(write_still=True)
        if not os.path.isfile(temp):
            raise error("Cycles did not write {}.".format(path))
        os.replace(temp, path)
    finally:
        if os.path.exists(temp):
            os.remove(temp)


def check_sweep(scene, canvas_obj, azimuths_deg, elevation_deg, samples):
    """Raise SweepError (one sentence) when the scene or the arguments cannot make a sweep; return the key light."""
    if canvas_obj is None:
        raise SweepError("The scene has no Paint Relief canvas: build the canvas first.")
    if canvas_plane.MAP_SIZE_KEY not in canvas_obj:
        raise SweepError("Canvas {} has no map size: build the canvas again.".format(canvas_obj.name))
    if len(azimuths_deg) == 0:
        raise SweepError("The light sweep needs at least one azimuth.")
    try:
        values.check_render_names(azimuths_deg)
    except ValueError as error:
        raise SweepError(str(error)) from None
    if not 0.0 < float(elevation_deg) <= 90.0:
        raise SweepError("The light elevation must be above 0 and at most 90 degrees, got {:g}.".format(elevation_deg))
    if int(samples) < 1:
        raise SweepError("Cycles needs at least 1 sample, got {}.".format(samples))
    key = canvas_plane.find_role(scene, "key_light")
    if key is None or key.type != "LIGHT":
        raise SweepError("The scene has no Paint Relief key light: add the lights first.")
    if scene.camera is None or scene.camera.get(canvas_plane.ROLE_KEY) != "camera":
        raise SweepError("The scene has no Paint Relief camera: add the camera first.")
    return key


def sweep_steps(context, canvas_obj, azimuths_deg, elevation_deg, renders_dir, samples):
    """Render the sweep one image per step; yields (renders done, renders in all, message) before each render.

    azimuths_deg: the painter's convention; elevation_deg above the canvas.
    Writes ``renders_dir/relief_AAA.exr`` and ``flat_AAA.exr``. Only the key
    light shines (other lights are hidden from the render meanwhile); the key
    keeps the brightness it gives a flat canvas. The render size is the
    canvas's map size during the sweep. Closing the generator early
    (cancel) or an error restores the scene just the same. Raises SweepError.
    """
    scene = context.scene
    azimuths = [float(a) for a in azimuths_deg]
    key = check_sweep(scene, canvas_obj, azimuths, elevation_deg, samples)
    try:
        os.makedirs(renders_dir, exist_ok=True)
    except OSError as error:
        raise SweepError("Cannot write to the renders folder {}: {}.".format(
            renders_dir, (error.strerror or str(error)).lower())) from None
    total = 2 * len(azimuths)
    previous = configure_render(scene, samples)
    previous.append((scene.render, "filepath", scene.render.filepath))
    # Render size = map size for the sweep only: the scene's own size comes back afterwards.
    map_w, map_h = (int(v) for v in canvas_obj[canvas_plane.MAP_SIZE_KEY])
    previous += [(scene.render, "resolution_x", scene.render.resolution_x),
                 (scene.render, "resolution_y", scene.render.resolution_y)]
    scene.render.resolution_x, scene.render.resolution_y = map_w, map_h
    previous += [(key, "rotation_mode", key.rotation_mode), (key, "rotation_quaternion", key.rotation_quaternion.copy()),
                 (key, "rotation_euler", key.rotation_euler.copy()), (key, "location", key.location.copy()),
                 (key.data, "energy", key.data.energy)]
    for obj in scene.objects:
        if obj.type == "LIGHT" and obj != key:
            previous.append((obj, "hide_render", obj.hide_render))
            obj.hide_render = True
    previous.append((key, "hide_render", key.hide_render))
    key.hide_render = False
    brightness = key_brightness(key)
    distance = max(canvas_obj.dimensions[:2])
    done = 0
    try:
        for azimuth in azimuths:
            aim_key(key, azimuth, elevation_deg, brightness, distance)
            for kind in ("relief", "flat"):
                yield done, total, "Rendering the {} canvas, light at {:g} degrees ({}/{})".format(
                    kind, azimuth, done + 1, total)
                canvas_plane.set_relief(canvas_obj, kind == "relief")
                render_still(scene, os.path.join(renders_dir, values.render_file_name(kind, azimuth)))
                done += 1
    finally:
        canvas_plane.set_relief(canvas_obj, True)
        restore(previous)


def run_steps(steps, progress, cancel, cancelled, before=None):
    """Run the render generator ``steps`` (it yields (done, total, message) before each render) to its end, closed
    whatever happens (its ``finally`` restores the scene): ``before()`` first at each step when given, then
    ``cancel()`` asked and, when it returns True, the exception ``cancelled(done, total)`` raised, else
    ``progress(done / total, message)``."""
    try:
        for done, total, message in steps:
            if before is not None:
                before()
            if cancel is not None and cancel():
                raise cancelled(done, total)
            if progress is not None:
                progress(done / total, message)
    finally:
        steps.close()


def render_sweep(context, canvas_obj, azimuths_deg, elevation_deg, renders_dir, samples, progress=None, cancel=None):
    """Run :func:`sweep_steps` to the end; return the list of files written.

    progress(fraction, message) is called before each render; cancel() is
    asked before each render and, when it returns True, the sweep stops
    (scene restored) and SweepError says so.
    """
    steps = sweep_steps(context, canvas_obj, azimuths_deg, elevation_deg, renders_dir, samples)
    run_steps(steps, progress, cancel, lambda done, total: SweepError(
        "The light sweep was cancelled after {} of {} renders.".format(done, total)))
    if progress is not None:
        progress(1.0, "Rendered {} images".format(2 * len(azimuths_deg)))
    return [os.path.join(renders_dir, values.render_file_name(kind, a)) for a in azimuths_deg for kind in ("relief", "flat")]


def relief_pixels(canvas_obj):
    """The canvas's relief in the 2-D bump model's unit (pixel widths per height unit)."""
    map_w = int(canvas_obj[canvas_plane.MAP_SIZE_KEY][0])
    width_m = canvas_obj.dimensions[0]
    return canvas_plane.canvas_thickness(canvas_obj) / (width_m / map_w)


def compare(core_package, painting_dir, renders_dir, azimuths_deg, elevation_deg, out_dir, relief_px=None,
            progress=None):
    """Call ``core.evaluation.comparison.run_comparison`` of ``core_package`` (the extension's ``core``); return its dict.

    ``relief_px`` (the canvas's relief for the 2-D bump model) is passed when
    the comparison accepts it.
    """
    import importlib
    import inspect

    comparison = importlib.import_module(core_package.__name__ + ".evaluation.comparison")
    kwargs = {"progress": progress}
    if relief_px is not None and "relief_px" in inspect.signature(comparison.run_comparison).parameters:
        kwargs["relief_px"] = float(relief_px)
    return comparison.run_comparison(painting_dir, renders_dir, list(azimuths_deg), float(elevation_deg), out_dir,
                                     **kwargs)
