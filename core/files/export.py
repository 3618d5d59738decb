"""Writing a painting to a folder: relief maps as EXR, a preview, the strokes and a report."""

from __future__ import annotations

import hashlib
import json
import time
from pathlib import Path

import numpy as np

from ..colour import srgb_to_linear
from ..lighting import DEFAULT_RELIEF, PAPER_STRENGTH, encode_normals, normal_map, paper_lighting
from ..results import Painting
from ..version import __version__
from . import io


def map_attributes(painting: Painting) -> dict:
    """EXR header attributes that say how a painting was made.

    The seed is stored as decimal text: header integers hold only 32 bits and
    seeds go up to 2^63 - 1.
    """
    return {
        "paint_relief:version": __version__,
        "paint_relief:seed": str(painting.params.seed),
        "paint_relief:height_mode": painting.params.height_mode,
        "paint_relief:params": json.dumps(painting.params.to_dict(), sort_keys=True),
    }


PAINTING_FILES = ("color.exr", "height.exr", "opacity.exr", "orientation.exr", "normal.exr", "painting.png",
                  "lit_paper.png", "strokes.json", "report.json")
"""Every file ``write_painting`` writes, report.json last."""


def file_digests(folder: Path, names) -> dict:
    """{name: {"bytes": size, "sha256": hex digest}} of the files ``names`` in ``folder``."""
    digests = {}
    for name in names:
        data = (Path(folder) / name).read_bytes()
        digests[name] = {"bytes": len(data), "sha256": hashlib.sha256(data).hexdigest()}
    return digests


def write_painting(folder: Path, painting: Painting, source: str) -> dict:
    """Write the painting's files into ``folder``; returns the report written as report.json.

    The maps are 16-bit half floats, zip-compressed (8-bit colour needs 1/256;
    half keeps 1/2048 of the value, far finer than paint height or opacity vary).

    color.exr    RGB, scene-linear Rec.709 (the sRGB painting converted)
    height.exr   Y, paint height (1 = one full bristle's contact)
    opacity.exr  Y, stroke opacity in [0, 1]
    orientation.exr  Y, stroke direction in radians [0, pi) (the paper's lighting needs it)
    normal.exr   RGB, tangent-space normals of the height field (lighting.normal_map at
                 relief DEFAULT_RELIEF px per height unit; OpenGL convention X right, Y up,
                 Z out), stored ENCODED as n * 0.5 + 0.5 in [0, 1]: Blender's Normal Map
                 node expects encoded colour data, so load it as Non-Color data
    painting.png the painting, 8-bit sRGB
    lit_paper.png the painting lit by the paper's Eq. 6-7 at strength PAPER_STRENGTH, 8-bit sRGB
    strokes.json one entry per stroke: layer, anchor, size, path, anchor colour
    report.json  figures of the run, and the size and SHA-256 of every other file above
                 ("files"), so a folder can be checked to hold one complete painting
    """
    folder = Path(folder)
    t0 = time.perf_counter()
    attributes = map_attributes(painting)
    io.write_exr(folder / "color.exr", srgb_to_linear(painting.colour), half=True, attributes=attributes)
    io.write_exr(folder / "height.exr", painting.height, channels=("Y",), half=True, attributes=attributes)
    io.write_exr(folder / "opacity.exr", painting.opacity, channels=("Y",), half=True, attributes=attributes)
    io.write_exr(folder / "orientation.exr", painting.orientation, channels=("Y",), half=True, attributes=attributes)
    normal_attributes = dict(attributes, **{"paint_relief:normal_relief": float(DEFAULT_RELIEF),
                                            "paint_relief:normal_encoding": "n*0.5+0.5, OpenGL (Y up)"})
    io.write_exr(folder / "normal.exr", encode_normals(normal_map(painting.height, DEFAULT_RELIEF)), half=True,
                 attributes=normal_attributes)
    io.write_png(folder / "painting.png", painting.colour)
    io.write_png(folder / "lit_paper.png",
                 paper_lighting(painting.colour, painting.height, painting.orientation, PAPER_STRENGTH))
    io.write_json(folder / "strokes.json", {"version": __version__, "strokes": [s.to_dict() for s in painting.strokes]},
                  indent=None)
    report = dict(painting.statistics)
    report["seconds"] = dict(report["seconds"], writing=round(time.perf_counter() - t0, 4))
    report.update({"input": str(source), "params": painting.params.to_dict(),
                   "height_range": [float(np.min(painting.height)), float(np.max(painting.height))],
                   "files": file_digests(folder, PAINTING_FILES[:-1])})
    io.write_json(folder / "report.json", report)
    return report
