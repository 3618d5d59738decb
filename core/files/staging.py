"""All-or-nothing output folders: a run's files appear together or not at all.

The guarantee. Whatever fails and whenever the process stops (an error, a
full disk, SIGINT, SIGTERM, SIGKILL, power loss), the output folder holds
either every file of the new run or exactly the files it held before; files
in it that the run does not write (other outputs, the user's own files and
folders) are never touched. The folder is only ever mixed between the commit
point and the end of the commit (a handful of renames) when the process is
killed (SIGKILL or power loss) in that window; the commit is then completed by
the next run into the folder (and by ``settle``, which readers such as the
map check call) before anything else happens there.

How. One writer per folder holds ``folderlock`` for the whole run. Files are
written into a hidden staging folder ``OUT/.staging-<pid>-<random>`` on the
same file system and flushed to disk (``fsync``). The commit point is the
atomic rename of a journal ``OUT/.paint-relief-commit.json`` (flushed, and
its folder flushed) that names the staging folder and its files. After it,
the files are renamed into ``OUT`` one by one (each rename atomic), then the
journal and the staging folder are removed. A journal found by a later run
is rolled forward the same way (renames are idempotent: a file already moved
is no longer in the staging folder); staging folders without a journal are
the remains of runs stopped before their commit point and are removed.
SIGINT and SIGTERM are held back (``signals.deferred``) from the commit
point to the end of the clean-up, so only SIGKILL or power loss can stop a
commit midway. A name that cannot be replaced (a folder where a file should
be) is found before the commit point and refused with one sentence.

A run that created the output folder (and its parents) and then failed
removes them again, so a failed run leaves no folder behind.
"""

from __future__ import annotations

import contextlib
import json
import os
import pathlib
import secrets
import shutil
from typing import Iterator, List, Optional

from ..errors import OutputError, plain_cause
from . import folderlock, signals
from .writing import is_temporary_name

STAGING_PREFIX = ".staging-"
JOURNAL_NAME = ".paint-relief-commit.json"
_JOURNAL_TEMP_PREFIX = JOURNAL_NAME + ".tmp-"
PROBE_PREFIX = ".paint-relief-probe-"
RETIRED_PREFIX = ".retired-"
"""The name a committed folder (a time-lapse) that a new one replaces has between the two renames."""


def _why(exc: OSError) -> str:
    """The lower-case reason of an OSError in plain words, without a full stop."""
    return plain_cause(exc)


def _fsync_file(path: pathlib.Path) -> None:
    """Flush a written file's data to disk."""
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def fsync_folder(path: pathlib.Path) -> None:
    """Flush a folder's entries (renames, new files) to disk where the platform allows it."""
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def _safe_name(name: object) -> bool:
    """True for a plain file name (no separators, not '.' or '..')."""
    return isinstance(name, str) and name not in ("", ".", "..") and "/" not in name and os.sep not in name


def _roll_forward(folder: pathlib.Path, staging_name: str, names: List[str]) -> None:
    """Move every named file still in the staging folder into ``folder``; then drop the journal and staging.

    A staged folder (a time-lapse's) replaces the folder of its name: that one is renamed aside
    (``RETIRED_PREFIX``), the new one renamed in, the old one removed; a run stopped in between is finished
    the same way by the next (the old one is removed by ``recover``)."""
    staging = folder / staging_name
    for name in names:
        source, target = staging / name, folder / name
        if not os.path.lexists(source):
            continue
        if source.is_dir() and not source.is_symlink() and target.is_dir() and not target.is_symlink():
            retired = folder / f"{RETIRED_PREFIX}{staging_name}-{name}"
            shutil.rmtree(retired, ignore_errors=True)
            os.replace(target, retired)
            os.replace(source, target)
            shutil.rmtree(retired, ignore_errors=True)
        else:
            os.replace(source, target)
    fsync_folder(folder)
    try:
        (folder / JOURNAL_NAME).unlink()
    except FileNotFoundError:
        pass
    fsync_folder(folder)
    shutil.rmtree(staging, ignore_errors=True)


