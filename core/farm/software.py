"""What a Dask worker runs of the painter and of the libraries its bytes depend on, compared with this process.

A cluster paints the bytes of one process only when every worker runs the
painter's version and the NumPy, SciPy and OpenImageIO versions of the
command. ``installed`` answers that on each worker. It travels as its source
text, evaluated there by Python's built-in ``eval`` (``on_worker``), never as
pickled code or a reference into the painter, and uses the standard library
only: a worker that cannot import the painter, or runs another Python, answers
too.
"""

from __future__ import annotations

import inspect
import textwrap
from typing import Dict, Optional, Sequence, Tuple

PAINTER = "Paint Relief"

PACKAGES: Tuple[Tuple[str, str, str, Optional[str]], ...] = (
    (PAINTER, "core.version", "__version__", None),
    ("NumPy", "numpy", "__version__", "numpy"),
    ("SciPy", "scipy", "__version__", "scipy"),
    ("OpenImageIO", "OpenImageIO", "VERSION_STRING", "OpenImageIO"),
)
"""(name, module, the module's version attribute, pip's name or None for the painter itself) of what is compared."""

INSTALL = 'pip install ".[farm]"'
"""What installs the painter and Dask on a worker, from a checkout of the painter."""


def installed(packages: Sequence[Tuple[str, str, str, Optional[str]]]) -> dict:
    """Run on a worker (and here): {"host": its host name, "versions": {name: version or None}, "errors": {name:
    why it could not be imported}} for each (name, module, attribute, _) of ``packages``. Standard library only."""
    import importlib
    import socket

    versions: Dict[str, Optional[str]] = {}
    errors: Dict[str, str] = {}
    for name, module, attribute, _ in packages:
        try:
            versions[name] = str(getattr(importlib.import_module(module), attribute))
        except Exception as exc:  # an import that fails in any way is what this tells
            versions[name] = None
            errors[name] = " ".join(str(exc).split()).rstrip(".") or type(exc).__name__
    return {"host": socket.gethostname(), "versions": versions, "errors": errors}


def difference(worker: str, theirs: dict, ours: dict) -> Optional[str]:
    """One sentence naming ``worker`` (its address) when what it runs (``installed`` there: ``theirs``) differs from
    this process's (``ours``), with what differs and what to install; None when they are the same."""
    where = f"The Dask worker {worker} on {theirs['host']}"
    if theirs["versions"].get(PAINTER) is None:
        why = theirs["errors"].get(PAINTER, "not found")
        return f"{where} cannot import the painter ({why}): install it on every worker ({INSTALL} from this checkout)."
    names = [name for name, *_ in PACKAGES if theirs["versions"].get(name) != ours["versions"].get(name)]
    if not names:
        return None
    pins = [f"{pip}=={ours['versions'][name]}" for name, _, _, pip in PACKAGES
            if name in names and pip and ours["versions"].get(name)]
    return (f"{where} runs {listed(names, theirs)} but this command runs {listed(names, ours)}: install the same "
            f"versions on every worker ({' '.join([INSTALL, *pins])} from this checkout).")


def listed(names: Sequence[str], found: dict) -> str:
    """"NumPy 1.26.4 and no SciPy": the versions of ``names`` in ``found`` (``installed``'s answer)."""
    said = [f"{name} {found['versions'][name]}" if found["versions"].get(name) else f"no {name}" for name in names]
    return said[0] if len(said) == 1 else ", ".join(said[:-1]) + " and " + said[-1]


def on_worker(function, *args) -> str:
    """An expression that, given to the built-in ``eval`` on a worker, defines ``function`` there from its source
    text and returns ``function(*args)``; ``args`` are plain values written as Python literals."""
    source = "from __future__ import annotations\n" + textwrap.dedent(inspect.getsource(function))
    return f"(lambda space: (exec({source!r}, space), space[{function.__name__!r}](*{args!r}))[1])({{}})"
