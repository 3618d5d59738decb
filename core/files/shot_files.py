"""The names in a painted shot's folder and in a frame pattern, and reading a painting's report.json: one rule for
the painter, the extension, the relit film and the benches.

A shot's frame ``n`` is written as ``<map>_<n>`` beside one report.json:
``painting_0016.png``, ``color_0016.exr``, ``height_0016.exr``,
``opacity_0016.exr``, ``orientation_0016.exr`` (and ``normal_0016.exr``),
the number zero-padded to 4 digits, more when it needs them, as Blender
numbers an image sequence. A frame pattern's last run of ``#`` stands for
the zero-padded frame number (``render/frame_####.png``).

Only the standard library is used, so Blender's user interface imports this
module without loading NumPy.
"""

from __future__ import annotations

import json
import os
import re
from typing import List, Optional, Tuple

REPORT_FILE = "report.json"
"""A painting's report, a still's or a shot's."""

FRAME_MAPS = ("painting.png", "color.exr", "height.exr", "opacity.exr", "orientation.exr")
"""The files every painted frame has, unnumbered, in the order the report lists them."""

NORMAL_MAP = "normal.exr"
"""The tangent-space normal map a frame has when it is painted with the normal map."""

_DIGITS = re.compile(r"\d+")
_HASHES = re.compile(r"#+")


def frame_suffix(number: int) -> str:
    """"_0016" for frame 16: the frame number zero-padded to 4 digits (more when it needs them)."""
    return f"_{int(number):04d}"


def numbered_name(name: str, number: int) -> str:
    """The file of frame ``number`` of the map ``name`` in a painted shot: ``("color.exr", 16)`` ->
    ``"color_0016.exr"``."""
    stem, dot, suffix = name.rpartition(".")
    return f"{stem}{frame_suffix(number)}{dot}{suffix}"


def frame_file_names(number: int, normal_map: bool) -> List[str]:
    """The files of frame ``number`` in a painted shot (``FRAME_MAPS`` numbered, then the normal map when
    ``normal_map``)."""
    return [numbered_name(name, number) for name in FRAME_MAPS + ((NORMAL_MAP,) if normal_map else ())]


def is_pattern(text: str) -> bool:
    """True when ``text`` names no existing file and its file name holds a ``#``."""
    return "#" in os.path.basename(str(text)) and not os.path.isfile(str(text))


def pattern_parts(name: str) -> Tuple[str, int, str]:
    """(before, digits, after) of a frame pattern's file ``name``: its last run of ``#`` is a frame number of
    ``digits`` digits at least. ValueError (one sentence) when the name holds no ``#``."""
    runs = list(_HASHES.finditer(name))
    if not runs:
        raise ValueError(f"The frame pattern {name} holds no '#' for the frame number.")
    last = runs[-1]
    return name[:last.start()], last.end() - last.start(), name[last.end():]


def shot_name(source: str) -> str:
    """The name a shot given as ``source`` (a folder of frames or a ``#`` pattern) is known by: the folder's name,
    or the pattern's file name without its frame number, extension and the separators around them
    (``render/shot_####.exr`` -> ``shot``; ``render/####.exr`` -> ``render``)."""
    folder, name = os.path.split(os.path.normpath(str(source)))
    if not is_pattern(name):
        return name
    before, _, after = pattern_parts(name)
    stem = (before + after.rpartition(".")[0] if "." in after else before + after).strip("._- ")
    return stem or os.path.basename(folder)


def pattern_file(pattern: str, number: int) -> str:
    """The file of frame ``number`` in a frame ``pattern`` (more digits than its ``#`` when the number needs them,
    as Blender writes): ``("shot_####.png", 12)`` -> ``"shot_0012.png"``."""
    folder, name = os.path.split(str(pattern))
    before, digits, after = pattern_parts(name)
    return os.path.join(folder, f"{before}{int(number):0{digits}d}{after}")


def numbered_file(path: str) -> Tuple[str, int]:
    """How Blender reads an image sequence from one of its files: ``(pattern, number)``.

    The last run of digits in the file name's stem is the frame number; the
    pattern has it replaced by as many ``#`` (``/a/shot_0005.png`` ->
    ``("/a/shot_####.png", 5)``). ValueError (one sentence) when the name
    holds no digits.
    """
    folder, name = os.path.split(str(path))
    stem, extension = os.path.splitext(name)
    runs = list(_DIGITS.finditer(stem))
    if not runs:
        raise ValueError(f"The file name {name} holds no frame number, so it starts no image sequence.")
    last = runs[-1]
    pattern = stem[:last.start()] + "#" * (last.end() - last.start()) + stem[last.end():] + extension
    return os.path.join(folder, pattern), int(last.group())


def read_report(folder) -> Optional[dict]:
    """The report.json of the painting in ``folder`` as a dict; None when the folder holds none.

    OSError when it cannot be read, ValueError when it is not a JSON object.
    """
    path = os.path.join(str(folder), REPORT_FILE)
    if not os.path.isfile(path):
        return None
    with open(path, encoding="utf-8") as stream:
        report = json.load(stream)
    if not isinstance(report, dict):
        raise ValueError(f"{path} holds no JSON object.")
    return report


def is_shot_report(report: dict) -> bool:
    """Whether a painting's ``report`` (``read_report``) is a shot's, not a still's."""
    return "sequence" in report
