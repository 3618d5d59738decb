"""A painting's time-lapse written as a painted shot's folder: the painting being painted, frame by frame.

``core paint --timelapse N`` (``paint_file(..., timelapse=N)``) writes
``OUTDIR/timelapse/`` with the painting: for frames 1 .. N, the files a
painted shot's frame has (``shot_files.frame_file_names``:
``painting_0001.png``, ``color_0001.exr``, ``height_0001.exr``,
``opacity_0001.exr``, ``orientation_0001.exr``), and a shot's report.json
(format ``FORMAT`` under "timelapse"), so Build Canvas makes an animated relief
canvas of it and the relit film (``sample_scenes/animate.py``) renders it.
The frames come as arrays (``strokes.snapshots.Frame``); the last is the
painting's own, so its maps hold the painting's color.exr, height.exr and
opacity.exr values exactly. The frames are written uncompressed
(``raw_files``: half-float EXRs and PNGs with stored rows, 13 bytes a pixel a
frame), about four times faster than compressed through OpenImageIO; a
hundred frames are written in about the painting's own time (bench/timelapse.py);
orientation is the painting's for every frame (one file written, hard-linked
under every frame's name, ``shared``).
"""

from __future__ import annotations

import concurrent.futures
import functools
import os
import shutil
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Optional, Tuple

import numpy as np

from .. import tuning
from ..colour import srgb_to_linear
from ..errors import OutputError, ParameterError, plain_cause
from ..progress import Stage
from ..version import __version__
from . import quiet, raw_files, writing
from .shot_files import REPORT_FILE, frame_file_names

TIMELAPSE_DIR = "timelapse"
"""The folder of the time-lapse inside a painting's output folder."""

FORMAT = 1
"""The time-lapse report's format (report.json's "timelapse" → "format")."""

MAX_FRAMES = 1000
"""The most frames a time-lapse takes."""

FRAME_BYTES_PER_PIXEL = 13
"""A frame's bytes on disk per pixel: colour 6, height 2, opacity 2 (half floats), the PNG 3."""

COLOUR_CHANNELS = ("R", "G", "B")
"""The colour EXR's channels."""

WAIT_SECONDS = 0.1
"""Seconds between looks at the cancel callback while the frames are written."""

STILL_MOTION = "none"
"""report.json's "motion" of a time-lapse: its frames are one still picture (``motion.source.STILL_MOTION``)."""


def check_frames(frames, what: str = "The time-lapse") -> int:
    """``frames`` as an int when it is a whole number from 1 to ``MAX_FRAMES``; ParameterError in one sentence
    otherwise."""
    if isinstance(frames, bool) or not isinstance(frames, (int, np.integer)) or not 1 <= int(frames) <= MAX_FRAMES:
        raise ParameterError(f"{what} takes a whole number of frames from 1 to {MAX_FRAMES}, got {frames!r}.")
    return int(frames)


def shared(source: Path, target: Path) -> None:
    """``target`` made the file ``source`` (the orientation map every frame has): a hard link, which takes no
    bytes (the painter replaces files by renaming new ones over them, never writes into them), or a copy where
    the file system has no hard links. OSError when neither can be made."""
    try:
        os.link(source, target)
    except OSError:
        shutil.copyfile(source, target)


