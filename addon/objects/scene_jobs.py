# SPDX-License-Identifier: GPL-3.0-or-later
"""Paint Scene's paintings: the objects whose texture sets are the same pictures painted as one texture, each
painting with a folder of its own.

Objects whose sources are the same pictures (the same bytes, by SHA-256,
read with the same extension rules), such as a floor and a wall that wear
one image, are painted together: their triangles, each in its own UVs and
world positions, make one mesh, painted once, and every one of them wears
that painting. A baked source is its object's own, so an object with a bake
is painted alone. Each painting's folder is named after its first object.
"""

import hashlib
import os
from typing import List, NamedTuple

import numpy as np


class Gathered(NamedTuple):
    """What Paint Scene gathered of one object: its name, its ``sources.SourceSet`` and its
    ``core.SurfaceMesh``."""

    name: str
    source_set: object
    mesh: object


class ScenePainting(NamedTuple):
    """One texture Paint Scene paints: the objects that wear it (names, in name order), its folder name, its
    sources (paths) with their extension rules, and the mesh of all its objects' triangles."""

    names: List[str]
    folder: str
    paths: List[str]
    extensions: List[str]
    mesh: object


def file_digest(path):
    """The SHA-256 (hex) of the file at ``path``'s bytes."""
    digest = hashlib.sha256()
    with open(path, "rb") as file:
        for block in iter(lambda: file.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def folder_name(name, taken):
    """A folder name for ``name``: any character a file system might refuse as "_", made unique (ignoring case)
    against ``taken``, a set it is added to."""
    safe = "".join(c if c.isalnum() or c in "-_. " else "_" for c in name).strip(" .") or "object"
    unique, k = safe, 2
    while unique.lower() in taken:
        unique, k = "{}_{}".format(safe, k), k + 1
    taken.add(unique.lower())
    return unique


def _key(gathered, digests):
    """What makes two objects' texture sets one: their sources' digests and extension rules; None (painted alone)
    when a source is a bake."""
    source_set = gathered.source_set
    if any(kind == "bake" for kind in source_set.kinds):
        return None
    return tuple((digests[path], rule) for path, rule in zip(source_set.paths, source_set.extensions, strict=True))


def scene_paintings(gathered, mesh_type):
    """The ``ScenePainting``s of ``gathered`` (a list of ``Gathered`` in name order), in the order of their first
    objects. ``mesh_type`` makes a mesh from (uv, position, source) arrays (``core.SurfaceMesh``)."""
    digests = {path: file_digest(path) for item in gathered for path in item.source_set.paths}
    groups, keys = [], {}
    for item in gathered:
        key = _key(item, digests)
        if key is not None and key in keys:
            groups[keys[key]].append(item)
            continue
        if key is not None:
            keys[key] = len(groups)
        groups.append([item])
    taken, paintings = set(), []
    for items in groups:
        first = items[0]
        meshes = [item.mesh for item in items]
        mesh = first.mesh if len(items) == 1 else mesh_type(
            np.concatenate([m.uv for m in meshes]), np.concatenate([m.position for m in meshes]),
            np.concatenate([np.zeros(len(m.uv), np.int64) if m.source is None else m.source for m in meshes]))
        paintings.append(ScenePainting([item.name for item in items], folder_name(first.name, taken),
                                       list(first.source_set.paths), list(first.source_set.extensions), mesh))
    return paintings


def keeps_source(paths, scratch):
    """Whether some of ``paths`` lives in the temporary folder ``scratch`` (so the painting keeps a copy)."""
    root = os.path.normpath(scratch)
    return any(os.path.normpath(path).startswith(root + os.sep) for path in paths)
