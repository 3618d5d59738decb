# SPDX-License-Identifier: GPL-3.0-or-later
"""The Grease Pencil round trip: a painting's strokes to a Grease Pencil object, and its strokes, as the artist
left them, laid again into a new painting.

``make_strokes`` reads a painted folder's strokes.json through
``core.drawn_strokes`` and makes the object (``grease_pencil``).
``lay_strokes`` reads the object's strokes back (moved, deleted,
recoloured, drawn anew in its layer; ``prepare_lay``) and lays them in one call of
``core.lay_drawn`` into a new painted folder (``lay_work``, which touches no
Blender data, so the panel runs it in a worker thread); then the object shows that
painting's strokes (every stroke now one of its list), the scene's painting
is the new folder, and the canvas the object sits on, if any, shows the new
maps, rebuilt in place (its size, thickness and relief method kept).
"""

import os

import bpy

from .. import values
from ..scene import canvas_plane
from . import grease_pencil


def _core():
    from ... import core

    return core


def make_strokes(context, folder, width_cm, thickness_mm, frame_start, frame_end):
    """The Grease Pencil object of painted ``folder``'s strokes (``grease_pencil.strokes_object``); returns
    (object, stroke count). ``core.PaintReliefError`` (one sentence) when the folder holds no stroke list."""
    core = _core()
    drawn = core.drawn_strokes(os.path.normpath(bpy.path.abspath(folder)))
    obj = grease_pencil.strokes_object(context, folder, drawn, width_cm, thickness_mm / 1000.0, frame_start,
                                       frame_end)
    return obj, len(drawn)


def default_output(folder):
    """The new painted folder a lay of ``folder``'s strokes goes to: ``<folder>_laid_NNN`` beside it."""
    folder = os.path.normpath(folder)
    return values.next_painting_folder(os.path.dirname(folder), os.path.basename(folder) + "_laid")


def _relief_method(canvas):
    if canvas.modifiers.get(canvas_plane.DISPLACE_MODIFIER) is not None:
        return "MESH"
    if canvas.modifiers.get(canvas_plane.SUBDIVISION_MODIFIER) is not None:
        return "CYCLES_ADAPTIVE"
    return "NORMAL_MAP"


def lay_strokes(context, obj, output_dir=None, reference=None, progress=None, cancel=None):
    """Lay the strokes of the Grease Pencil object ``obj`` into a new painted folder (``output_dir``, else
    ``default_output``) against ``reference`` (else the photograph the painting's report.json names); returns
    core's report. Raises ``grease_pencil.StrokesError`` or ``core.PaintReliefError`` (one sentence; Cancelled
    when ``cancel()`` says so) with nothing written and the scene unchanged: ``prepare_lay``, then ``lay_work``,
    then ``show_laid``."""
    folder, drawn, out = prepare_lay(obj, output_dir)
    report = lay_work(folder, drawn, out, reference)(progress, cancel)
    show_laid(context, obj, folder, report)
    return report


def prepare_lay(obj, output_dir=None):
    """(painted folder, drawn strokes, output folder) of a lay of ``obj``'s strokes, read from Blender's data:
    what ``lay_work`` needs, so it can run away from it. ``grease_pencil.StrokesError`` (one sentence) when the
    object cannot be read."""
    core = _core()
    folder = obj.get(canvas_plane.PAINTING_DIR_KEY)
    drawn = grease_pencil.read_drawn(obj, core)
    if not folder:
        raise grease_pencil.StrokesError("{} does not remember its painted folder: make it again with Strokes as "
                                         "Grease Pencil.".format(obj.name))
    return folder, drawn, os.path.normpath(output_dir) if output_dir else default_output(folder)


def lay_work(folder, drawn, out, reference=None):
    """work(progress, cancel): ``core.lay_drawn`` of ``prepare_lay``'s values, touching no Blender data (it may
    run in a worker thread); returns core's report."""
    def work(progress, cancel):
        return _core().lay_drawn(folder, drawn, out, reference_path=reference, progress=progress, cancel=cancel)
    return work


def show_laid(context, obj, folder, report):
    """Show the painting ``report`` (core's, of a lay of ``folder``'s strokes) laid: ``obj`` holds its strokes,
    the scene's painting is its folder, the canvas ``obj`` sits on shows its maps."""
    core = _core()
    out = report["output_dir"]
    canvas = obj.parent if obj.parent is not None and obj.parent.get(canvas_plane.ROLE_KEY) == "canvas" else None
    if canvas is not None and canvas.get(canvas_plane.PAINTING_DIR_KEY) == os.path.normpath(folder):
        plane = tuple(obj[grease_pencil.PLANE_KEY])
        canvas[canvas_plane.PAINTING_DIR_KEY] = os.path.normpath(out)
        canvas_plane.build_canvas(context, out, 100.0 * plane[0], 1000.0 * canvas_plane.canvas_thickness(canvas),
                                  _relief_method(canvas))
    lift = grease_pencil.lift_of(obj)
    frame = grease_pencil.paint_frame(obj)
    grease_pencil.write_strokes(frame, core.drawn_strokes(out), tuple(obj[grease_pencil.PLANE_KEY]), lift)
    obj[canvas_plane.PAINTING_DIR_KEY] = os.path.normpath(out)
    settings = getattr(context.scene, "paint_relief", None)
    if settings is not None:
        settings.painting_dir = out