class FrameFiles:
    """A time-lapse frame's files held as their bytes (``raw_files``): colour (half-float scene-linear R, G, B),
    height and opacity EXRs and the PNG, from a bare canvas of ``canvas_colour`` (sRGB triple) and zero height
    and opacity. ``apply`` stores a snapshot delta's pixels, ``fill`` the painting's, ``write`` writes frame k."""

    def __init__(self, shape: Tuple[int, int], canvas_colour):
        height, width = shape
        self.width = int(width)
        self.colour = raw_files.HalfPlanes(height, width, COLOUR_CHANNELS)
        self.height = raw_files.HalfPlanes(height, width, ("Y",))
        self.opacity = raw_files.HalfPlanes(height, width, ("Y",))
        self.png = raw_files.StoredRows(height, width)
        bare = np.clip(np.asarray(canvas_colour, np.float32), 0.0, 1.0).astype(np.float16).view(np.uint16)
        linear, png = half_tables()
        for c, name in enumerate(COLOUR_CHANNELS):
            self.colour.plane(name)[...] = linear[bare[c]]
        self.png.pixels[...] = png[bare]

    def apply(self, delta) -> None:
        """Store a ``strokes.snapshots.Delta``'s pixels: its float16 sRGB colour converted by ``half_tables`` (the
        numbers converting it gives), its height and opacity as they are."""
        rows, columns = np.divmod(delta.index, self.width)
        bits = delta.colour.view(np.uint16)
        linear, png = half_tables()
        for c, name in enumerate(COLOUR_CHANNELS):
            self.colour.plane(name)[rows, columns] = linear[bits[:, c]]
        self.png.pixels[rows, columns] = png[bits]
        self.height.plane("Y")[rows, columns] = delta.height.view(np.uint16)
        self.opacity.plane("Y")[rows, columns] = delta.opacity.view(np.uint16)

    def fill(self, colour: np.ndarray, height: np.ndarray, opacity: np.ndarray) -> None:
        """Store a whole painting: colour (H, W, 3) sRGB [0, 1], height and opacity (H, W), float32. The PNG's
        8-bit values are ``floor(v * 255 + 0.5)`` clipped to [0, 255], as ``writing.write_png`` quantises."""
        srgb = np.nan_to_num(np.asarray(colour, np.float32), nan=0.0)
        self.png.pixels[...] = np.clip(np.floor(srgb * np.float32(255.0) + np.float32(0.5)), 0.0, 255.0)
        linear = srgb_to_linear(srgb).astype(np.float16).view(np.uint16)
        for c, name in enumerate(COLOUR_CHANNELS):
            self.colour.plane(name)[...] = linear[..., c]
        self.height.plane("Y")[...] = np.asarray(height, np.float16).view(np.uint16)
        self.opacity.plane("Y")[...] = np.asarray(opacity, np.float16).view(np.uint16)

    def coverage(self) -> float:
        """The mean opacity of the frame."""
        return float(np.mean(self.opacity.plane("Y").view(np.float16), dtype=np.float64))

    def write(self, folder: Path, number: int, orientation: Path, attributes: dict) -> None:
        """Write the frame's files into ``folder`` as frame ``number`` (``frame_file_names``), the EXRs with the
        header ``attributes`` and the frame's number; ``orientation``, the orientation map written once, is
        hard-linked under the frame's name (``shared``)."""
        names = frame_file_names(number, False)
        mine = dict(attributes, **{"paint_relief:frame": str(number)})
        self.png.write(folder / names[0])
        self.colour.write(folder / names[1], mine)
        self.height.write(folder / names[2], mine)
        self.opacity.write(folder / names[3], mine)
        target = folder / names[4]
        if orientation != target:
            try:
                shared(orientation, target)
            except OSError as exc:
                cause = plain_cause(exc)
                raise OutputError(f"Cannot write {target}: {cause}.", path=target, cause=cause) from exc


