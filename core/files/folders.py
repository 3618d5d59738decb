"""Where paintings go: each painting's own folder, ``<parent>/<stem>_<counter>``.

A photograph ``My photo (1).JPG`` painted into ``parent`` gets the folder
``parent/My_photo_1_001``, or ``_002``, ... when that one exists already, so
a new painting never overwrites an earlier one. Blender's Paint button and
the command line name folders by this one rule. Nothing here touches the
disk but to ask whether a path exists, and to clear a folder that holds only
what a run stopped before its first commit left (a lock file no process
holds, staging folders): that folder is free again. No folder is created.

A batch run again (``resumed_folders``) looks for each input's folder among
the existing ones first: one whose painting is that input's, or one a
stopped run left unfinished, which is settled (``staging.settle``: an
interrupted commit completed, a stopped run's remains removed) before it is
judged.

Standard library only, and ``core.files`` loads its other modules on first
use, so the extension can name folders without loading the painter's
libraries.
"""

from __future__ import annotations

import os
import pathlib
import re
from typing import Callable, Dict, Iterable, List, Optional, Tuple

# Counter width of a painting folder's name: photo_001.
DIGITS = 3


def folder_stem(image_path) -> str:
    """A folder-name-safe stem of an image file name: ``"My photo (1).JPG"`` -> ``"My_photo_1"``.

    Letters, digits, '-' and '_' are kept, runs of anything else become one
    '_'; an empty result becomes ``"painting"``.
    """
    stem = os.path.splitext(os.path.basename(str(image_path).rstrip("/\\")))[0]
    stem = re.sub(r"[^0-9A-Za-z_-]+", "_", stem).strip("_")
    return stem or "painting"


def _first_free(parent, stem: str, digits: int, taken) -> str:
    """The first ``parent/<stem>_<counter>`` (counter from 1, at least ``digits`` wide) that neither exists nor is
    in ``taken``, a set of case-folded folders (``Photo_001`` and ``photo_001`` are one folder on macOS and Windows)."""
    counter = 1
    while True:
        folder = os.path.join(parent, "{}_{:0{}d}".format(stem, counter, digits))
        if folder.casefold() not in taken and (not os.path.exists(folder) or _abandoned(folder)):
            return folder
        counter += 1


def _abandoned(folder: str) -> bool:
    """Whether ``folder`` held only the remains of a run stopped before it committed anything (its lock file, held
    by no process, and staging folders); those remains are removed (``staging.settle``), leaving it empty."""
    from .folderlock import LOCK_NAME
    from .staging import STAGING_PREFIX, settle

    try:
        names = os.listdir(folder)
        if not names or not all(name == LOCK_NAME or name.startswith(STAGING_PREFIX) for name in names):
            return False
        settle(pathlib.Path(folder))
        return not os.listdir(folder)
    except OSError:
        return False


def next_painting_folder(parent, image_path, digits: int = DIGITS) -> str:
    """The first ``parent/<stem>_<counter>`` (counter from 1, ``digits`` wide, wider past its largest) that does not
    exist yet, ``stem`` being ``folder_stem(image_path)``. Nothing is created."""
    return _first_free(parent, folder_stem(image_path), digits, ())


def painting_folders(parent, inputs: Iterable, digits: int = DIGITS) -> List[str]:
    """One folder per input, in order, all distinct: for each, the first ``parent/<stem>_<counter>`` that neither
    exists nor was given to an earlier input of the list (``a/photo.png`` and ``b/photo.png`` get ``photo_001`` and
    ``photo_002`` when neither exists; names differing only in case count as one). Nothing is created."""
    taken = set()
    folders = []
    for image_path in inputs:
        folder = _first_free(parent, folder_stem(image_path), digits, taken)
        taken.add(folder.casefold())
        folders.append(folder)
    return folders


def resumed_folders(parent, inputs: Iterable, owns: Callable[[int, str], object],
                    digits: int = DIGITS) -> List[Tuple[str, object]]:
    """One folder per input, in order, all distinct, each with what ``owns`` said of it: the folders of a batch run
    again, which goes on where an earlier run of it stopped.

    For input k, the existing folders ``parent/<stem>_<counter>`` not given to an earlier input are looked through in
    counter order, each settled first (an interrupted commit completed, a stopped run's staging folders and lock
    file removed; a folder another run holds is passed over). The first for which ``owns(k, folder)`` is truthy
    (it holds input k's painting, whole or to be gone on with) is input k's, with that value. Else the first that is
    empty once settled (a run stopped before its first commit left it) is input k's, with None; else the first free
    counter, as ``painting_folders`` names it, with None. ``owns`` is asked only of folders that hold something.
    Nothing is created."""
    taken: set = set()
    settled: Dict[str, Optional[List[str]]] = {}
    chosen = []
    for k, image_path in enumerate(inputs):
        stem = folder_stem(image_path)
        existing = [folder for folder in _numbered(parent, stem, digits) if folder.casefold() not in taken]
        for folder in existing:
            if folder not in settled:
                settled[folder] = _settled_names(folder)
        found = None
        for folder in existing:
            if settled[folder]:
                found = owns(k, folder)
                if found:
                    break
        if not found:
            found = None
            folder = next((f for f in existing if settled[f] == []), None) or _first_free(parent, stem, digits, taken)
        taken.add(folder.casefold())
        chosen.append((folder, found))
    return chosen


def _numbered(parent, stem: str, digits: int) -> List[str]:
    """The existing folders ``parent/<stem>_<counter>`` named as ``_first_free`` names them, in counter order."""
    try:
        names = os.listdir(parent)
    except OSError:
        return []
    counters = set()
    for name in names:
        head, _, number = name.rpartition("_")
        if (head.casefold() == stem.casefold() and number.isdigit() and number.isascii() and int(number) > 0
                and number == "{:0{}d}".format(int(number), digits)):
            counters.add(int(number))
    folders = [os.path.join(parent, "{}_{:0{}d}".format(stem, counter, digits)) for counter in sorted(counters)]
    return [folder for folder in folders if os.path.isdir(folder)]


def _settled_names(folder: str) -> Optional[List[str]]:
    """The names ``folder`` holds once settled (``staging.settle``; a lock file no process holds is not counted);
    None when another run holds it, or it cannot be read."""
    from ..errors import OutputError
    from .folderlock import LOCK_NAME, acquire
    from .staging import JOURNAL_NAME, STAGING_PREFIX, settle

    try:
        settle(pathlib.Path(folder))
        names = os.listdir(folder)
        if LOCK_NAME in names:
            with acquire(pathlib.Path(folder), attempts=2):
                pass
            names = [name for name in names if name != LOCK_NAME]
    except (OSError, OutputError):
        return None
    if any(name.startswith((STAGING_PREFIX, JOURNAL_NAME)) for name in names):
        return None
    return names
