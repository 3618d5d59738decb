"""What a sequence's next frame needs of the last frame committed, kept in the output folder so a run can resume.

The state file is written with each frame's files and committed with them,
so it always belongs to the last complete frame: its strokes (the
``StrokeList`` and each stroke's life), the judging canvas's error and bare
maps, the next stroke identity, the frame's index and the length of the
lives file after it. Arrays are stored as they are in memory (NumPy's .npz,
no pickling), so a resumed run continues with the same bytes.
"""

from __future__ import annotations

import dataclasses
import io
import zipfile
import zlib
from pathlib import Path
from typing import NamedTuple

import numpy as np

from ..errors import InputError, plain_cause
from ..strokes.stroke_list import StrokeList
from .frame_step import PaintedFrame
from .living import LivingStrokes

STATE_FILE = ".sequence-state.npz"

_LIST_FIELDS = [field.name for field in dataclasses.fields(StrokeList)]
_LIFE_FIELDS = ["ident", "birth", "level", "dying", "offsets", "birth_length"]


class SavedState(NamedTuple):
    """A sequence's state after its frame ``index`` (0-based)."""

    frame: PaintedFrame         # without orientation (None): ``frame_step.shown_canvas`` lays the frame
    index: int
    lives_bytes: int


def save_state(path: Path, frame: PaintedFrame, index: int, lives_bytes: int) -> None:
    """Write the state after frame ``index`` (0-based) to ``path`` (in a staging folder: it is committed with the
    frame's files); ``lives_bytes``: the lives file's length after that frame."""
    living = frame.living
    arrays = {f"list_{name}": getattr(living.strokes, name) for name in _LIST_FIELDS}
    arrays.update({f"life_{name}": getattr(living, name) for name in _LIFE_FIELDS})
    arrays.update(error=frame.error, fresh=frame.fresh, opacity=frame.opacity,
                  counters=np.array([index, lives_bytes, frame.next_ident, living.fade_frames, frame.born,
                                     frame.died], np.int64))
    archive = io.BytesIO()  # made whole in memory, so a full disk fails the plain write below and nothing else
    np.savez(archive, **arrays)
    with open(path, "wb") as stream:
        stream.write(archive.getbuffer())


def load_state(path: Path) -> SavedState:
    """The state written by ``save_state``; InputError (one sentence naming the file) when it is missing, is not
    an archive of arrays (nothing in it is ever unpickled) or lacks the arrays of a state."""
    path = Path(path)
    if not path.is_file():
        raise InputError(_unreadable(path, "it does not exist"))
    try:
        if not zipfile.is_zipfile(path):
            raise InputError(_unreadable(path, "it is not an archive of arrays that Paint Relief wrote"))
        with np.load(path, allow_pickle=False) as data:
            arrays = {name: data[name] for name in data.files}
    except FileNotFoundError:
        raise InputError(_unreadable(path, "it does not exist")) from None
    except OSError as exc:
        raise InputError(_unreadable(path, plain_cause(exc))) from None
    except (KeyError, ValueError, EOFError, zipfile.BadZipFile, zlib.error):
        raise InputError(_unreadable(path, "its arrays are damaged")) from None
    try:
        return _saved_state(arrays)
    except (KeyError, ValueError, TypeError, IndexError):
        raise InputError(_unreadable(path, "it lacks the arrays of a sequence state or they do not fit "
                                           "together")) from None


def _unreadable(path: Path, problem: str) -> str:
    """The one sentence of a state file ``path`` that cannot be used because of ``problem`` (no full stop)."""
    return f"The sequence state {path} cannot be used: {problem}; paint the sequence into another folder."


def _saved_state(arrays: dict) -> SavedState:
    """The SavedState of the ``arrays`` of a state file (by name); KeyError, ValueError, TypeError or IndexError
    when they are not a state's."""
    strokes = StrokeList(**{name: arrays[f"list_{name}"] for name in _LIST_FIELDS})
    counters = arrays["counters"]
    if counters.dtype != np.int64 or counters.shape != (6,):
        raise ValueError("the counters are not six 64-bit integers")
    index, lives_bytes, next_ident, fade_frames, born, died = (int(v) for v in counters)
    living = LivingStrokes(strokes, **{name: arrays[f"life_{name}"] for name in _LIFE_FIELDS},
                           fade_frames=fade_frames)
    n = len(living.ident)
    if index < 0 or lives_bytes <= 0 or len(strokes) != n or any(len(getattr(living, name)) != n
                                                                  for name in ("birth", "level", "dying")):
        raise ValueError("the arrays do not fit together")
    return SavedState(PaintedFrame(living, None, arrays["error"], arrays["fresh"], arrays["opacity"], next_ident,
                                   born, died, {}), index, lives_bytes)
