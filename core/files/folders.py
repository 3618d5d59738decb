"""Where paintings go: each painting's own folder, ``<parent>/<stem>_<counter>``.

A photograph ``My photo (1).JPG`` painted into ``parent`` gets the folder
``parent/My_photo_1_001``, or ``_002``, ... when that one exists already, so
a new painting never overwrites an earlier one. Blender's Paint button and
the command line name folders by this one rule. Nothing here touches the
disk but to ask whether a path exists, and to clear a folder that holds only
what a run stopped before its first commit left (a lock file no process
holds, staging folders): that folder is free again. No folder is created.

Standard library only, and ``core.files`` loads its other modules on first
use, so the extension can name folders without loading the painter's
libraries.
"""

from __future__ import annotations

import os
import pathlib
import re
from typing import Iterable, List

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
