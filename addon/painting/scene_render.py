# SPDX-License-Identifier: GPL-3.0-or-later
"""The scene's animation as footage for Paint Animation: its frames rendered one by one into multilayer EXR
files with the Vector pass, the scene's settings put back after every frame.

Each frame is one blocking ``bpy.ops.render.render(write_still=True)`` of
the scene's own engine, at the scene's own resolution, of one view layer
(the others are switched off for that render, which keeps the file to that
layer's passes; a single-layer render would keep stale layers of an earlier
render in the file, and Blender 5 then fails to write it). For that render
only:

- the output is a multilayer EXR, 32-bit float, ZIP, written under a hidden
  temporary name and renamed when complete (so the folder never holds part
  of a frame);
- the view layer's Vector pass is on and motion blur off (Cycles writes the
  pass only without it);
- compositing is off (with compositor nodes the file's first picture is the
  composite, which the painter would read instead of the render, and whose
  pixels need not match the Vector pass), the sequencer is off (its strips
  would replace the scene's picture), so are multiview, single-layer
  rendering and the burnt-in stamp.

``render_settings`` records each value before changing it and puts every one
back when the render ends, fails or is interrupted; the compositor's nodes,
the other passes and every other setting are never written. The frame the
scene shows is changed by ``scene.frame_set`` (as an animation render does, so
frame-change handlers run) and put back by ``RenderedFrames.close``.
"""

import contextlib
import os

import bpy

from .. import values

# The folder inside a painted sequence folder that holds the scene's rendered frames until the painting
# is complete (kept after a cancel, so that the next run goes on with the same footage).
RENDER_FOLDER = "scene_render"
RENDER_SUFFIX = ".exr"
_PARTIAL_PREFIX = ".rendering_"


class Changes:
    """Attribute changes that are put back in the order they were made.

    ``set(owner, name, value)`` records the attribute's value the first time
    it is changed; ``restore()`` writes every recorded value back, first
    recorded first (an image format before the depth it allows).
    """

    def __init__(self):
        self._saved = []
        self._seen = set()

    def set(self, owner, name, value):
        key = (owner.as_pointer(), name)
        if key not in self._seen:
            self._seen.add(key)
            self._saved.append((owner, name, getattr(owner, name)))
        if getattr(owner, name) != value:
            setattr(owner, name, value)

    def keep(self, owner, names):
        """Record ``names`` of ``owner`` (their current values) to be put back, without changing them."""
        for name in names:
            self.set(owner, name, getattr(owner, name))

    def restore(self):
        """Write every recorded value back; return the "owner.name" of those Blender refused (none expected)."""
        refused = []
        for owner, name, original in self._saved:
            try:
                if getattr(owner, name) != original:
                    setattr(owner, name, original)
            except (AttributeError, TypeError, ValueError, ReferenceError):
                refused.append(name)
        self._saved.clear()
        self._seen.clear()
        return refused


def _plain_names(struct, first=()):
    """The writable plain (not pointer or collection) settings of a Blender struct, those of ``first`` that
    it has first."""
    properties = struct.bl_rna.properties
    first = [name for name in first if name in properties]
    return first + [prop.identifier for prop in properties
                    if not prop.is_readonly and prop.type not in ("POINTER", "COLLECTION")
                    and prop.identifier != "rna_type" and prop.identifier not in first]


@contextlib.contextmanager
def render_settings(scene, view_layer, filepath):
    """Within the block, ``scene`` renders ``view_layer`` alone with its Vector pass into the multilayer EXR
    ``filepath`` (module docstring); every setting is put back when the block ends, however it ends."""
    changes = Changes()
    render = scene.render
    image_settings = render.image_settings
    try:
        # Every plain format setting is recorded, media type and file format first: setting a file format
        # adjusts the depth, mode or codec it allows, and (Blender 4.x) putting FFmpeg back resets its
        # container, so the FFmpeg settings are recorded too and put back after the format.
        changes.keep(image_settings, _plain_names(image_settings, first=("media_type", "file_format")))
        changes.keep(render.ffmpeg, _plain_names(render.ffmpeg))
        if "media_type" in image_settings.bl_rna.properties:  # Blender 5.x
            changes.set(image_settings, "media_type", "MULTI_LAYER_IMAGE")
        changes.set(image_settings, "file_format", "OPEN_EXR_MULTILAYER")
        changes.set(image_settings, "color_depth", "32")
        changes.set(image_settings, "exr_codec", "ZIP")
        changes.set(image_settings, "color_management", "FOLLOW_SCENE")
        changes.set(render, "filepath", values.escape_render_path(filepath, bpy.app.version >= (5, 0, 0)))
        changes.set(render, "use_file_extension", True)
        changes.set(render, "use_motion_blur", False)
        changes.set(render, "use_compositing", False)
        changes.set(render, "use_sequencer", False)
        changes.set(render, "use_single_layer", False)
        changes.set(render, "use_multiview", False)
        changes.set(render, "use_stamp", False)
        for layer in scene.view_layers:
            changes.set(layer, "use", layer == view_layer)
        changes.set(view_layer, "use_pass_vector", True)
        yield
    finally:
        refused = changes.restore()
        if refused:
            raise RuntimeError("Blender refused to put back the render settings {} after rendering the "
                               "animation.".format(", ".join(refused)))


