"""What the frames of a sequence are: their files in order, their frame numbers and their size.

A sequence is given as one folder (its PNG, JPEG, TIFF and EXR files), one
pattern whose run of ``#`` stands for the zero-padded frame number
(``render/frame_####.png``, as Blender writes), or files listed in order.
``find_frames`` finds them, selects ``--frames A-B`` and checks them from
their names and headers before any painting (frame numbers from 0 to
``MAX_FRAME``, running up by 1, one size): each refusal is an ``InputError``
(or a ``ParameterError`` for ``--frames``) whose one sentence names the frame
file and the problem. ``check_output_folder`` refuses an output folder whose
painted frames would be read, or written over, as frames. A frame's picture is read with ``reading.read_image`` (a
Blender multilayer EXR's Combined pass); its Blender motion with
``read_vector_pass``.
"""

from __future__ import annotations

import os
import pathlib
import re
from dataclasses import dataclass
from typing import List, Optional, Sequence, Tuple

import numpy as np

from ..errors import InputError, ParameterError, plain_cause
from . import reading
from .image_files import PathLike
from .shot_files import frame_file_names, is_pattern, pattern_parts

IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".tif", ".tiff", ".exr")
"""The file name endings (any case) of a folder's frames."""

VECTOR_PASS = ("Vector", "XYZW")
"""Blender's motion pass in a multilayer EXR and its channels."""

MAX_FRAME = 1_048_574
"""The highest frame number: Blender's last frame (its frame range is 0 to 1,048,574), so a painted shot is shown
in Blender frame for frame; strokes.lives stores frame numbers as 64-bit integers, which hold it."""

_DIGITS = re.compile(r"\d+")
_RANGE = re.compile(r"(\d*)-(\d*)|(\d+)")


@dataclass(frozen=True)
class Frames:
    """The frames of a sequence: ``paths[i]`` holds frame number ``numbers[i]`` (increasing by 1), every
    frame ``width`` x ``height`` pixels."""

    paths: Tuple[pathlib.Path, ...]
    numbers: Tuple[int, ...]
    width: int
    height: int


def find_frames(inputs: Sequence[str], frame_range: Optional[str] = None,
                max_megapixels: float = float("inf")) -> Frames:
    """The frames named by the command line's ``inputs``, those of ``frame_range`` (``--frames``) only, checked.

    ``inputs``: one folder, one ``#`` pattern, or files in order
    (``frame_files``). Numbers (``check_range``, ``check_numbers``),
    selection and order are checked before any header is read, then every
    selected frame's header (``check_headers``).
    Reads no pixel and writes nothing.
    """
    paths, numbers, named = frame_files(inputs)
    paths, numbers = select_frames(paths, numbers, frame_range)
    if named:
        check_range(paths, numbers)
        check_numbers(paths, numbers)
    width, height = check_headers(paths, max_megapixels)
    return Frames(tuple(paths), tuple(numbers), width, height)


def frame_files(inputs: Sequence[str]) -> Tuple[List[pathlib.Path], List[int], bool]:
    """(paths, frame numbers, whether the numbers come from the file names) of the frames ``inputs`` name.

    One folder: its image files (``IMAGE_SUFFIXES``, hidden files and
    folders left out). One input that is not a file and whose name holds a
    run of ``#``: the files matching that pattern (``pattern_files``).
    Anything else: the files as listed, in that order. A frame's number is
    the last run of digits in its file name's stem (a pattern's ``#``
    digits) when every frame has one, else its place 1, 2, 3, ... A folder's
    and a pattern's frames are ordered by number, or by name when numbered
    by place. InputError when a folder or pattern gives no frame, or a
    listed file is missing or cannot be read (before ``--frames`` selects
    among them by their numbers).
    """
    if not inputs:
        raise InputError("No frames were given: give a folder, a pattern such as frame_####.png, or image files.")
    if len(inputs) == 1 and os.path.isdir(inputs[0]):
        return _ordered(folder_files(pathlib.Path(inputs[0])))
    if len(inputs) == 1 and is_pattern(inputs[0]):
        found = pattern_files(inputs[0])
        return [path for path, _ in found], [number for _, number in found], True
    paths = [pathlib.Path(text) for text in inputs]
    for path in paths:
        reading.check_input_path(path, role="frame")
    return _numbered(paths)


def folder_files(folder: pathlib.Path) -> List[pathlib.Path]:
    """The image files of ``folder`` (``IMAGE_SUFFIXES``, any case; not hidden, not folders), in no set order.

    InputError when the folder cannot be listed or holds no such file.
    """
    names = [name for name in _listed(folder)
             if not name.startswith(".") and name.lower().endswith(IMAGE_SUFFIXES)]
    paths = [folder / name for name in names if _frame_file(folder / name)]
    if not paths:
        raise InputError(f"The folder {folder} holds no frames: no PNG, JPEG, TIFF or EXR file.")
    return paths