def recover(folder: pathlib.Path) -> None:
    """Finish a committed run's commit and remove the remains of stopped runs in ``folder``.

    The caller must hold the folder's lock. A journal is rolled forward; a
    journal that cannot be parsed cannot have been committed (the journal
    appears by one rename of a complete file) and is removed. Then every
    ``.staging-*`` folder, journal temporary and write probe left in
    ``folder`` is removed, and every temporary file a writer killed midway
    left there (``writing.is_temporary_name``: the lives file is written in
    the folder itself). Raises OutputError when a committed run cannot be
    completed.
    """
    folder = pathlib.Path(folder)
    journal = folder / JOURNAL_NAME
    with signals.deferred():
        if journal.exists():
            try:
                entry = json.loads(journal.read_text(encoding="utf-8"))
                staging_name, names = entry["staging"], list(entry["files"])
                valid = (_safe_name(staging_name) and staging_name.startswith(STAGING_PREFIX)
                         and all(_safe_name(n) for n in names))
            except (OSError, ValueError, KeyError, TypeError):
                valid = False
            try:
                if valid:
                    _roll_forward(folder, staging_name, names)
                else:
                    journal.unlink()
            except OSError as exc:
                raise OutputError(f"Cannot finish the interrupted commit in {folder}: {_why(exc)}.") from exc
        try:
            entries = list(os.scandir(folder))
        except OSError:
            return
        for entry in entries:
            if entry.name.startswith((STAGING_PREFIX, RETIRED_PREFIX)) and entry.is_dir(follow_symlinks=False):
                shutil.rmtree(entry.path, ignore_errors=True)
            elif entry.name.startswith((_JOURNAL_TEMP_PREFIX, PROBE_PREFIX)) or (
                    is_temporary_name(entry.name) and entry.is_file(follow_symlinks=False)):
                with contextlib.suppress(OSError):
                    os.unlink(entry.path)


def settle(folder: pathlib.Path) -> None:
    """Complete an interrupted commit in ``folder`` when no run is writing there; otherwise do nothing.

    For readers: after ``settle`` a folder no writer holds is never mixed,
    and holds no staging folder, journal or lock file of a stopped run.
    Never raises.
    """
    folder = pathlib.Path(folder)
    if not any(p.name.startswith((STAGING_PREFIX, JOURNAL_NAME, folderlock.LOCK_NAME)) for p in _listing(folder)):
        return
    try:
        with folderlock.acquire(folder, attempts=2):
            recover(folder)
    except OutputError:
        pass


def _listing(folder: pathlib.Path) -> List[pathlib.Path]:
    try:
        return list(folder.iterdir())
    except OSError:
        return []


class OutputFolder:
    """An output folder locked for one run: ``staged()`` writes a set of files all-or-nothing."""

    def __init__(self, folder: pathlib.Path, lock: folderlock.FolderLock):
        self.folder = folder
        self.lock = lock
        self.committed = False

    @contextlib.contextmanager
    def staged(self, staging: Optional[pathlib.Path] = None) -> Iterator[pathlib.Path]:
        """Yield a staging folder; when the body succeeds, commit its files into the folder.

        The staging folder is a new empty one, or ``staging``: one that
        ``new_staging`` made in this folder and another process (a worker of
        a cluster sharing the storage) filled, which this commit takes over.
        On an exception (or a signal) the staging folder is removed and the
        folder keeps exactly the files it had. A file name whose target is a
        folder raises OutputError before anything is replaced. A file that
        could not be written in the staging folder (a full disk) is reported
        by its name and this folder, never by its hidden staging path.
        """
        staging = pathlib.Path(staging) if staging is not None else new_staging(self.folder)
        try:
            yield staging
            names = sorted(p.name for p in staging.iterdir())
            self._check_targets([name for name in names if not (staging / name).is_dir()])
            self._check_folders([name for name in names if (staging / name).is_dir()])
            for name in names:
                inner = sorted((staging / name).iterdir()) if (staging / name).is_dir() else []
                for path in inner + [staging / name]:
                    try:
                        _fsync_file(path)
                    except OSError as exc:
                        raise OutputError(f"Cannot write {name}: {_why(exc)}.", staging / name,
                                          _why(exc)) from exc
            fsync_folder(staging)
        except BaseException as exc:
            with signals.deferred():
                shutil.rmtree(staging, ignore_errors=True)
            if isinstance(exc, OutputError) and exc.path is not None and pathlib.Path(exc.path).parent == staging:
                raise OutputError(f"Cannot write {pathlib.Path(exc.path).name} into the output folder {self.folder}: "
                                  f"{exc.cause or 'it could not be written'}; the folder was left as it was.",
                                  self.folder / pathlib.Path(exc.path).name, exc.cause) from exc
            raise
        try:
            with signals.deferred():
                try:
                    self._commit(staging, names)
                except BaseException:
                    if not (self.folder / JOURNAL_NAME).exists():
                        shutil.rmtree(staging, ignore_errors=True)
                    raise
                self.committed = True
        except signals.Interrupted as exc:
            if self.committed:
                exc.committed = str(self.folder)
            raise

    def check_names(self, names: List[str]) -> None:
        """OutputError (one sentence naming the path) when something stands where one of the files ``names`` must
        go and could not be replaced: called before any work, so nothing is painted in vain."""
        self._check_targets(names)

    def check_folders(self, names: List[str]) -> None:
        """OutputError (one sentence naming the path) when a file stands where one of the folders ``names`` (a
        time-lapse) must go: called before any work."""
        self._check_folders(names)

    def _check_folders(self, names: List[str]) -> None:
        """OutputError when a target folder name is taken by something else than a folder."""
        for name in names:
            target = self.folder / name
            if os.path.lexists(target) and not (target.is_dir() and not target.is_symlink()):
                raise OutputError(f"Cannot write {target}: a file of that name is in the way.")

    def _check_targets(self, names: List[str]) -> None:
        """OutputError when a target name is taken by a folder (a rename could not replace it)."""
        for name in names:
            target = self.folder / name
            if target.is_dir() and not target.is_symlink():
                raise OutputError(f"Cannot write {target}: a folder of that name is in the way.")

    def _commit(self, staging: pathlib.Path, names: List[str]) -> None:
        """Write the journal (the commit point), then roll forward."""
        temp = self.folder / f"{_JOURNAL_TEMP_PREFIX}{secrets.token_hex(4)}"
        text = json.dumps({"staging": staging.name, "files": names})
        try:
            with open(temp, "w", encoding="utf-8") as f:
                f.write(text)
                f.flush()
                os.fsync(f.fileno())
            os.replace(temp, self.folder / JOURNAL_NAME)
        except OSError as exc:
            with contextlib.suppress(OSError):
                temp.unlink()
            raise OutputError(f"Cannot write to output folder {self.folder}: {_why(exc)}.") from exc
        fsync_folder(self.folder)
        try:
            _roll_forward(self.folder, staging.name, names)
        except OSError as exc:
            raise OutputError(f"Cannot finish writing the outputs into {self.folder}: {_why(exc)}; "
                              f"the next run into that folder completes them.") from exc


