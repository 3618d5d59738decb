"""Writing a painting to a folder: relief maps as EXR, a preview, the strokes and a report."""

from __future__ import annotations

import hashlib
import json
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Callable, Optional, Sequence

import numpy as np

from .. import tuning
from ..colour import srgb_to_linear
from ..errors import InputError, plain_cause
from ..lighting import DEFAULT_RELIEF, PAPER_STRENGTH, encode_normals, normal_map, paper_lighting
from ..params import Params
from ..results import Painting
from ..version import __version__
from . import quiet, reading, writing
from .shot_files import REPORT_FILE
from .stroke_file import STROKES_FILE, stroke_document


def map_attributes(params: Params) -> dict:
    """EXR header attributes that say how a painting was made with ``params``.

    The seed is stored as decimal text: header integers hold only 32 bits and
    seeds go up to 2^63 - 1.
    """
    return {
        "paint_relief:version": __version__,
        "paint_relief:seed": str(params.seed),
        "paint_relief:height_mode": params.height_mode,
        "paint_relief:params": json.dumps(params.to_dict(), sort_keys=True),
    }


PAINTING_FILES = ("color.exr", "height.exr", "opacity.exr", "orientation.exr", "painting.png", "lit_paper.png",
                  "strokes.json", REPORT_FILE)
"""Every file ``write_painting`` writes, report.json last (and normal.exr when asked)."""

NORMAL_FILE = "normal.exr"

def file_digest(path: Path) -> dict:
    """{"bytes": size, "sha256": hex digest} of the file at ``path``."""
    data = Path(path).read_bytes()
    return {"bytes": len(data), "sha256": hashlib.sha256(data).hexdigest()}


def input_sha256(path) -> str:
    """The SHA-256 (hex) of the input file at ``path``, read in blocks; InputError naming it when it cannot be
    read. A still's report.json records it ("input_sha256"), so a batch run again knows the painting of an input."""
    try:
        with open(path, "rb") as stream:
            return hashlib.file_digest(stream, "sha256").hexdigest()
    except OSError as exc:
        raise InputError(f"The image {path} cannot be read: {plain_cause(exc)}.") from None


def file_digests(folder: Path, names) -> dict:
    """{name: {"bytes": size, "sha256": hex digest}} of the files ``names`` in ``folder``."""
    return dict(zip(names, run_all([lambda n=name: file_digest(Path(folder) / n) for name in names]), strict=True))


def run_all(tasks: Sequence[Callable[[], object]]) -> list:
    """Run ``tasks`` on ``tuning.WRITERS`` threads; their results in order. The first failure (in task order) is raised
    once all have finished, so no file is still being written when the caller cleans up."""
    with ThreadPoolExecutor(tuning.WRITERS) as pool:
        futures = [pool.submit(task) for task in tasks]
    return [future.result() for future in futures]


def rows_with_halo(shape: tuple, compute: Callable[[int, int], np.ndarray], halo: int) -> writing.RowBlocks:
    """RowBlocks of an image whose rows depend on the ``halo`` rows around them.

    compute(a, b) makes rows a .. b - 1 of the (H, W, C) ``shape`` image from
    the same rows of its inputs (treating row a and row b - 1 as the border
    where they are not); each block is computed with ``halo`` extra rows on
    both sides and cut back, so it equals the image computed whole.
    """
    def rows(y0: int, y1: int) -> np.ndarray:
        a, b = max(0, y0 - halo), min(shape[0], y1 + halo)
        return compute(a, b)[y0 - a:y1 - a]
    return writing.RowBlocks(tuple(shape), rows)


HEIGHT_DIGEST_ATTR = "paint_relief:height_sha256"
"""normal.exr's record of the height.exr it was made from (its SHA-256)."""


def painting_attributes(attributes: dict) -> dict:
    """The Paint Relief attributes of a map's header (``map_attributes`` and the like) to write into another map;
    the channel order is left out, as each map records its own."""
    return {k: v for k, v in attributes.items() if k.startswith("paint_relief:") and k != "paint_relief:channel_order"}


def write_normal_map(path: Path, height: np.ndarray, attributes: dict, height_digest: str) -> None:
    """normal.exr at ``path``: tangent-space normals of the (H, W) ``height`` as height.exr stores it (in half
    floats; see ``write_painting``), recording ``height_digest``, the SHA-256 of that height.exr."""
    normal_attributes = dict(attributes, **{"paint_relief:normal_relief": float(DEFAULT_RELIEF),
                                            "paint_relief:normal_encoding": "n*0.5+0.5, OpenGL (Y up)",
                                            HEIGHT_DIGEST_ATTR: height_digest})
    def normals(a: int, b: int) -> np.ndarray:
        stored = height[a:b].astype(np.float16).astype(np.float32)
        return encode_normals(normal_map(stored, DEFAULT_RELIEF))
    rows = rows_with_halo(height.shape + (3,), normals, 1)
    writing.write_exr(path, rows, half=True, attributes=normal_attributes)


