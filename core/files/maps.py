"""Checks of a painted folder before anything else (Blender above all) reads it.

``check_maps`` reads each relief map in full with OpenImageIO and refuses,
with one sentence naming the file, anything Blender should never receive: a
missing, empty, truncated or unreadable file, the wrong channels, NaN or
infinite values, sizes that disagree, or maps of two different paintings.
``check_painting`` verifies that a folder holds one complete painting: every
file listed in report.json with its size and SHA-256, and every EXR's header
seed equal to the report's.
"""

from __future__ import annotations

import hashlib
import pathlib
from typing import Dict, Sequence, Tuple

from ..errors import InputError
from . import reading
from .shot_files import REPORT_FILE, read_report
from .staging import settle

EXPECTED_CHANNELS = {
    "color.exr": ("R", "G", "B"),
    "height.exr": ("Y",),
    "opacity.exr": ("Y",),
    "orientation.exr": ("Y",),
    "normal.exr": ("R", "G", "B"),
}
"""Channel names of each map ``export.write_painting`` writes."""
CANVAS_MAPS = ("color.exr", "height.exr", "opacity.exr")
"""The maps a canvas in Blender is built from."""
_SAME_PAINTING = ("paint_relief:seed", "paint_relief:params")


def check_maps(folder, names: Sequence[str] = CANVAS_MAPS) -> Tuple[int, int]:
    """Validate the EXR maps ``names`` of a painted ``folder``; return their (width, height).

    Each map must exist, be read in full without error, hold exactly its
    expected channels (EXPECTED_CHANNELS; other names: any), hold only finite
    values and have the size of the first map. Maps that carry Paint Relief
    header attributes must agree on the seed and parameters (one painting).
    An interrupted commit in the folder is completed first when no run is
    writing there (``staging.settle``). Raises InputError with one sentence.
    """
    folder = pathlib.Path(folder)
    if not folder.is_dir():
        raise InputError(f"The painted folder {folder} does not exist.")
    settle(folder)
    size = None
    first = None
    origin: Dict[str, object] = {}
    for name in names:
        path = folder / name
        if not path.is_file():
            raise InputError(f"The painted map {path} does not exist; paint into {folder} first.")
        data, channels, attributes = reading.read_exr(path)  # InputError: unreadable, truncated, empty, NaN or inf
        expected = EXPECTED_CHANNELS.get(name)
        if expected is not None and tuple(channels) != expected:
            raise InputError(f"The painted map {path} has the channels {','.join(channels)}, "
                             f"expected {','.join(expected)}.")
        h, w = data.shape[:2]
        if size is None:
            size, first = (w, h), path
        elif (w, h) != size:
            raise InputError(f"The painted map {path} is {w} x {h} pixels but {first} is {size[0]} x {size[1]}.")
        mine = {k: attributes.get(k) for k in _SAME_PAINTING if k in attributes}
        if mine:
            if origin and mine != origin:
                raise InputError(f"The painted map {path} belongs to another painting than {first} "
                                 f"(their seeds or parameters differ); paint into {folder} again.")
            origin = origin or mine
    return size


def check_painting(folder) -> str:
    """Verify that ``folder`` holds one complete painting; return its seed as text.

    report.json must parse and list ("files") every other file of the
    painting with its size and SHA-256; every listed file must match, and
    every EXR's ``paint_relief:seed`` must equal the report's seed. Raises
    InputError with one sentence naming the first file that disagrees.
    """
    folder = pathlib.Path(folder)
    report_path = folder / REPORT_FILE
    try:
        report = read_report(folder)
        if report is None:
            raise FileNotFoundError(report_path)
        files = dict(report["files"])
        seed = str(report["seed"])
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise InputError(f"The report {report_path} is missing or unreadable ({type(exc).__name__}).") from None
    for name, expected in files.items():
        path = folder / name
        try:
            data = path.read_bytes()
        except OSError:
            raise InputError(f"The painting file {path} is missing.") from None
        if len(data) != expected["bytes"] or hashlib.sha256(data).hexdigest() != expected["sha256"]:
            raise InputError(f"The painting file {path} is not the one {report_path} lists.")
        if name.endswith(".exr"):
            _, _, attributes = reading.read_exr(path)
            if str(attributes.get("paint_relief:seed")) != seed:
                raise InputError(f"The painting file {path} has seed {attributes.get('paint_relief:seed')}, "
                                 f"not the report's {seed}.")
    return seed
