"""The process that paints one job of ``paint_objects``: ``python -m core.objects.worker FOLDER INDEX THREADS``.

It is started with the folder of the extension (the parent of ``core``) on
its path, so it imports ``core`` as a package of its own, never the package
that holds it inside Blender (that one imports ``bpy``). It reads job
``INDEX`` from ``FOLDER`` (``jobs.write_job``), paints it with
``core.paint_object`` on at most ``THREADS`` worker threads (which changes
no byte: ``core.workers``), and writes ``<INDEX>.result.json``: {"report":
the report} or {"error": {"kind": the error's class, "message": its one
sentence}}, whole or not at all. Its progress goes to stdout, a line
``PROGRESS_TAG [fraction, message]`` at a time. It stops, as
``paint_object`` stops when cancelled (nothing written), once the file
``STOP_FILE`` appears in ``FOLDER``.
"""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

PROGRESS_TAG = "paint-relief-progress"
"""The first word of a line of progress on the worker's stdout."""

STOP_FILE = "stop"
"""The file whose appearance in the jobs' folder stops every worker."""

PROGRESS_SECONDS = 0.1
"""Seconds at least between two lines of progress (the last, at fraction 1, always goes)."""


def result_name(index: int) -> str:
    """The name of the file holding job ``index``'s result."""
    return f"{index}.result.json"


def paint_job(folder: Path, index: int, threads: int) -> dict:
    """Paint job ``index`` of ``folder`` on at most ``threads`` worker threads; its result (module docstring)."""
    from .. import tuning
    from ..api import paint_object
    from ..errors import PaintReliefError
    from .jobs import read_job

    tuning.MAX_WORKERS = max(1, threads)
    stop = folder / STOP_FILE
    last = [0.0]

    def progress(fraction: float, message: str) -> None:
        now = time.monotonic()
        if fraction < 1.0 and now - last[0] < PROGRESS_SECONDS:
            return
        last[0] = now
        sys.stdout.write(f"{PROGRESS_TAG} {json.dumps([float(fraction), str(message)])}\n")
        sys.stdout.flush()

    job = read_job(folder, index)
    try:
        return {"report": paint_object(**job, progress=progress, cancel=stop.exists)}
    except PaintReliefError as exc:
        return {"error": {"kind": type(exc).__name__, "message": str(exc)}}
    except Exception as exc:    # a failure of the painter itself: the batch still hears it in one sentence
        why = str(exc).strip().rstrip(".") or "no reason given"
        return {"error": {"kind": "PaintReliefError",
                          "message": f"Painting into {job['output_dir']} failed: {type(exc).__name__}, {why}."}}


def main(arguments) -> int:
    """Run one job (module docstring); the exit status: 0 with its result written, 2 for wrong arguments."""
    if len(arguments) != 3:
        sys.stderr.write("usage: python -m core.objects.worker FOLDER INDEX THREADS\n")
        return 2
    folder, index, threads = Path(arguments[0]), int(arguments[1]), int(arguments[2])
    result = paint_job(folder, index, threads)
    target = folder / result_name(index)
    temporary = target.with_name(target.name + ".tmp")
    temporary.write_text(json.dumps(result), encoding="utf-8")
    os.replace(temporary, target)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
