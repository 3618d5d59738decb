"""Progress reporting and cancellation shared by every long stage.

A progress callback has the signature ``progress(fraction, message)`` with
``fraction`` in [0, 1]; a cancel callback takes no argument and returns True
when the work must stop. Both are optional everywhere.
"""

from __future__ import annotations

import sys
import time
from typing import Callable, Optional

from .errors import Cancelled

ProgressFn = Optional[Callable[[float, str], None]]
CancelFn = Optional[Callable[[], bool]]


class Stage:
    """Maps a sub-stage's own [0, 1] progress onto a slice [start, end] of the whole."""

    def __init__(self, progress: ProgressFn, cancel: CancelFn, start: float = 0.0, end: float = 1.0):
        self.progress = progress
        self.cancel = cancel
        self.start = start
        self.end = end

    def report(self, fraction: float, message: str) -> None:
        """Report ``fraction`` (0..1 of this stage) and raise Cancelled if asked to stop."""
        if self.progress is not None:
            f = self.start + (self.end - self.start) * min(max(fraction, 0.0), 1.0)
            self.progress(f, message)
        self.check()

    def check(self) -> None:
        """Raise Cancelled when the cancel callback says so."""
        if self.cancel is not None and self.cancel():
            raise Cancelled("The run was cancelled; no output was written.")

    def sub(self, start: float, end: float) -> "Stage":
        """A stage covering [start, end] of this one."""
        span = self.end - self.start
        return Stage(self.progress, self.cancel, self.start + span * start, self.start + span * end)


class ConsoleProgress:
    """A single self-overwriting progress line on stderr, at most ten updates a second."""

    def __init__(self, stream=None, min_interval: float = 0.1):
        self.stream = stream if stream is not None else sys.stderr
        self.min_interval = min_interval
        self._last = 0.0
        self._width = 0

    def __call__(self, fraction: float, message: str) -> None:
        now = time.monotonic()
        if fraction < 1.0 and now - self._last < self.min_interval:
            return
        self._last = now
        line = f"{100.0 * fraction:5.1f}%  {message}"
        pad = max(0, self._width - len(line))
        self._width = len(line)
        self.stream.write("\r" + line + " " * pad)
        self.stream.flush()

    def close(self) -> None:
        """End the progress line."""
        if self._width:
            self.stream.write("\n")
            self.stream.flush()
            self._width = 0
