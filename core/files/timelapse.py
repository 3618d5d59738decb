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
opacity.exr values exactly. The EXRs are half floats, ``FRAME_COMPRESSION``
compressed (lossless, faster to write than zip), the PNGs zlib level
``PNG_LEVEL`` without row filters; orientation is the painting's for every
frame (one file written, hard-linked under every frame's name, ``shared``).
"""

from __future__ import annotations

import functools
import os
import shutil
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Iterable, Optional

import numpy as np

from .. import tuning
from ..colour import srgb_to_linear
from ..errors import OutputError, ParameterError, plain_cause
from ..progress import Stage
from ..version import __version__
from . import quiet, writing
from .shot_files import REPORT_FILE, frame_file_names

TIMELAPSE_DIR = "timelapse"
"""The folder of the time-lapse inside a painting's output folder."""

FORMAT = 1
"""The time-lapse report's format (report.json's "timelapse" → "format")."""

MAX_FRAMES = 1000
"""The most frames a time-lapse takes (each frame is about 10 bytes per pixel on disk)."""

FRAME_COMPRESSION = "rle"
"""The frames' EXR compression: lossless; a 1-megapixel frame's files take about 130 ms of processor time with it,
170 ms with zip (for 1.45 times zip's bytes) and 100 ms uncompressed (2.1 times)."""

PNG_LEVEL = 1
"""The frames' PNG zlib level."""

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


def frame_task(folder: Path, number: int, colour: np.ndarray, height: np.ndarray, opacity: np.ndarray,
               orientation: Path, attributes: dict):
    """The writer of frame ``number``'s files into ``folder``: colour (H, W, 3) sRGB [0, 1], height and opacity
    (H, W), float16 or float32; ``orientation`` the orientation map written once (``shared``). Returns the files'
    names in ``frame_file_names`` order."""
    names = frame_file_names(number, False)
    mine = dict(attributes, **{"paint_relief:frame": str(number)})

    def write() -> list:
        if colour.dtype == np.float16:
            linear_table, png_table = half_tables()
            bits = colour.view(np.uint16)
            png = writing.RowBlocks(colour.shape, lambda y0, y1: png_table[bits[y0:y1]])
            linear = writing.RowBlocks(colour.shape, lambda y0, y1: linear_table[bits[y0:y1]])
        else:
            srgb = np.asarray(colour, np.float32)
            png = srgb
            linear = writing.RowBlocks(srgb.shape, lambda y0, y1: srgb_to_linear(srgb[y0:y1]))
        writing.write_png(folder / names[0], png, level=PNG_LEVEL, filters=writing.PNG_UNFILTERED)
        writing.write_exr(folder / names[1], linear, half=True, attributes=mine, compression=FRAME_COMPRESSION)
        for name, values in ((names[2], height), (names[3], opacity)):
            writing.write_exr(folder / name, np.asarray(values, np.float32), channels=("Y",), half=True,
                              attributes=mine, compression=FRAME_COMPRESSION)
        target = folder / names[4]
        if orientation != target:
            try:
                shared(orientation, target)
            except OSError as exc:
                cause = plain_cause(exc)
                raise OutputError(f"Cannot write {target}: {cause}.", path=target, cause=cause) from exc
        return names
    return write


def write_timelapse(folder, frames: Iterable, count: int, orientation_map: np.ndarray, attributes: dict,
                    source: str, params_dict: dict, statistics: Optional[dict] = None,
                    stage: Optional[Stage] = None) -> dict:
    """Write a time-lapse of ``count`` frames into the new folder ``folder``; return its summary for the
    painting's report.

    frames: the ``strokes.snapshots.Frame`` of each frame in order (made as they are written, a few in memory at
    a time); orientation_map (H, W) radians [0, pi); attributes: the maps' header (``export.map_attributes``);
    source: the picture painted (report.json's "input" for every frame); params_dict: the painting's parameters.
    report.json is a painted shot's (``shot_files.is_shot_report``), frames numbered 1 .. ``count``, "motion"
    ``STILL_MOTION``, with under "timelapse" the format, the painting's strokes and the snapshot step, and per
    frame the strokes shown, the mean opacity ("coverage") and each file's bytes. ``statistics``: more to record
    under "timelapse" (the snapshots' bytes). OutputError (one sentence naming the file) when a file cannot be
    written. ``stage`` (optional) hears "Time-lapse: frame k of N" and is polled for cancel before each frame and
    once all are written (Cancelled: the caller removes the folder).
    """
    clock = time.perf_counter()
    folder = Path(folder)
    try:
        folder.mkdir()
    except OSError as exc:
        raise OutputError(f"Cannot write {folder}: {plain_cause(exc)}.", path=folder, cause=plain_cause(exc)) from exc
    orientation = folder / frame_file_names(1, False)[4]
    writing.write_exr(orientation, orientation_map, channels=("Y",), half=True, attributes=attributes,
                      compression=FRAME_COMPRESSION)
    per_frame, height, width = [], None, None
    batch = max(1, 2 * tuning.WRITERS)
    with quiet.captured(), ThreadPoolExecutor(tuning.WRITERS) as pool:
        pending = []
        for number, frame in enumerate(frames, start=1):
            if stage is not None:
                stage.check()
                stage.report(1.0, f"Time-lapse: frame {number} of {count}")
            height, width = frame.height.shape
            per_frame.append({"frame": number, "strokes": int(frame.strokes),
                              "coverage": round(float(np.mean(frame.opacity, dtype=np.float64)), 6)})
            pending.append(pool.submit(frame_task(folder, number, frame.colour, frame.height, frame.opacity,
                                                  orientation, attributes)))
            if len(pending) >= batch:
                pending.pop(0).result()
        for future in pending:
            future.result()
    if stage is not None:
        stage.check()
    if len(per_frame) != count:
        raise ValueError(f"The time-lapse was to have {count} frames, but {len(per_frame)} were made.")
    for entry in per_frame:
        entry["files"] = {name: {"bytes": (folder / name).stat().st_size}
                          for name in frame_file_names(entry["frame"], False)}
    numbers = [entry["frame"] for entry in per_frame]
    summary = {"format": FORMAT, "folder": TIMELAPSE_DIR, "frames": count,
               "strokes": per_frame[-1]["strokes"], **(statistics or {}),
               "seconds": round(time.perf_counter() - clock, 4)}
    report = {"version": __version__, "sequence": "timelapse", "timelapse": summary,
              "input": [str(source)] * count, "frame_count": count, "width": int(width), "height": int(height),
              "motion": STILL_MOTION, "fade_frames": 0, "params": params_dict, "frames": numbers,
              "per_frame": per_frame, "complete": True}
    writing.write_json(folder / REPORT_FILE, report)
    return summary


@functools.cache
def half_tables() -> tuple:
    """(linear, png): for every float16 bit pattern v of an sRGB value, ``srgb_to_linear(v)`` as float32 and the
    8-bit PNG value ``floor(v * 255 + 0.5)`` clipped to [0, 255] (NaN 0), as ``write_png`` quantises: a frame
    held as float16 is converted by looking its values up, with the same numbers as converting it."""
    values = np.arange(1 << 16, dtype=np.uint16).view(np.float16).astype(np.float32)
    finite = np.nan_to_num(values, nan=0.0, posinf=0.0, neginf=0.0)
    with np.errstate(over="ignore", invalid="ignore"):
        png = np.clip(np.floor(np.nan_to_num(values, nan=0.0) * np.float32(255.0) + np.float32(0.5)), 0.0, 255.0)
    return srgb_to_linear(finite), png.astype(np.uint8)
