"""The C heap while painting: the temporaries of one stroke reused by the next instead of mapped afresh.

A stroke of a wide brush makes tens of megabytes of temporary arrays. By
default glibc's malloc gives freed memory back to the system as soon as the
free space at the top of its heap passes a threshold, and serves large blocks
from fresh mappings, so the next stroke faults every page in again: at 10
megapixels about a tenth of the painting time went to page faults. Inside
``reused_heap()`` blocks up to MMAP_THRESHOLD come from the heap and up to
TRIM_THRESHOLD of free heap is kept; on leaving, glibc's default thresholds
come back and the free heap is returned to the system (``malloc_trim``).
Full-image arrays (larger than MMAP_THRESHOLD from about 3 megapixels) are
still mapped and unmapped as before. The painter's worker threads
(``core.workers``) allocate from the same heap (M_ARENA_MAX 1, for the rest
of the process's life), so what one thread frees the next allocation reuses
whichever thread makes it, instead of each thread's own heap keeping its
freed blocks beside the others'. Other C libraries are left as they are.

The thresholds are process-wide, and glibc can neither report them nor give
back its dynamic mmap threshold once they are set, so only the painter's own
process uses this: ``python -m core paint`` wraps its run in it. Inside
Blender (``core.paint_file`` from the panel) the heap is left as Blender set it.
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import threading
from typing import Iterator

M_TRIM_THRESHOLD = -1
M_MMAP_THRESHOLD = -3
M_ARENA_MAX = -8
MMAP_THRESHOLD = 32 * 2**20      # glibc's largest allowed value on 64-bit systems
TRIM_THRESHOLD = 256 * 2**20
DEFAULT_THRESHOLD = 128 * 2**10  # glibc's default for both

_lock = threading.Lock()
_users = 0


def _glibc():
    """The C library when it is glibc (it has mallopt and malloc_trim), else None."""
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        return libc if hasattr(libc, "mallopt") and hasattr(libc, "malloc_trim") else None
    except OSError:
        return None


@contextlib.contextmanager
def reused_heap() -> Iterator[None]:
    """Keep freed blocks in the heap for the block's duration (nested and threaded uses count; glibc only)."""
    global _users
    libc = _glibc()
    if libc is None:
        yield
        return
    with _lock:
        _users += 1
        if _users == 1:
            libc.mallopt(M_MMAP_THRESHOLD, MMAP_THRESHOLD)
            libc.mallopt(M_TRIM_THRESHOLD, TRIM_THRESHOLD)
            libc.mallopt(M_ARENA_MAX, 1)
    try:
        yield
    finally:
        with _lock:
            _users -= 1
            if _users == 0:
                libc.mallopt(M_MMAP_THRESHOLD, DEFAULT_THRESHOLD)
                libc.mallopt(M_TRIM_THRESHOLD, DEFAULT_THRESHOLD)
                libc.malloc_trim(0)
