# SPDX-License-Identifier: GPL-3.0-or-later
"""The painter's libraries inside Blender, and the one check that says what is missing.

``core`` imports NumPy, SciPy and OpenImageIO. NumPy comes with every
Blender; SciPy comes from the extension's wheels. OpenImageIO is taken from
Blender itself wherever Blender has its Python binding (Blender 4.4 and
later; in the ``bpy`` module it is exposed by
``bpy.utils.expose_bundled_modules()``), so the painter reads and writes
images with the very library Blender uses. Blender 4.2 LTS ships
OpenImageIO's libraries without a Python binding: there the OpenImageIO
wheel the manifest declares is used.

Blender puts the extensions' wheels ahead of its own modules on ``sys.path``,
so on Blender 5.x a plain ``import OpenImageIO`` would find the wheel; the
bundled binding is therefore loaded from Blender's own folder first, under
its usual name, and every later ``import OpenImageIO`` (the painter's
included) gets that one.

Nothing is imported when the extension is enabled: :func:`problem` runs when
an operator starts, before any painting or rendering.
"""

import importlib.machinery
import importlib.util
import os
import sys

import bpy

OPENIMAGEIO = "OpenImageIO"
# (module, what the painter needs it for, where it should have come from)
REQUIRED = (
    ("numpy", "arrays", "Blender's own Python"),
    ("scipy", "image filters", "the extension's SciPy wheel"),
    (OPENIMAGEIO, "reading and writing images", None),
)


def bundled_site_packages():
    """The folder of Python modules Blender bundles with itself, or None when it has none.

    In the ``bpy`` module (Blender 4.4+) ``expose_bundled_modules()`` is
    called first, as Blender documents for using its bundled bindings.
    """
    if getattr(bpy.app, "module", False) and hasattr(bpy.utils, "expose_bundled_modules"):
        bpy.utils.expose_bundled_modules()
    python = bpy.utils.system_resource("PYTHON")
    if not python:
        return None
    if sys.platform == "win32":
        folder = os.path.join(python, "lib", "site-packages")
    else:
        folder = os.path.join(python, "lib", "python{}.{}".format(*sys.version_info[:2]), "site-packages")
    return folder if os.path.isdir(folder) else None


def _load_from(name, folder):
    """Import package ``name`` from ``folder`` only, registered under ``name``; None when it is not there."""
    spec = importlib.machinery.PathFinder.find_spec(name, [folder])
    if spec is None or spec.loader is None:
        return None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[name]
        raise
    return module


def load_openimageio():
    """Import OpenImageIO, Blender's own binding first; return the module (ImportError when there is none).

    Once imported, the same module is returned: the choice is made once per
    Blender session.
    """
    if OPENIMAGEIO in sys.modules and sys.modules[OPENIMAGEIO] is not None:
        return sys.modules[OPENIMAGEIO]
    folder = bundled_site_packages()
    if folder is not None:
        try:
            module = _load_from(OPENIMAGEIO, folder)
        except ImportError:
            module = None  # a broken bundled binding: fall back to the extension's wheel
        if module is not None:
            return module
    return importlib.import_module(OPENIMAGEIO)


def openimageio_source(module):
    """'blender' when ``module`` is Blender's bundled binding, 'wheel' otherwise (the extension's)."""
    folder = bundled_site_packages()
    path = os.path.realpath(getattr(module, "__file__", "") or "")
    if folder is not None and path.startswith(os.path.realpath(folder) + os.sep):
        return "blender"
    return "wheel"


def problem():
    """None when the painter's libraries import; else one sentence naming the missing one and the remedy.

    Imports them (OpenImageIO through :func:`load_openimageio`); call when an
    operator starts, never at registration.
    """
    version = bpy.app.version_string
    for name, use, source in REQUIRED:
        try:
            if name == OPENIMAGEIO:
                load_openimageio()
            else:
                importlib.import_module(name)
        except ImportError as error:
            if name == OPENIMAGEIO:
                source = "Blender {} (which has no OpenImageIO binding) or the extension's OpenImageIO wheel".format(
                    version)
            reason = " ".join(str(error).split()).rstrip(".")
            return ("Paint Relief cannot start: the Python module {} ({}) should come from {} but does not "
                    "import ({}); install the Paint Relief package built for this platform again.".format(
                        name, use, source, reason))
    return None
