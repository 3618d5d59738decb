"""Messages that image libraries print themselves, captured so they can be folded into our one sentence.

libpng, libjpeg and OpenEXR write warnings and errors straight to the
process's standard error (file descriptor 2), outside Python. Inside
``captured()`` descriptor 2 points at a temporary file; the text lands in
the yielded ``Captured`` and callers fold it into their message. Capturing
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


@contextlib.contextmanager
def captured() -> Iterator[Captured]:
    """Point descriptor 2 at a temporary file for the block when capturing is on; yield what was printed.

    Descriptor 2 belongs to the whole process: while one thread captures,
    a block in another thread captures nothing itself (what it prints lands
    in the first thread's capture) instead of waiting for it.
    """
    result = Captured()
    if not _enabled or not _lock.acquire(blocking=False):
        yield result
        return
    try:
        try:
            sys.stderr.flush()
        except (AttributeError, ValueError, OSError):
            pass
        saved = os.dup(2)
        with tempfile.TemporaryFile() as sink:
            os.dup2(sink.fileno(), 2)
            try:
                yield result
            finally:
                os.dup2(saved, 2)
                os.close(saved)
                sink.seek(0)
                result.text = sink.read(65536).decode("utf-8", errors="replace")
    finally:
        _lock.release()
