"""A job of ``paint_objects``: ``core.paint_object``'s arguments for one object, checked, and handed to another
process as files.

A job is a dict of ``paint_object``'s keyword arguments (``ARGUMENTS``;
``REQUIRED`` must be there). It is written into a folder as ``<k>.json``
(paths as strings, the parameters as ``Params.to_dict`` gives them, the
other arguments as they are) and, for a ``SurfaceMesh``, ``<k>.npz`` holding
its arrays unchanged (dtype and values), so the process reading it back
calls ``paint_object`` with the same values, and paints the same bytes.
"""

from __future__ import annotations

import dataclasses
import json
import os
from pathlib import Path

import numpy as np

from ..errors import ParameterError
from ..params import Params
from ..surface.mesh import SurfaceMesh

ARGUMENTS = ("texture_path", "mesh", "output_dir", "params", "texture_size", "stroke_mm", "normal_map",
             "keep_source", "across_seams", "extensions", "max_memory")
"""The keyword arguments of ``core.paint_object`` a job may give (its progress and cancel are the batch's)."""

REQUIRED = ("texture_path", "mesh", "output_dir", "params")
"""The arguments every job gives."""


def checked_job(job, number: int) -> dict:
    """A copy of ``job`` when it is a dict of ``ARGUMENTS`` giving every one of ``REQUIRED`` with ``params`` a
    ``Params`` and ``mesh`` a ``SurfaceMesh`` or a path; else ParameterError in one sentence naming object
    ``number`` (counted from 1). The values themselves are ``paint_object``'s to check."""
    if not isinstance(job, dict):
        raise ParameterError(f"Object {number}'s job is not a dict of paint_object's arguments.")
    unknown = sorted(str(name) for name in set(job) - set(ARGUMENTS))
    if unknown:
        raise ParameterError(f"Object {number}'s job names {', '.join(unknown)}, which paint_objects does not take "
                             f"(it takes {', '.join(ARGUMENTS)}).")
    missing = [name for name in REQUIRED if job.get(name) is None]
    if missing:
        raise ParameterError(f"Object {number}'s job gives no {' and no '.join(missing)}.")
    if not isinstance(job["params"], Params):
        raise ParameterError(f"Object {number}'s params are not a core.Params.")
    if not isinstance(job["mesh"], (SurfaceMesh, str, os.PathLike)):
        raise ParameterError(f"Object {number}'s mesh is neither a core.SurfaceMesh nor the path of an OBJ file.")
    return dict(job)


def _plain(value):
    """A NumPy scalar as the Python number it holds (for JSON); TypeError for anything else JSON cannot hold."""
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"a value of type {type(value).__name__}")


def write_job(folder: Path, index: int, job: dict) -> None:
    """Write the checked ``job`` into ``folder`` as ``<index>.json`` (and ``<index>.npz`` for a ``SurfaceMesh``);
    ParameterError in one sentence naming object ``index + 1`` when a value cannot be handed over (an array of
    Python objects, a value JSON cannot hold)."""
    number = index + 1
    document = {name: value for name, value in job.items() if name not in ("texture_path", "mesh", "output_dir",
                                                                              "params")}
    texture = job["texture_path"]
    listed = isinstance(texture, (list, tuple))
    document["texture_path"] = [os.fspath(p) for p in texture] if listed else os.fspath(texture)
    document["output_dir"] = os.fspath(job["output_dir"])
    document["params"] = job["params"].to_dict()
    mesh = job["mesh"]
    if isinstance(mesh, SurfaceMesh):
        arrays = {name: np.asarray(getattr(mesh, name)) for name in SurfaceMesh._fields
                  if getattr(mesh, name) is not None}
        if any(array.dtype.hasobject for array in arrays.values()):
            raise ParameterError(f"Object {number}'s mesh holds arrays of Python objects, not of numbers.")
        np.savez(Path(folder) / f"{index}.npz", **arrays)
        document["mesh"] = {"arrays": f"{index}.npz"}
    else:
        document["mesh"] = {"obj": os.fspath(mesh)}
    if isinstance(document.get("stroke_mm"), (tuple, np.ndarray)):
        document["stroke_mm"] = list(document["stroke_mm"])
    try:
        text = json.dumps(document, default=_plain)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"Object {number}'s job holds {exc}, which cannot be handed to another "
                             f"process.") from None
    (Path(folder) / f"{index}.json").write_text(text, encoding="utf-8")


def read_job(folder: Path, index: int) -> dict:
    """The keyword arguments of ``core.paint_object`` that ``write_job`` wrote into ``folder`` for ``index``."""
    document = json.loads((Path(folder) / f"{index}.json").read_text(encoding="utf-8"))
    fields = {f.name for f in dataclasses.fields(Params)}
    document["params"] = Params(**{k: tuple(v) if isinstance(v, list) else v
                                   for k, v in document["params"].items() if k in fields})
    mesh = document["mesh"]
    if "arrays" in mesh:
        with np.load(Path(folder) / mesh["arrays"], allow_pickle=False) as arrays:
            document["mesh"] = SurfaceMesh(*(arrays[name] if name in arrays else None
                                             for name in SurfaceMesh._fields))
    else:
        document["mesh"] = mesh["obj"]
    return document
