"""One writer per output folder: an exclusive lock on ``<folder>/.paint-relief.lock``.

The lock is an operating-system lock on an open file (``fcntl.flock`` on
POSIX, ``msvcrt.locking`` on Windows), so it belongs to the process that
holds it and vanishes with it: a lock file left behind by a process that was
killed (SIGKILL, power loss) is not held by anyone and the next run simply
takes it over. The file holds the owner's process id as decimal text, so a
second run that meets a held lock names the process in its one sentence.

On release the lock file is removed while it is still held. A run that
opened the old file just before it was removed notices, after locking, that
its file is no longer the one at the path and tries again, so two runs never
both believe they hold the folder.
"""

from __future__ import annotations

import os
import pathlib
from typing import Optional

from ..errors import OutputError, plain_cause

LOCK_NAME = ".paint-relief.lock"

try:  # POSIX
    import fcntl

    def _try_lock(fd: int) -> bool:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return True
        except BlockingIOError:
            return False

    def _unlock(fd: int) -> None:
        fcntl.flock(fd, fcntl.LOCK_UN)

    _REMOVE_ON_RELEASE = True
except ImportError:  # Windows
    import msvcrt

    def _try_lock(fd: int) -> bool:
        try:
            os.lseek(fd, 0, os.SEEK_SET)
            msvcrt.locking(fd, msvcrt.LK_NBLCK, 1)
            return True
        except OSError:
            return False

    def _unlock(fd: int) -> None:
        os.lseek(fd, 0, os.SEEK_SET)
        msvcrt.locking(fd, msvcrt.LK_UNLCK, 1)

    _REMOVE_ON_RELEASE = False  # an open file cannot be removed on Windows


def _owner(path: pathlib.Path) -> str:
    """The process id written in the lock file ``path``, or '' when unknown."""
    try:
        text = path.read_text(encoding="ascii", errors="replace").strip()
    except OSError:
        return ""
    return text if text.isdigit() else ""


class FolderLock:
    """The exclusive right to write into one folder; use as a context manager or call release()."""

    def __init__(self, folder: pathlib.Path, fd: int):
        self.folder = folder
        self.path = folder / LOCK_NAME
        self._fd: Optional[int] = fd

    @property
    def held(self) -> bool:
        """True until release()."""
        return self._fd is not None

    def release(self) -> None:
        """Remove the lock file (POSIX) and give up the lock; calling it twice does nothing."""
        fd, self._fd = self._fd, None
        if fd is None:
            return
        try:
            if _REMOVE_ON_RELEASE:
                try:
                    self.path.unlink()
                except OSError:
                    pass
            _unlock(fd)
        finally:
            os.close(fd)

    def __enter__(self) -> "FolderLock":
        return self

    def __exit__(self, *exc) -> None:
        self.release()


def acquire(folder: pathlib.Path, attempts: int = 20) -> FolderLock:
    """Take the lock of the existing ``folder`` or raise OutputError naming the process that holds it.

    Never waits: a held lock is reported at once. A lock file whose owner
    has died is taken over. ``attempts`` bounds the retries when the lock
    file is replaced between opening and locking it.
    """
    folder = pathlib.Path(folder)
    path = folder / LOCK_NAME
    for _ in range(attempts):
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as exc:
            raise OutputError(f"Cannot write to output folder {folder}: {plain_cause(exc, folder)}.") from exc
        if not _try_lock(fd):
            os.close(fd)
            owner = _owner(path)
            who = f"process {owner}" if owner else "another process"
            raise OutputError(f"The output folder {folder} is being written by {who}; "
                              f"wait for it to finish or choose another folder.")
        try:
            same = os.path.samestat(os.fstat(fd), os.stat(path))
        except FileNotFoundError:
            same = False
        if not same:  # the file was removed by its previous owner after we opened it
            _unlock(fd)
            os.close(fd)
            continue
        os.ftruncate(fd, 0)
        os.lseek(fd, 0, os.SEEK_SET)
        os.write(fd, str(os.getpid()).encode("ascii"))
        return FolderLock(folder, fd)
    raise OutputError(f"Cannot lock the output folder {folder}: its lock file keeps changing.")
