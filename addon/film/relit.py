# SPDX-License-Identifier: GPL-3.0-or-later
"""The relit painted film's Blender half: every frame of the animated canvas rendered under the raking light.

For each painted frame N the scene goes to frame N (the animated canvas
shows that frame's colour and relief) and Cycles renders the camera's view
to ``relit/NNNN.png``: 8-bit sRGB PNG, 'Standard' view transform, a fixed
render seed (the noise does not change from frame to frame on its own).
:func:`film_steps` renders one frame per step, so an interactive operator
can advance it from a timer and stop between frames; :func:`render_film`
runs it to the end. Every render setting it changes, the output path and
the scene's frame are put back afterwards, also when it fails or is cancelled.

:func:`encode_movie` puts a folder of numbered PNG frames into an MP4 (H.264)
with Blender's own FFmpeg, through the Sequencer of a scene of its own.
"""

import os
import time

import bpy

from ..comparison.compare import cycles_attributes, render_still, restore, run_steps
from ..scene import animated, canvas_plane

MOVIE_FPS = 10
"""Frames a second of the side-by-side MP4 (as the GIF)."""


class FilmError(Exception):
    """The film cannot be rendered or encoded; the message is one sentence."""


def frame_file(number):
    """``0016.png``: a film frame's file name (``core.evaluation.film_files``, the rule the film's figures read
    it by)."""
    from ...core.evaluation import film_files

    return film_files.frame_file(number)


def film_attributes(scene, samples, denoise):
    """(owner, attribute, value) of every setting the film's renders need, in the order they are set."""
    image = scene.render.image_settings
    settings = cycles_attributes(scene, denoise) + [(scene.cycles, "samples", int(samples)),
                                                    (scene.render, "use_motion_blur", False)]
    if hasattr(image, "media_type"):  # Blender 5.0: choose the media type before the format
        settings.append((image, "media_type", "IMAGE"))
    settings += [(image, "file_format", "PNG"), (image, "color_mode", "RGB"), (image, "color_depth", "8")]
    if hasattr(image, "color_management"):
        settings.append((image, "color_management", "FOLLOW_SCENE"))
    return [(owner, name, value) for owner, name, value in settings if hasattr(owner, name)]


def configure_film(scene, samples, denoise, size):
    """Set the film's render settings and the render size ``size`` (width, height) px; return the previous
    values for ``compare.restore``."""
    previous = []
    settings = film_attributes(scene, samples, denoise)
    settings += [(scene.render, "resolution_x", int(size[0])), (scene.render, "resolution_y", int(size[1]))]
    for owner, name, value in settings:
        previous.append((owner, name, getattr(owner, name)))
        setattr(owner, name, value)
    return previous


def check_film(scene, canvas_obj, samples):
    """Raise FilmError (one sentence) when the scene cannot render the film; return the canvas's frame numbers."""
    if canvas_obj is None or not animated.is_animated(canvas_obj):
        raise FilmError("The scene has no animated Paint Relief canvas: build the canvas from a painted sequence "
                        "first.")
    if int(samples) < 1:
        raise FilmError("Cycles needs at least 1 sample, got {}.".format(samples))
    if scene.camera is None:
        raise FilmError("The scene has no camera: add the Paint Relief camera first.")
    first, count = (int(v) for v in canvas_obj[animated.SEQUENCE_KEY])
    return list(range(first, first + count))


def film_steps(context, canvas_obj, relit_dir, samples, size, denoise=False, seconds=None):
    """Render the film one frame per step; yields (frames done, frames in all, message) before each render.

    size: (width, height) of the renders in px; denoise: Cycles' denoiser
    on. Writes ``relit_dir/NNNN.png`` for every frame N of the canvas's
    sequence; appends each render's seconds to the list ``seconds`` when
    given. Closing the generator early (cancel) or an error restores the
    scene just the same. Raises FilmError.
    """
    scene = context.scene
    frames = check_film(scene, canvas_obj, samples)
    try:
        os.makedirs(relit_dir, exist_ok=True)
    except OSError as error:
        raise FilmError("Cannot write to the film's folder {}: {}.".format(
            relit_dir, (error.strerror or str(error)).lower())) from None
    previous = [(scene.render, "filepath", scene.render.filepath)]
    previous += configure_film(scene, samples, denoise, size)
    frame_before = scene.frame_current
    try:
        for done, number in enumerate(frames):
            yield done, len(frames), "Rendering frame {} ({}/{})".format(number, done + 1, len(frames))
            scene.frame_set(number)
            start = time.perf_counter()
            render_still(scene, os.path.join(relit_dir, frame_file(number)), FilmError)
            if seconds is not None:
                seconds.append(time.perf_counter() - start)
    finally:
        restore(previous)
        scene.frame_set(frame_before)


