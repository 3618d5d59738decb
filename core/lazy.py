"""Packages whose public names load their modules on first use, so that importing the package stays light."""

from __future__ import annotations

import importlib
from typing import Callable, Dict, List, Tuple


def lazy_names(package: str, homes: Dict[str, str]) -> Tuple[Callable[[str], object], Callable[[], List[str]]]:
    """(``__getattr__``, ``__dir__``) for the package named ``package``: each public name of ``homes`` ({name: the
    module that defines it, relative to the package, e.g. ``"analysis.run"``}) is imported from its module when it
    is first asked for; any other name is an AttributeError."""

    def __getattr__(name: str) -> object:
        if name in homes:
            return getattr(importlib.import_module("." + homes[name], package), name)
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__() -> List[str]:
        return sorted(set(vars(importlib.import_module(package))) | set(homes))

    return __getattr__, __dir__
