"""All-or-nothing output folders: files are written into a hidden staging
folder and moved into place only when every one of them was written."""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from pathlib import Path
from typing import Iterator

from .errors import OutputError


@contextlib.contextmanager
def staged_outputs(out_dir: Path) -> Iterator[Path]:
    """Yield a staging folder inside ``out_dir``; on success move its files into ``out_dir``.

    On any exception the staging folder is removed and ``out_dir`` keeps
    exactly the files it had before.
    """
    out_dir = Path(out_dir)
    try:
        staging = Path(tempfile.mkdtemp(prefix=".staging-", dir=out_dir))
    except OSError as exc:
        raise OutputError(f"Cannot write to output folder {out_dir}: {exc.strerror or exc}.") from exc
    try:
        yield staging
        for item in sorted(staging.iterdir()):
            os.replace(item, out_dir / item.name)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
