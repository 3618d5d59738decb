"""Messages that image libraries print themselves, captured so they can be folded into our one sentence.

libpng, libjpeg and OpenEXR write warnings and errors straight to the
process's standard error (file descriptor 2), outside Python. Inside
``captured()`` descriptor 2 points at a temporary file, shared by the
blocks of every thread; the text lands in the yielded ``Captured`` and
callers fold it into their message. Capturing
is switched on by ``enable()`` (the command line does, as it owns its
process); elsewhere (inside Blender, where other threads write to the same
descriptor) ``captured()`` captures nothing.
"""

from __future__ import annotations

import contextlib
import os
import sys
import tempfile
import threading
from typing import Iterator

_enabled = False
_lock = threading.RLock()


def enable(on: bool = True) -> None:
    """Capture library messages from now on (``on=False`` stops it)."""
    global _enabled
    _enabled = bool(on)


class Captured:
    """What the libraries printed inside one ``captured()`` block (``text``, '' when nothing)."""

    def __init__(self) -> None:
        self.text = ""


class _Sink:
    """Descriptor 2 pointed at a temporary file while any thread is inside ``captured()``: how many are (``users``),
    the file and the descriptor 2 to give back."""

    def __init__(self) -> None:
        self.users, self.file, self.saved = 0, None, -1

    def enter(self) -> int:
        """Join the capture, starting it for the first user; the file's length now (where this user's text
        starts)."""
        if self.users == 0:
            try:
                sys.stderr.flush()
            except (AttributeError, ValueError, OSError):
                pass
            self.file = tempfile.TemporaryFile()
            self.saved = os.dup(2)
            os.dup2(self.file.fileno(), 2)
        self.users += 1
        return os.fstat(self.file.fileno()).st_size

    def leave(self, start: int) -> str:
        """Leave the capture, ending it for the last user; what was printed since ``start``."""
        self.file.seek(start)
        text = self.file.read(65536).decode("utf-8", errors="replace")
        self.users -= 1
        if self.users == 0:
            os.dup2(self.saved, 2)
            os.close(self.saved)
            self.file.close()
            self.file, self.saved = None, -1
        return text


_sink = _Sink()


@contextlib.contextmanager
def captured() -> Iterator[Captured]:
    """Point descriptor 2 at a temporary file for the block when capturing is on; yield what was printed.

    Descriptor 2 belongs to the whole process: blocks in several threads share one capture, which ends when the
    last of them does, so nothing a library prints inside any block reaches the terminal. A block's text is all
    that was printed while it ran, in any thread.
    """
    result = Captured()
    if not _enabled:
        yield result
        return
    with _lock:
        start = _sink.enter()
    try:
        yield result
    finally:
        with _lock:
            result.text = _sink.leave(start)
