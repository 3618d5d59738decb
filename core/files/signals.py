"""SIGINT and SIGTERM as an exception, and sections of code they cannot cut in two.

``install()`` (main thread only, used by the command line) makes both
signals raise ``Interrupted`` in the main thread, so every ``finally`` and
context manager on the way out runs: staging folders are removed, locks
released. Inside ``deferred()`` a signal is only recorded and raised when
the section ends, so a commit or a clean-up is never left half done.
"""

from __future__ import annotations

import contextlib
import signal
import threading
from typing import Iterator, Optional

_NAMES = {signal.SIGINT: "SIGINT", signal.SIGTERM: "SIGTERM"}


class Interrupted(BaseException):
    """A run was stopped by a signal; ``status`` is the conventional exit status 128 + signal number.

    ``committed`` names the folder whose outputs were completely written
    before the signal took effect (None when nothing was written).
    """

    def __init__(self, signum: int):
        self.signum = int(signum)
        self.name = _NAMES.get(signum, f"signal {signum}")
        self.status = 128 + self.signum
        self.committed: Optional[str] = None
        super().__init__(self.name)


_depth = 0
_pending: Optional[int] = None


def _handler(signum, frame) -> None:
    global _pending
    if _depth > 0:
        _pending = signum
        return
    raise Interrupted(signum)


def install() -> callable:
    """Make SIGINT and SIGTERM raise Interrupted and ignore SIGXFSZ; returns a function restoring the previous handlers.

    Does nothing (and returns a no-op) outside the main thread, where Python
    cannot install handlers.
    """
    if threading.current_thread() is not threading.main_thread():
        return lambda: None
    previous = {s: signal.signal(s, _handler) for s in _NAMES}
    if hasattr(signal, "SIGXFSZ"):  # a file-size limit then fails the write (EFBIG) instead of killing the process
        previous[signal.SIGXFSZ] = signal.signal(signal.SIGXFSZ, signal.SIG_IGN)

    def restore() -> None:
        for s, h in previous.items():
            signal.signal(s, h)
    return restore


@contextlib.contextmanager
def deferred() -> Iterator[None]:
    """Run the body to its end even if SIGINT or SIGTERM arrives; raise Interrupted afterwards.

    Nests. Only the main thread receives signals, so in other threads this
    does nothing (a commit there is never cut by a signal).
    """
    global _depth, _pending
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    _depth += 1
    try:
        yield
    finally:
        _depth -= 1
        if _depth == 0 and _pending is not None:
            signum, _pending = _pending, None
            raise Interrupted(signum)