def write_timelapse(folder, snapshots, painting: tuple, canvas_colour, orientation_map: np.ndarray,
                    attributes: dict, source: str, params_dict: dict, stage: Optional[Stage] = None) -> dict:
    """Write the time-lapse ``snapshots`` (``strokes.snapshots.Snapshots``) caught into the new folder ``folder``;
    return its summary for the painting's report.

    painting: its (colour (H, W, 3) sRGB [0, 1], height, opacity (H, W)) float32, the last frame; canvas_colour:
    the bare canvas's sRGB, before the first stroke; orientation_map (H, W) radians [0, pi); attributes: the maps'
    header (``export.map_attributes``); source: the picture painted (report.json's "input" for every frame);
    params_dict: the painting's parameters. The frames are written by ``tuning.WRITERS`` threads, each with
    ``FrameFiles`` of its own that every delta is stored in, each writing every WRITERS-th frame.
    report.json is a painted shot's (``shot_files.is_shot_report``), frames numbered 1 .. N, "motion"
    ``STILL_MOTION``, with under "timelapse" the format, the painting's strokes, the snapshot step and bytes,
    and per frame the strokes shown, the mean opacity ("coverage") and each file's bytes. OutputError (one
    sentence naming the file) when a file cannot be written. ``stage`` (optional) hears "Time-lapse: frame k of
    N" and is polled for cancel while the frames are written and once all are (Cancelled: the caller removes
    the folder).
    """
    clock = time.perf_counter()
    folder = Path(folder)
    try:
        folder.mkdir()
    except OSError as exc:
        raise OutputError(f"Cannot write {folder}: {plain_cause(exc)}.", path=folder, cause=plain_cause(exc)) from exc
    count = snapshots.frame_count
    height, width = np.shape(painting[1])
    orientation = folder / frame_file_names(1, False)[4]
    writing.write_exr(orientation, orientation_map, channels=("Y",), half=True, attributes=attributes)
    shown = list(snapshots.frame_deltas())
    steps = [deltas for _, deltas in shown]
    per_frame = [{"frame": k, "strokes": int(strokes)}
                 for k, strokes in enumerate([strokes for strokes, _ in shown] + [snapshots.count], start=1)]
    writers = max(1, min(tuning.WRITERS, count))
    stop = threading.Event()

    def write_every(first: int) -> None:
        files = FrameFiles((height, width), canvas_colour)
        for k in range(count):
            if stop.is_set():
                return
            if k < len(steps):
                for delta in steps[k]:
                    files.apply(delta)
            else:
                files.fill(*painting)
            if k % writers == first:
                files.write(folder, k + 1, orientation, attributes)
                per_frame[k]["coverage"] = round(files.coverage(), 6)
                done.append(k)

    done: list = []
    with quiet.captured(), ThreadPoolExecutor(writers) as pool:
        futures = [pool.submit(write_every, first) for first in range(writers)]
        try:
            while True:
                if stage is not None:
                    stage.check()
                    stage.report(1.0, f"Time-lapse: frame {len(done)} of {count}")
                ended, _ = concurrent.futures.wait(futures, timeout=WAIT_SECONDS, return_when="FIRST_EXCEPTION")
                for future in ended:
                    future.result()                 # a writer's failure, raised here (the others stop)
                if len(ended) == len(futures):
                    break
        finally:
            stop.set()
    if stage is not None:
        stage.check()
    for entry in per_frame:
        entry["files"] = {name: {"bytes": (folder / name).stat().st_size}
                          for name in frame_file_names(entry["frame"], False)}
    summary = {"format": FORMAT, "folder": TIMELAPSE_DIR, "frames": count, "strokes": int(snapshots.count),
               "step": snapshots.step, "snapshot_bytes": snapshots.held_bytes(),
               "seconds": round(time.perf_counter() - clock, 4)}
    report = {"version": __version__, "sequence": "timelapse", "timelapse": summary,
              "input": [str(source)] * count, "frame_count": count, "width": int(width), "height": int(height),
              "motion": STILL_MOTION, "fade_frames": 0, "params": params_dict,
              "frames": list(range(1, count + 1)), "per_frame": per_frame, "complete": True}
    writing.write_json(folder / REPORT_FILE, report)
    return summary


@functools.cache
def half_tables() -> tuple:
    """(linear, png): for every float16 bit pattern v of an sRGB value, ``srgb_to_linear(v)`` as float16 and the
    8-bit PNG value ``floor(v * 255 + 0.5)`` clipped to [0, 255] (NaN 0), as ``write_png`` quantises: a frame
    held as float16 is converted by looking its values up, with the same numbers as converting it."""
    values = np.arange(1 << 16, dtype=np.uint16).view(np.float16).astype(np.float32)
    finite = np.nan_to_num(values, nan=0.0, posinf=0.0, neginf=0.0)
    with np.errstate(over="ignore", invalid="ignore"):
        png = np.clip(np.floor(np.nan_to_num(values, nan=0.0) * np.float32(255.0) + np.float32(0.5)), 0.0, 255.0)
        linear = srgb_to_linear(finite).astype(np.float16)     # beyond the half range (never an sRGB in [0, 1]): inf
    return linear, png.astype(np.uint8)