def ensure_normal_map(folder: Path) -> Path:
    """The normal.exr of painted ``folder``, made from its height.exr unless it is already there for that height map.

    A normal map records the SHA-256 of the height.exr it was made from, so a
    folder painted again (its height.exr changed) gets a new one. Written
    atomically; InputError when height.exr cannot be read, OutputError when
    normal.exr cannot be written.
    """
    folder = Path(folder)
    path = folder / NORMAL_FILE
    digest = file_digest(folder / "height.exr")["sha256"] if (folder / "height.exr").is_file() else None
    if digest is not None and path.is_file():
        try:
            if reading.read_attributes(path).get(HEIGHT_DIGEST_ATTR) == digest:
                return path
        except InputError:
            pass                                    # unreadable: made again below
    height, _, attributes = reading.read_exr(folder / "height.exr")
    write_normal_map(path, height[:, :, 0], painting_attributes(attributes), digest)
    return path


def map_tasks(folder: Path, suffix: str, colour: np.ndarray, height: np.ndarray, opacity: np.ndarray,
              orientation: np.ndarray, attributes: dict) -> list:
    """The writers of a painting's maps into ``folder``, each a task for ``run_all``: painting<suffix>.png (8-bit
    sRGB), color<suffix>.exr (scene-linear RGB), height, opacity and orientation<suffix>.exr (Y), half floats with
    ``attributes`` in their headers. colour: (H, W, 3) sRGB [0, 1]; height, opacity, orientation: (H, W).
    ``suffix`` is "" for a still, "_0016" for frame 16 of a sequence."""
    linear = writing.RowBlocks(colour.shape, lambda y0, y1: srgb_to_linear(colour[y0:y1]))
    return [
        lambda: writing.write_png(folder / f"painting{suffix}.png", colour),
        lambda: writing.write_exr(folder / f"color{suffix}.exr", linear, half=True, attributes=attributes),
        lambda: writing.write_exr(folder / f"height{suffix}.exr", height, channels=("Y",), half=True,
                                  attributes=attributes),
        lambda: writing.write_exr(folder / f"opacity{suffix}.exr", opacity, channels=("Y",), half=True,
                                  attributes=attributes),
        lambda: writing.write_exr(folder / f"orientation{suffix}.exr", orientation, channels=("Y",), half=True,
                                  attributes=attributes),
    ]


