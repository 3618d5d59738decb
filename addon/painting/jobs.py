# SPDX-License-Identifier: GPL-3.0-or-later
"""One paint at a time per scene: the scenes whose painting is running now.

A painting runs in a worker thread while Blender stays usable; a second
*Paint* in the same scene would write the same settings and folders, so it
is refused until the first ends. The record lives in memory only (never in
the .blend file), so a crash cannot leave a scene locked. ``SceneJob`` is
the end of a long operator that paints while its scene is so recorded.
"""

from ..modal_job import ModalJob

_running = set()


def _key(scene):
    return scene.as_pointer()


def is_running(scene):
    """True while a painting of ``scene`` runs."""
    return _key(scene) in _running


def begin(scene):
    """Record that a painting of ``scene`` starts and return its key for ``end``; ValueError (one sentence)
    when one runs already."""
    if _key(scene) in _running:
        raise ValueError("A painting is already running in scene {}: wait for it to finish or press Esc to "
                         "cancel it.".format(scene.name))
    _running.add(_key(scene))
    return _key(scene)


def end(scene):
    """Record that the painting of ``scene`` (a scene, or the key ``begin`` returned, which stays usable once
    the scene is gone) ended (finished, failed or cancelled)."""
    _running.discard(scene if isinstance(scene, int) else _key(scene))


class SceneJob(ModalJob):
    """A long operator (``ModalJob``) whose work runs in its ``_worker`` while its ``_scene`` is recorded as
    painting (Paint, Paint Object). ``_end`` records the scene free, takes the timer, the progress bar and the
    status text away, then calls ``clean()`` (nothing unless the operator has more to clean)."""

    def cancel(self, context):
        """Blender ends the operator (the file closes, or Blender quits): stop the worker and clean up."""
        self._worker.stop()
        self._end(context)

    def _end(self, context):
        end(self._scene)
        self.end_modal(context)
        self.clean()

    def clean(self):
        """What the operator leaves behind once it has ended (nothing here)."""