def _missing_parents(folder: pathlib.Path) -> List[pathlib.Path]:
    """``folder`` and its ancestors that do not exist yet, outermost first."""
    missing = []
    p = folder
    while not os.path.lexists(p):
        missing.append(p)
        if p.parent == p:
            break
        p = p.parent
    return list(reversed(missing))


def new_staging(folder: pathlib.Path) -> pathlib.Path:
    """Make and return a new empty staging folder in the output folder ``folder`` (its name unique across
    processes and machines); OutputError when it cannot be made."""
    staging = pathlib.Path(folder) / f"{STAGING_PREFIX}{os.getpid()}-{secrets.token_hex(8)}"
    try:
        staging.mkdir()
    except OSError as exc:
        raise OutputError(f"Cannot write to output folder {folder}: {_why(exc)}.") from exc
    return staging


@contextlib.contextmanager
def output_folder(path) -> Iterator[OutputFolder]:
    """Create (if needed) and lock the output folder ``path`` for one run; yield an OutputFolder.

    On entry: an interrupted earlier commit is completed and stopped runs'
    staging folders are removed. On exit the lock is released; when the body
    raised and this call created the folder (or its parents), the folders it
    created are removed again if they hold nothing. OutputError (one
    sentence) when the folder cannot be created or written, or another run
    holds it.
    """
    folder = pathlib.Path(path)
    if folder.is_symlink() and not folder.exists():
        raise OutputError(f"Cannot write to output folder {folder}: it is a symbolic link whose target "
                          f"{os.readlink(folder)} does not exist.")
    created = _missing_parents(folder)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except FileExistsError as exc:
        raise OutputError(f"Cannot write to output folder {folder}: a file of that name is in the way.") from exc
    except OSError as exc:
        _remove_empty(created)
        raise OutputError(f"Cannot write to output folder {folder}: {_why(exc)}.") from exc
    if not folder.is_dir():
        raise OutputError(f"Cannot write to output folder {folder}: a file of that name is in the way.")
    ok = False
    target: Optional[OutputFolder] = None
    try:
        lock = folderlock.acquire(folder)
        try:
            recover(folder)
            target = OutputFolder(folder, lock)
            yield target
            ok = True
        finally:
            with signals.deferred():
                lock.release()
    except signals.Interrupted as exc:
        if target is not None and target.committed and exc.committed is None:
            exc.committed = str(folder)
        raise
    finally:
        if not ok and not (target is not None and target.committed):
            with signals.deferred():
                _remove_empty(created)


def _remove_empty(created: List[pathlib.Path]) -> None:
    """Remove the folders in ``created`` (outermost first) innermost first, each only if empty."""
    for p in reversed(created):
        try:
            os.rmdir(p)
        except OSError:
            return


@contextlib.contextmanager
def staged_outputs(out_dir, folder: Optional[OutputFolder] = None) -> Iterator[pathlib.Path]:
    """Yield a staging folder for ``out_dir``; on success its files are committed into ``out_dir`` together.

    Creates and locks ``out_dir`` for the duration unless ``folder`` (an
    OutputFolder this run already holds) is given. See the module docstring
    for the guarantee.
    """
    if folder is not None:
        with folder.staged() as staging:
            yield staging
        return
    with output_folder(out_dir) as held, held.staged() as staging:
        yield staging
