"""``core object MODEL``: a model file (.glb, .gltf, .obj, .fbx or a .blend scene) painted by
``sample_scenes/paint_object.py`` in a Blender found on this machine, run as a process of its own (core never
imports bpy).

The Blender is, in this order: the program or Python that the environment variable ``PAINT_RELIEF_BLENDER`` names
(a name beginning with "blender" is run as the Blender program, any other as a Python interpreter with the
``bpy`` module); the Python running this, when it has the ``bpy`` module; ``blender`` on the PATH.
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path
from typing import List, Optional

from .errors import InputError

MODEL_EXTENSIONS = (".glb", ".gltf", ".obj", ".fbx", ".blend")
"""The files ``core object`` paints through Blender: what Blender's own importers read, and its scenes."""
SCRIPT = Path(__file__).resolve().parent.parent / "sample_scenes" / "paint_object.py"
ENVIRONMENT = "PAINT_RELIEF_BLENDER"


def is_model(path) -> bool:
    """Whether ``path`` names a model file or a Blender scene by its extension (any case)."""
    return Path(path).suffix.lower() in MODEL_EXTENSIONS


def _refused(sentence: str) -> InputError:
    """An InputError whose command line ends with exit status 1."""
    error = InputError(sentence)
    error.status = 1
    return error


def find_blender(model) -> List[str]:
    """The command that runs a Python script in Blender, the script's path and arguments to follow: a Blender
    program's ``[blender, -b, --python-exit-code, 1, --python]`` (then ``SCRIPT -- ARGS``) or a Python's
    ``[python]`` (then ``SCRIPT ARGS``). The search is this module's docstring; none found is one sentence naming
    ``model``."""
    named = os.environ.get(ENVIRONMENT, "").strip()
    if named:
        program = shutil.which(named) or (named if os.path.isfile(named) else None)
        if program is None:
            raise _refused(f"Painting the model {model} needs Blender, but {ENVIRONMENT} names {named}, which is no "
                           f"program here: set it to a blender program or a Python with the bpy module.")
        return _command(program, Path(program).name.lower().startswith("blender"))
    if importlib.util.find_spec("bpy") is not None:
        return _command(sys.executable, False)
    program = shutil.which("blender")
    if program is not None:
        return _command(program, True)
    raise _refused(f"Painting the model {model} needs Blender, and none was found: install Blender (blender on the "
                   f"PATH) or the bpy module (pip install bpy), or set {ENVIRONMENT} to a blender program or a "
                   f"Python with bpy.")


def _command(program: str, is_blender: bool) -> List[str]:
    return [program, "-b", "--python-exit-code", "1", "--python"] if is_blender else [program]


def paint_model(model, output, name: Optional[str] = None, texture_size: Optional[int] = None, seed: int = 0,
                views: Optional[int] = None, samples: Optional[int] = None, resolution: Optional[int] = None,
                relief: Optional[str] = None) -> int:
    """Run ``sample_scenes/paint_object.py MODEL -o OUTPUT`` (and the options given) in the Blender
    ``find_blender`` finds; its output goes to this process's; returns its exit status (0 painted, 1 one
    sentence on stderr, 2 a malformed command line, 130 Ctrl-C)."""
    command = find_blender(model)
    if not SCRIPT.is_file():
        raise _refused(f"Painting the model {model} needs {SCRIPT}, the script of a Paint Relief checkout, which is "
                       f"not there.")
    arguments = [str(model), "-o", str(output), "--seed", str(seed)]
    for option, value in (("--object", name), ("--texture-size", texture_size), ("--views", views),
                          ("--samples", samples), ("--resolution", resolution), ("--relief", relief)):
        if value is not None:
            arguments += [option, str(value)]
    if len(command) > 1:            # Blender's own options end at "--"; the script's follow
        arguments = ["--"] + arguments
    sys.stdout.flush()
    sys.stderr.flush()
    child = subprocess.Popen(command + [str(SCRIPT)] + arguments)
    # The script answers a signal itself (one sentence, its folder left whole): Ctrl-C at a terminal reaches it
    # directly, SIGTERM is passed on, and this process waits for its answer.
    handlers = {}
    try:
        handlers[signal.SIGINT] = signal.signal(signal.SIGINT, lambda signum, frame: None)
        handlers[signal.SIGTERM] = signal.signal(signal.SIGTERM, lambda signum, frame: child.send_signal(signum))
    except ValueError:      # not the main thread: signals stay as they are
        pass
    try:
        return child.wait()
    finally:
        for signum, handler in handlers.items():
            signal.signal(signum, handler)
