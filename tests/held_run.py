"""``python -m core`` held at a chosen point of its work, so that a test acts on it there and nowhere else.

``start(arguments, point, count)`` runs ``python -m core ARGUMENTS`` in a child process in which the function
``point`` ("package.module:function", looked up on its module at each call) is wrapped: once its ``count``-th call
has returned, the child writes the line HELD to its stdout and waits for a line (or the end) on its stdin before
it goes on. ``held(process)`` waits for that line, however slow the machine; the test then signals or kills the
child, or starts a second command against it, and ``release(process)`` lets it go on. The shipped code knows
nothing of it: the child runs ``core/__main__.py`` as ``python -m core`` does, with its own signal handlers.

Run as a script it is that child: ``python tests/held_run.py POINT COUNT ARGUMENTS...``.
"""

from __future__ import annotations

import importlib
import os
import runpy
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
HELD = "paint-relief-test: held"
"""The line the child writes once it is held."""


def start(arguments, point: str, count: int = 1) -> subprocess.Popen:
    """The child running ``python -m core ARGUMENTS``, to be held after the ``count``-th call of ``point``; text
    pipes on its stdin, stdout and stderr."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), PYTHONDONTWRITEBYTECODE="1")
    return subprocess.Popen([sys.executable, __file__, point, str(count), *map(str, arguments)],
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=env, cwd=ROOT)


def held(process: subprocess.Popen) -> None:
    """Wait until ``process`` is held (its HELD line), however long it takes; AssertionError, with its stderr,
    when it ends without reaching the point."""
    for line in process.stdout:
        if line.rstrip("\n") == HELD:
            return
    process.wait()
    raise AssertionError(f"the command ended (status {process.returncode}) before it reached its point: "
                         f"{process.stderr.read()}")


def release(process: subprocess.Popen, timeout: float = 600) -> tuple:
    """Let a held ``process`` go on and wait for its end; (stdout, stderr). ``timeout`` only guards against a
    hang: far beyond the seconds a test's command takes on a loaded machine."""
    return process.communicate("\n", timeout=timeout)


def _hold_after(point: str, count: int) -> None:
    module_name, name = point.split(":")
    module = importlib.import_module(module_name)
    real = getattr(module, name)
    calls = 0

    def wrapped(*args, **kwargs):
        nonlocal calls
        result = real(*args, **kwargs)
        calls += 1
        if calls == count:
            print(HELD, flush=True)
            sys.stdin.readline()
        return result

    setattr(module, name, wrapped)


if __name__ == "__main__":
    sys.path[0] = str(ROOT)  # the painter's tree, not tests/, as for ``python -m core`` run there
    _hold_after(sys.argv[1], int(sys.argv[2]))
    sys.argv = ["core", *sys.argv[3:]]
    runpy.run_module("core", run_name="__main__", alter_sys=True)