def pattern_files(pattern: str) -> List[Tuple[pathlib.Path, int]]:
    """(path, frame number) of the files matching ``pattern``, ordered by number.

    The last run of ``#`` in the pattern's file name stands for a frame
    number of exactly that many digits (zero-padded, ``frame_####.png``
    matches frame_0007.png), or more digits when the number needs them
    (frame_12345.png, as Blender writes it); the rest of the name matches
    literally. InputError when no file matches.
    """
    pattern_path = pathlib.Path(pattern)
    folder = pattern_path.parent
    before, width, after = pattern_parts(pattern_path.name)
    name = re.compile(re.escape(before) + rf"(\d{{{width}}}|[1-9]\d{{{width},}})" + re.escape(after))
    found = []
    for entry in _listed(folder, pattern):
        match = name.fullmatch(entry)
        if match and _frame_file(folder / entry):
            found.append((folder / entry, int(match.group(1))))
    if not found:
        raise InputError(f"No file matches the frame pattern {pattern}.")
    return sorted(found, key=lambda item: (item[1], item[0].name))


def _frame_file(path: pathlib.Path) -> bool:
    """Whether ``path`` stands for a frame: a file, or a link to none (named by the header checks, not skipped)."""
    return path.is_file() or (path.is_symlink() and not path.exists())


def _listed(folder: pathlib.Path, pattern: Optional[str] = None) -> List[str]:
    """The names in ``folder`` (the frames' folder, or that of ``pattern``); InputError when it cannot be listed."""
    try:
        return os.listdir(folder)
    except OSError as exc:
        missing = isinstance(exc, FileNotFoundError)
        if pattern is None:
            raise InputError(f"Cannot list the folder {folder}: "
                             f"{'it does not exist' if missing else plain_cause(exc)}.") from None
        why = "does not exist" if missing else f"cannot be listed ({plain_cause(exc)})"
        raise InputError(f"No file matches the frame pattern {pattern}: its folder {folder} {why}.") from None


def frame_number(path: pathlib.Path) -> Optional[int]:
    """The last run of digits in ``path``'s file name stem as a number (frame_0012.exr -> 12); None if none."""
    runs = _DIGITS.findall(path.stem)
    return int(runs[-1]) if runs else None


def _numbered(paths: List[pathlib.Path]) -> Tuple[List[pathlib.Path], List[int], bool]:
    """(paths, numbers, from names): numbers from the file names when every one has one, else 1, 2, 3, ..."""
    numbers = [frame_number(path) for path in paths]
    if all(number is not None for number in numbers):
        return paths, numbers, True
    return paths, list(range(1, len(paths) + 1)), False


def _ordered(paths: List[pathlib.Path]) -> Tuple[List[pathlib.Path], List[int], bool]:
    """A folder's ``paths`` numbered (``_numbered``) and ordered: by number, or by name when numbered by place."""
    by_name = sorted(paths, key=_name_order)
    _, numbers, named = _numbered(by_name)
    if not named:
        return by_name, numbers, False
    pairs = sorted(zip(numbers, by_name, strict=True), key=lambda pair: pair[0])
    return [path for _, path in pairs], [number for number, _ in pairs], True


def _name_order(path: pathlib.Path) -> tuple:
    """Sort key of a file name with its runs of digits compared as numbers (frame_9 before frame_10)."""
    parts = re.split(r"(\d+)", path.name)
    return tuple((0, int(part), "") if part.isdigit() else (1, 0, part) for part in parts)


def parse_frame_range(text: str) -> Tuple[Optional[int], Optional[int]]:
    """``--frames`` text -> (first, last) frame number, inclusive; None for an open end.

    'A-B', 'A-' (A to the end), '-B' (the start to B) or 'A' (frame A
    alone), A and B whole numbers from 0 to ``MAX_FRAME``, A at most B.
    ParameterError naming the option otherwise.
    """
    match = _RANGE.fullmatch(text.strip())
    if match is None or match.group(0) == "-":
        raise ParameterError(f"The option --frames must be A-B, A-, -B or a single frame number A, got "
                             f"{_short(text)!r}.")
    if any(len(digits) > len(str(MAX_FRAME)) or int(digits) > MAX_FRAME for digits in match.groups() if digits):
        raise ParameterError(f"The option --frames takes frame numbers from 0 to {MAX_FRAME}, got {_short(text)!r}.")
    if match.group(3) is not None:
        return int(match.group(3)), int(match.group(3))
    first = int(match.group(1)) if match.group(1) else None
    last = int(match.group(2)) if match.group(2) else None
    if first is not None and last is not None and first > last:
        raise ParameterError(f"The option --frames {text} ends before it starts: give A-B with A at most B.")
    return first, last


def select_frames(paths: List[pathlib.Path], numbers: List[int],
                  frame_range: Optional[str]) -> Tuple[List[pathlib.Path], List[int]]:
    """The frames whose numbers lie in ``frame_range`` (``parse_frame_range``; None keeps all), in their order.

    ParameterError naming the option when the range selects no frame.
    """
    if frame_range is None:
        return paths, numbers
    first, last = parse_frame_range(frame_range)
    kept = [(path, number) for path, number in zip(paths, numbers, strict=True)
            if (first is None or number >= first) and (last is None or number <= last)]
    if not kept:
        raise ParameterError(f"The option --frames {frame_range} selects no frame: the frames are numbered "
                             f"{min(numbers)} to {max(numbers)}.")
    return [path for path, _ in kept], [number for _, number in kept]