def frame_path(folder, number):
    """The rendered file of scene frame ``number`` in ``folder``: ``folder/frame_0012.exr``."""
    return os.path.join(folder, values.render_file_stem(number) + RENDER_SUFFIX)


def render_frame(scene, view_layer, number, path):
    """Render scene frame ``number`` of ``view_layer`` into the multilayer EXR ``path`` (module docstring),
    written under a hidden name and renamed when complete. RuntimeError (one sentence) when Blender fails or
    writes no file."""
    folder = os.path.dirname(path)
    partial = os.path.join(folder, _PARTIAL_PREFIX + values.render_file_stem(number))
    written = partial + RENDER_SUFFIX
    if os.path.lexists(written):
        os.remove(written)
    scene.frame_set(number)
    with render_settings(scene, view_layer, partial):
        try:
            bpy.ops.render.render(write_still=True, scene=scene.name)
        except RuntimeError as error:
            raise RuntimeError("Rendering frame {} of scene {} failed: {}".format(
                number, scene.name, str(error).strip().splitlines()[0])) from None
    if not os.path.isfile(written):
        raise RuntimeError("Rendering frame {} of scene {} wrote no file {}.".format(number, scene.name, written))
    os.replace(written, path)


class RenderedFrames:
    """The scene's frame range rendered frame by frame into ``folder`` (frames already there are kept).

    ``render_next()`` renders one frame (a blocking render); ``close()``
    puts the scene's current frame back and removes unfinished files. The
    interactive operator calls ``render_next`` from a timer, so Blender stays
    responsive between frames and Esc stops after the frame in progress;
    headless, the same calls run in a loop.
    """

    def __init__(self, scene, view_layer, folder):
        self.scene_name = scene.name
        self.layer_name = view_layer.name
        self.folder = folder
        self.numbers = list(range(scene.frame_start, scene.frame_end + 1))
        for number in self.numbers:
            values.render_file_stem(number)  # refuses negative frames before anything is rendered
        self.paths = [frame_path(folder, number) for number in self.numbers]
        self._original_frame = (scene.frame_current, scene.frame_subframe)
        self._closed = False

    @property
    def done(self):
        """How many of the frames are rendered (complete files in the folder)."""
        return sum(1 for path in self.paths if os.path.isfile(path))

    def next_number(self):
        """The scene frame ``render_next`` renders next, None when every frame is rendered."""
        for number, path in zip(self.numbers, self.paths, strict=True):
            if not os.path.isfile(path):
                return number
        return None

    def scene(self):
        """The scene and its view layer; RuntimeError (one sentence) when either was removed meanwhile."""
        scene = bpy.data.scenes.get(self.scene_name)
        layer = scene.view_layers.get(self.layer_name) if scene is not None else None
        if layer is None:
            raise RuntimeError("Scene {} or its view layer {} was removed while its animation was being "
                               "rendered.".format(self.scene_name, self.layer_name))
        return scene, layer

    def render_next(self):
        """Render the next missing frame; return False when none is left."""
        number = self.next_number()
        if number is None:
            return False
        os.makedirs(self.folder, exist_ok=True)
        scene, layer = self.scene()
        render_frame(scene, layer, number, self.paths[self.numbers.index(number)])
        return True

    def close(self, restore_frame=True):
        """Put the scene's frame back (unless ``restore_frame`` is False: the file is closing, and a scene
        of the same name may belong to the next one) and remove a hidden unfinished file; safe to call twice."""
        if self._closed:
            return
        self._closed = True
        scene = bpy.data.scenes.get(self.scene_name) if restore_frame else None
        if scene is not None:
            frame, subframe = self._original_frame
            if (scene.frame_current, scene.frame_subframe) != (frame, subframe):
                scene.frame_set(frame, subframe=subframe)
        with contextlib.suppress(OSError):
            for name in os.listdir(self.folder):
                if name.startswith(_PARTIAL_PREFIX):
                    os.remove(os.path.join(self.folder, name))