def render_film(context, canvas_obj, relit_dir, samples, size, denoise=False, progress=None, cancel=None):
    """Run :func:`film_steps` to the end; return the seconds each frame's render took.

    progress(fraction, message) is called before each render ("Rendering
    frame N (k/n)") and after it ("Rendered frame N (k/n) in S s"); cancel()
    is asked before each render and, when it returns True, the film stops
    (scene restored; the frames rendered stay) and FilmError says so.
    """
    frames = check_film(context.scene, canvas_obj, samples)
    seconds = []

    def rendered():
        if progress is not None and seconds:
            done = len(seconds)
            progress(done / len(frames), "Rendered frame {} ({}/{}) in {:.1f} s".format(
                frames[done - 1], done, len(frames), seconds[-1]))

    steps = film_steps(context, canvas_obj, relit_dir, samples, size, denoise, seconds)
    run_steps(steps, progress, cancel, lambda done, total: FilmError(
        "The film was cancelled after {} of {} frames.".format(done, total)), before=rendered)
    rendered()
    return seconds


def canvas_map_size(canvas_obj):
    """(width, height) px of the canvas's maps."""
    return tuple(int(v) for v in canvas_obj[canvas_plane.MAP_SIZE_KEY])


# ---------------------------------------------------------------------------
# the movie


def movie_available():
    """True when this Blender was built with FFmpeg (it can write MP4 files)."""
    return bool(getattr(bpy.app.build_options, "codec_ffmpeg", False))


def _strips(editor):
    """The Sequencer's strip collection: ``strips`` from Blender 4.4, ``sequences`` before."""
    return editor.strips if hasattr(editor, "strips") else editor.sequences


def encode_movie(frames_dir, frames, size, path, fps=MOVIE_FPS):
    """Put the PNGs ``frames_dir/NNNN.png`` of ``frames`` (numbers, in order), each ``size`` (width, height) px,
    into the MP4 ``path`` (H.264) with Blender's FFmpeg; written under a temporary name, then renamed.

    Uses a scene of its own, removed afterwards; the user's scenes are not
    touched. Raises FilmError when this Blender has no FFmpeg or writes no file.
    """
    if not movie_available():
        raise FilmError("This Blender has no FFmpeg, so it cannot write {}.".format(path))
    folder = os.path.dirname(os.path.abspath(path))
    temp_dir = os.path.join(folder, ".movie.tmp-{}".format(os.getpid()))
    os.makedirs(temp_dir, exist_ok=True)
    scene = bpy.data.scenes.new("Paint Relief movie")
    try:
        editor = scene.sequence_editor_create()
        names = [frame_file(n) for n in frames]
        strip = _strips(editor).new_image(name="frames", filepath=os.path.join(frames_dir, names[0]), channel=1,
                                          frame_start=1)
        for name in names[1:]:
            strip.elements.append(name)
        render = scene.render
        render.resolution_x, render.resolution_y = (int(v) + int(v) % 2 for v in size)  # H.264 wants even sizes
        render.resolution_percentage = 100
        render.fps, render.fps_base = int(fps), 1.0
        scene.frame_start, scene.frame_end = 1, len(names)
        scene.view_settings.view_transform = "Standard"
        image = render.image_settings
        if hasattr(image, "media_type"):
            image.media_type = "VIDEO"
        image.file_format = "FFMPEG"
        render.ffmpeg.format = "MPEG4"
        render.ffmpeg.codec = "H264"
        render.ffmpeg.constant_rate_factor = "HIGH"
        render.use_sequencer = True
        render.filepath = os.path.join(temp_dir, "movie")
        bpy.ops.render.render(animation=True, scene=scene.name)
        written = [name for name in os.listdir(temp_dir) if name.lower().endswith(".mp4")]
        if len(written) != 1:
            raise FilmError("Blender's FFmpeg wrote no movie for {}.".format(path))
        os.replace(os.path.join(temp_dir, written[0]), path)
    finally:
        bpy.data.scenes.remove(scene)
        for name in os.listdir(temp_dir):
            os.remove(os.path.join(temp_dir, name))
        os.rmdir(temp_dir)
    return path