def write_painting(folder: Path, painting: Painting, source: str, normal_map: bool = False, pages: int = 1,
                   source_sha256: Optional[str] = None, extra_files: Sequence[str] = (),
                   more: Optional[Callable[[], dict]] = None) -> dict:
    """Write the painting's files into ``folder``; returns the report written as report.json.

    The maps are 16-bit half floats, zip-compressed (8-bit colour needs 1/256;
    half keeps 1/2048 of the value, far finer than paint height or opacity vary).
    Images are made and written a block of rows at a time, ``tuning.WRITERS`` files at once.

    color.exr    RGB, scene-linear Rec.709 (the sRGB painting converted)
    height.exr   Y, paint height (1 = one full bristle's contact)
    opacity.exr  Y, stroke opacity in [0, 1]
    orientation.exr  Y, stroke direction in radians [0, pi) (the paper's lighting needs it)
    painting.png the painting, 8-bit sRGB
    lit_paper.png the painting lit by the paper's Eq. 6-7 at strength PAPER_STRENGTH, 8-bit sRGB
    strokes.json one entry per stroke: layer, anchor, size, path, anchor colour, and what laying it again needs
                 when the painting kept its ``stroke_list`` (``stroke_file``, format 2)
    report.json  figures of the run, the input ("input"; "input_page" 0, the image painted, of its
                 "input_pages" ``pages`` images; with ``source_sha256``, the input file's SHA-256 as
                 "input_sha256"), and the size and SHA-256 of every other file above ("files"), so a
                 folder can be checked to hold one complete painting
    normal.exr   only with ``normal_map``: RGB, tangent-space normals of the height field
                 (lighting.normal_map at relief DEFAULT_RELIEF px per height unit; OpenGL
                 convention X right, Y up, Z out), stored ENCODED as n * 0.5 + 0.5 in [0, 1]:
                 Blender's Normal Map node expects encoded colour data, so load it as Non-Color data

    ``extra_files``: names of files the caller wrote into ``folder`` before, listed in the report's "files" too.
    ``more`` (optional): called once the files are written; what it returns goes into the report (a time-lapse
    written meanwhile waits there to be finished).
    """
    folder = Path(folder)
    t0 = time.perf_counter()
    attributes = map_attributes(painting.params)
    colour, height = painting.colour, painting.height
    shape = colour.shape
    lit = rows_with_halo(shape, lambda a, b: paper_lighting(colour[a:b], height[a:b], painting.orientation[a:b],
                                                            PAPER_STRENGTH), 2)
    tasks = [lambda: writing.write_png(folder / "lit_paper.png", lit)]
    tasks += map_tasks(folder, "", colour, height, painting.opacity, painting.orientation, attributes)
    document = stroke_document([s.to_dict() for s in painting.strokes], painting.stroke_list,
                               painting.params.to_dict(), shape[1], shape[0], __version__)
    tasks.append(lambda: writing.write_json(folder / STROKES_FILE, document, indent=None))
    with quiet.captured():          # one capture for all the writers (library messages go to no terminal)
        run_all(tasks)
    files = file_digests(folder, PAINTING_FILES[:-1])
    if normal_map:
        write_normal_map(folder / NORMAL_FILE, height, attributes, files["height.exr"]["sha256"])
        files[NORMAL_FILE] = file_digest(folder / NORMAL_FILE)
    if extra_files:
        files.update(file_digests(folder, list(extra_files)))
    report = dict(painting.statistics, **(more() if more is not None else {}))
    report["seconds"] = dict(report["seconds"], writing=round(time.perf_counter() - t0, 4))
    report.update({"input": str(source), "input_page": 0, "input_pages": int(pages)})
    if source_sha256 is not None:
        report["input_sha256"] = source_sha256
    report.update({"params": painting.params.to_dict(), "height_range": [float(np.min(height)), float(np.max(height))],
                   "files": files})
    writing.write_json(folder / REPORT_FILE, report)
    return report


CELL_MAPS = ("color", "height", "opacity")
"""The maps written for each cell of an atlas of several cells (``write_cell_maps``), with "normal" when asked."""


def cell_map_names(suffix: str, normal_map: bool) -> dict:
    """{map: file name} of one atlas cell's maps: "color<suffix>.exr" and the like (``CELL_MAPS``, and "normal"
    with ``normal_map``); ``suffix`` as ``surface.atlas.cell_file_suffix`` gives it (".s0", ".s1.1002")."""
    return {name: f"{name}{suffix}.exr" for name in CELL_MAPS + (("normal",) if normal_map else ())}


def write_cell_maps(folder: Path, painting: Painting, cells: Sequence[tuple], normal_map: bool = False) -> list:
    """Write each atlas cell's region of the painting's maps as maps of their own into ``folder``, so a cell's
    maps fit its source's own UV square; returns the names written. cells: (suffix, rows, cols) each, the rows and
    columns slices of the cell in the painting's (H, W) maps. color is scene-linear RGB, height and opacity Y,
    normal (with ``normal_map``) as ``write_painting``'s normal.exr, made from the cell's height alone; all half
    floats with the painting's attributes."""
    folder = Path(folder)
    attributes = map_attributes(painting.params)
    tasks, names, normals = [], [], []
    for suffix, rows, cols in cells:
        named = cell_map_names(suffix, normal_map)
        colour = painting.colour[rows, cols]
        tasks += [lambda n=named["color"], c=colour: writing.write_exr(
                      folder / n, writing.RowBlocks(c.shape, lambda y0, y1, c=c: srgb_to_linear(c[y0:y1])),
                      half=True, attributes=attributes),
                  lambda n=named["height"], h=painting.height[rows, cols]: writing.write_exr(
                      folder / n, np.ascontiguousarray(h), channels=("Y",), half=True, attributes=attributes),
                  lambda n=named["opacity"], o=painting.opacity[rows, cols]: writing.write_exr(
                      folder / n, np.ascontiguousarray(o), channels=("Y",), half=True, attributes=attributes)]
        names += [named[name] for name in CELL_MAPS]
        if normal_map:
            normals.append((named["normal"], named["height"], painting.height[rows, cols]))
    with quiet.captured():
        run_all(tasks)
    for name, height_name, height in normals:
        write_normal_map(folder / name, np.ascontiguousarray(height), attributes,
                         file_digest(folder / height_name)["sha256"])
        names.append(name)
    return names
