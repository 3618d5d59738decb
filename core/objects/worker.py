"""The process that paints jobs of ``paint_objects`` one after another: ``python -m core.objects.worker FOLDER
THREADS``.

It is started with the folder of the extension (the parent of ``core``) on
its path, so it imports ``core`` as a package of its own, never the package
that holds it inside Blender (that one imports ``bpy``). It reads lines
``paint K`` on stdin; for each it reads job K from ``FOLDER``
(``jobs.write_job``), paints it with ``core.paint_object`` on at most
``THREADS`` worker threads (which changes no byte: ``core.workers``),
writes ``<K>.result.json`` ({"report": the report} or {"error": {"kind":
the error's class, "message": its one sentence}}, whole or not at all) and
says ``DONE_TAG K`` on stdout. Its progress goes to stdout too, a line
``PROGRESS_TAG K [fraction, message]`` at a time. It ends at the end of
stdin. A job stops, as ``paint_object`` stops when cancelled (nothing
written), once the file ``STOP_FILE`` appears in ``FOLDER``. Starting once
for several jobs, a worker loads the painter's modules once.
"""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

PROGRESS_TAG = "paint-relief-progress"
"""The first word of a line of progress on the worker's stdout."""

DONE_TAG = "paint-relief-done"
"""The first word of the line saying that a job's result is written."""

STOP_FILE = "stop"
"""The file whose appearance in the jobs' folder stops every worker."""

PROGRESS_SECONDS = 0.1
"""Seconds at least between two lines of progress (the last, at fraction 1, always goes)."""


def result_name(index: int) -> str:
    """The name of the file holding job ``index``'s result."""
    return f"{index}.result.json"


def say(line: str) -> None:
    """Write ``line`` on stdout at once."""
    sys.stdout.write(line + "\n")
    sys.stdout.flush()


def paint_job(folder: Path, index: int) -> dict:
    """Paint job ``index`` of ``folder``; its result (module docstring)."""
    from ..api import paint_object
    from ..errors import PaintReliefError
    from .jobs import read_job

    stop = folder / STOP_FILE
    last = [0.0]

    def progress(fraction: float, message: str) -> None:
        now = time.monotonic()
        if fraction < 1.0 and now - last[0] < PROGRESS_SECONDS:
            return
        last[0] = now
        say(f"{PROGRESS_TAG} {index} {json.dumps([float(fraction), str(message)])}")

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
    """Paint the jobs named on stdin (module docstring); the exit status: 0, or 2 for wrong arguments."""
    from .. import tuning

    if len(arguments) != 2:
        sys.stderr.write("usage: python -m core.objects.worker FOLDER THREADS\n")
        return 2
    folder, tuning.MAX_WORKERS = Path(arguments[0]), max(1, int(arguments[1]))
    for line in sys.stdin:
        words = line.split()
        if len(words) != 2 or words[0] != "paint":
            continue
        index = int(words[1])
        result = paint_job(folder, index)
        target = folder / result_name(index)
        temporary = target.with_name(target.name + ".tmp")
        temporary.write_text(json.dumps(result), encoding="utf-8")
        os.replace(temporary, target)
        say(f"{DONE_TAG} {index}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