def _short(text: str) -> str:
    """``text`` cut to its first 40 characters, with '...' when it is longer."""
    return text if len(text) <= 40 else text[:40] + "..."


def check_range(paths: Sequence[pathlib.Path], numbers: Sequence[int]) -> None:
    """Refuse a frame numbered from its name above ``MAX_FRAME``: InputError naming the file and its number."""
    for path, number in zip(paths, numbers, strict=True):
        if number > MAX_FRAME:
            raise InputError(f"The frame {path} is numbered {_short(str(number))} by its name, above {MAX_FRAME}, "
                             f"the last frame Blender can hold: number the frames from 0 to {MAX_FRAME}.")


def check_numbers(paths: Sequence[pathlib.Path], numbers: Sequence[int]) -> None:
    """Refuse frames numbered from their names unless the numbers run up by exactly 1 from frame to frame.

    InputError, naming the files: two frames with one number; a frame
    listed after one with a higher number; a gap (the missing numbers).
    """
    seen = {}
    for path, number in zip(paths, numbers, strict=True):
        if number in seen:
            raise InputError(f"{seen[number]} and {path} both have frame number {number}: "
                             f"give the frames of one sequence.")
        seen[number] = path
    steps = [(paths[i - 1], numbers[i - 1], paths[i], numbers[i]) for i in range(1, len(paths))]
    for before, b, after, a in steps:
        if a < b:
            raise InputError(f"{after} (frame {a}) is listed after {before} (frame {b}): "
                             f"list the frames in the order of their numbers.")
    for before, b, after, a in steps:
        if a > b + 1:
            missing = f"frame {b + 1} is missing" if a == b + 2 else f"frames {b + 1} to {a - 1} are missing"
            raise InputError(f"{after} follows {before}: {missing}.")


def check_headers(paths: Sequence[pathlib.Path], max_megapixels: float = float("inf")) -> Tuple[int, int]:
    """(width, height) shared by every frame, from their headers alone (no pixel is decoded).

    InputError naming the frame file when one is missing, unreadable, empty
    or above ``max_megapixels`` (``reading.probe``), or when its size
    differs from the first frame's.
    """
    width, height, _ = reading.probe(paths[0], max_megapixels, role="frame")
    for path in paths[1:]:
        w, h, _ = reading.probe(path, max_megapixels, role="frame")
        if (w, h) != (width, height):
            raise InputError(f"The frame {path} is {w} x {h} pixels but the first frame {paths[0]} is "
                             f"{width} x {height}: every frame must have the same size.")
    return width, height


def check_output_folder(inputs: Sequence[str], found: Frames, output_dir, normal_map: bool = False) -> None:
    """Refuse to paint the frames ``found`` from ``inputs`` into ``output_dir`` when the shot's own files would be
    read, or written over, as frames; before anything is written.

    InputError naming both when ``output_dir`` is the folder given as the one
    input (the painted frames would be frames of the next run), or when a
    frame file sits in ``output_dir`` under the name of a file the shot
    writes there (``shot_files.frame_file_names``). A pattern's or listed
    files' folder may be the output folder otherwise
    (``render/frame_####.png`` into ``render``), and a folder inside the
    frames' folder may be (a folder's subfolders are not read).
    """
    output = os.path.realpath(output_dir)
    if len(inputs) == 1 and os.path.isdir(inputs[0]) and os.path.realpath(inputs[0]) == output:
        raise InputError(f"The output folder {output_dir} is the folder of frames {inputs[0]}: the painted frames "
                         f"would be read as frames, so paint into another folder.")
    for path, number in zip(found.paths, found.numbers, strict=True):
        if os.path.realpath(path.parent) == output and path.name in frame_file_names(number, normal_map):
            raise InputError(f"The frame {path} would be written over by the shot's own {path.name} in the output "
                             f"folder {output_dir}: paint into another folder.")


def read_vector_pass(path: PathLike) -> Optional[np.ndarray]:
    """Blender's Vector pass of the frame ``path``: float32 (H, W, 4), its raw X, Y, Z, W channels as stored,
    rows top first; None when the frame has none (not a multilayer EXR, or rendered without the pass).

    Forward motion to the next frame in image axes is (-Z, +W), backward
    motion to the previous frame (X, -Y). InputError naming the frame as
    ``reading.read_pass``.
    """
    return reading.read_pass(path, *VECTOR_PASS, role="frame")


def carry_vector_passes(paths: Sequence[pathlib.Path]) -> bool:
    """Whether every frame holds Blender's Vector pass (its motion), from the headers; False when none does.

    InputError naming the first frame without one when only some do: a sequence's motion comes from one source.
    """
    holding = [reading.holds_pass(path, *VECTOR_PASS, role="frame") for path in paths]
    if all(holding) or not any(holding):
        return all(holding)
    first_with = paths[holding.index(True)]
    first_without = paths[holding.index(False)]
    raise InputError(f"The frame {first_without} has no Vector pass but {first_with} has one: render every frame "
                     f"with the Vector pass, or none.")
