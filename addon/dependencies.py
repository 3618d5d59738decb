# SPDX-License-Identifier: GPL-3.0-or-later
"""The painter's libraries inside Blender, and the one check that says what is missing.

``core`` imports NumPy, SciPy, threadpoolctl and OpenImageIO. NumPy comes
with every Blender; SciPy and threadpoolctl (pure Python, one wheel for every
Blender) come from the extension's wheels. OpenImageIO is taken from
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

The package carries a SciPy wheel for each Python that Blender ships (3.11 for
4.2 LTS to 5.0, 3.13 for 5.1 and later), and Blender's installer takes the one
of the running Python. Blender 4.2.0 alone keeps one wheel per distribution,
the newest, whatever its Python, so on its Python 3.11 it installs the SciPy
built for 3.13, which cannot import. There :func:`load_own_wheel` unpacks this
Python's SciPy wheel from the package into the extension's user folder once
and puts that folder first on ``sys.path``, as Blender does with the folder of
the wheels it installs.

Nothing is imported when the extension is enabled: :func:`problem` runs when
an operator starts, before any painting or rendering.
"""

import importlib.machinery
import importlib.util
import os
import shutil
import sys
import zipfile

import bpy

OPENIMAGEIO = "OpenImageIO"
# (distribution, module whose import proves it works, what the painter needs it for, where it comes from)
REQUIRED = (
    ("numpy", "numpy", "arrays", "Blender's own Python"),
    ("scipy", "scipy.ndimage", "image filters", "the extension's SciPy wheel"),
    ("threadpoolctl", "threadpoolctl", "BLAS thread limits", "the extension's threadpoolctl wheel"),
    (OPENIMAGEIO, OPENIMAGEIO, "reading and writing images", None),
)
# The extension's package (``bl_ext.<repository>.paint_relief``) and its folder.
EXTENSION_PACKAGE = __package__.rpartition(".")[0]
EXTENSION_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


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


def own_wheel(distribution):
    """The package's wheel of ``distribution`` built for the running Python (``-cp311-`` on 3.11), or None."""
    folder = os.path.join(EXTENSION_DIR, "wheels")
    tag = "-cp{}{}-".format(*sys.version_info[:2])
    names = sorted(name for name in os.listdir(folder)
                   if name.startswith(distribution + "-") and tag in name and name.endswith(".whl")
                   ) if os.path.isdir(folder) else []
    return os.path.join(folder, names[-1]) if names else None


def load_own_wheel(distribution, module):
    """Import ``module`` from the package's own wheel of ``distribution`` for this Python; None when there is none.

    The wheel is unpacked once into the extension's user folder (through a
    temporary name, so an interrupted unpacking is never used), that folder
    goes first on ``sys.path`` and the modules of the unusable copy are
    forgotten.
    """
    wheel = own_wheel(distribution)
    if wheel is None:
        return None
    folder = bpy.utils.extension_path_user(EXTENSION_PACKAGE, path="wheels", create=True)
    target = os.path.join(folder, os.path.basename(wheel)[:-len(".whl")])
    if not os.path.isdir(target):
        partial = target + ".partial"
        shutil.rmtree(partial, ignore_errors=True)
        with zipfile.ZipFile(wheel) as archive:
            archive.extractall(partial)
        os.replace(partial, target)
    if target not in sys.path:
        sys.path.insert(0, target)
    for name in [n for n in sys.modules if n == distribution or n.startswith(distribution + ".")]:
        del sys.modules[name]
    importlib.invalidate_caches()
    return importlib.import_module(module)


def problem():
    """None when the painter's libraries import; else one sentence naming the missing one and the remedy.

    Imports them (OpenImageIO through :func:`load_openimageio`); call when an
    operator starts, never at registration.
    """
    version = bpy.app.version_string
    for name, module, use, source in REQUIRED:
        try:
            if name == OPENIMAGEIO:
                load_openimageio()
            else:
                try:
                    importlib.import_module(module)
                except ImportError:
                    if load_own_wheel(name, module) is None:
                        raise
        except ImportError as error:
            if name == OPENIMAGEIO:
                source = "Blender {} (which has no OpenImageIO binding) or the extension's OpenImageIO wheel".format(
                    version)
            reason = " ".join(str(error).split()).rstrip(".")
            return ("Paint Relief cannot start: the Python module {} ({}) should come from {} but does not "
                    "import ({}); install the Paint Relief package built for this platform again.".format(
                        name, use, source, reason))
    return None
