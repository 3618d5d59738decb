"""Errors the painter reports to a person: one sentence naming the file and the problem."""

from __future__ import annotations

import errno
import os
from typing import Optional


class PaintReliefError(Exception):
    """A failure caused by input or settings; its message is one complete sentence."""


class InputError(PaintReliefError):
    """An input file is missing, unreadable, empty, too large or holds invalid values."""


class OutputError(PaintReliefError):
    """An output file or folder cannot be written.

    ``path`` is the file that could not be written and ``cause`` the reason in
    plain words (no full stop), when known: a caller that wrote ``path`` in a
    hidden staging folder words its own sentence from them.
    """

    def __init__(self, message: str, path=None, cause: Optional[str] = None):
        super().__init__(message)
        self.path = path
        self.cause = cause


class ParameterError(PaintReliefError):
    """A parameter is outside its allowed range."""


class Cancelled(PaintReliefError):
    """The caller asked to stop; nothing partial was written."""


_CAUSES = {
    errno.ENOSPC: "no space is left on the device",
    errno.EDQUOT: "the disk quota is used up",
    errno.EFBIG: "the file is too large: it would pass this process's file size limit (ulimit -f)",
    errno.EACCES: "permission denied",
    errno.EPERM: "permission denied",
    errno.EROFS: "the file system is read-only",
    errno.EIO: "the device reported an input/output error",
}


def plain_cause(exc: OSError, folder=None) -> str:
    """An operating system error's cause in plain words, lower case, without a full stop or file name.

    ``folder``: the existing folder a file was being created in. Creating a file there can fail with
    'no such file or directory' (/proc/self and other system folders); that is said as what it means.
    """
    if exc.errno == errno.ENOENT and folder is not None and os.path.isdir(folder):
        return "it is a folder in which no file can be created"
    if exc.errno in _CAUSES:
        return _CAUSES[exc.errno]
    return (exc.strerror or str(exc) or "an unknown error").strip().rstrip(".").lower()


def reading_error(what: str, exc: OSError, kind: str) -> InputError:
    """The one-sentence InputError of ``exc``, a failure to open or read the file ``what`` names ("The mesh
    PATH"): it does not exist, it is a folder and not ``kind`` ("an OBJ file"), or why it cannot be read."""
    if isinstance(exc, FileNotFoundError):
        return InputError(f"{what} does not exist.")
    if isinstance(exc, IsADirectoryError):
        return InputError(f"{what} is a folder, not {kind}.")
    return InputError(f"{what} cannot be read: {plain_cause(exc)}.")
