"""A mesh as the texture painter takes it: triangles with UV coordinates and positions (ALGORITHM §10).

Blender hands the painter its loop triangles' arrays directly. On the command
line a mesh comes as a Wavefront OBJ file, the plain text every 3-D program
writes: its ``v`` positions (in metres, as Blender writes them at scale 1),
its ``vt`` texture coordinates and its ``f`` faces, each polygon cut into
triangles that stay inside it (``polygons``: a fan where it is convex).
"""

from __future__ import annotations

from pathlib import Path
from typing import List, NamedTuple, Optional

import numpy as np

from ..errors import InputError, reading_error
from .polygons import triangles as polygon_triangles


class SurfaceMesh(NamedTuple):
    """T triangles of a mesh's surface."""

    uv: np.ndarray              # (T, 3, 2) float64, the corners' UV coordinates (u right, v up)
    position: np.ndarray        # (T, 3, 3) float64 m, the corners' positions
    source: Optional[np.ndarray] = None     # (T,) int64 >= 0: the source image each is painted from; None: all 0


def check_mesh(mesh: SurfaceMesh, name: str) -> SurfaceMesh:
    """``mesh`` as float64 arrays; InputError (one sentence naming ``name``) when its arrays do not fit together,
    hold no triangle or a value that is not finite, or its sources are not whole numbers from 0, one a triangle."""
    uv, position = np.asarray(mesh.uv, np.float64), np.asarray(mesh.position, np.float64)
    if uv.ndim != 3 or uv.shape[1:] != (3, 2) or position.shape != uv.shape[:1] + (3, 3):
        raise InputError(f"The mesh {name} must give three UV points and three positions for each triangle, "
                         f"got arrays of shapes {uv.shape} and {position.shape}.")
    if len(uv) == 0:
        raise InputError(f"The mesh {name} has no faces to paint.")
    if not (np.isfinite(uv).all() and np.isfinite(position).all()):
        raise InputError(f"The mesh {name} holds a UV coordinate or a position that is not a finite number.")
    source = None
    if mesh.source is not None:
        given = np.asarray(mesh.source)
        if (given.shape != uv.shape[:1] or not (np.issubdtype(given.dtype, np.integer) or given.dtype == bool)
                or (given < 0).any()):
            raise InputError(f"The mesh {name} must give each of its {len(uv)} triangles a source image as a whole "
                             f"number from 0, got an array of shape {given.shape} and type {given.dtype}.")
        source = given.astype(np.int64)
    return SurfaceMesh(uv, position, source)


def read_obj(path) -> SurfaceMesh:
    """The triangles of the Wavefront OBJ file ``path`` (module docstring); InputError (one sentence naming the
    file and, where it is one, the line) when it cannot be read, a line is not understood, an index points
    nowhere, or a face has no texture coordinates. Each triangle's source is its face's material: the k-th
    material named by ``usemtl`` (in the order first named) is source k, a face before any ``usemtl`` source 0."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise reading_error(f"The mesh {path}", exc, "an OBJ file") from None
    positions: List[List[float]] = []
    coordinates: List[List[float]] = []
    faces: List[List[tuple]] = []
    materials: dict = {}
    material: List[int] = []
    current = 0
    for number, line in enumerate(text.splitlines(), 1):
        words = line.split("#", 1)[0].split()
        if not words:
            continue
        try:
            if words[0] == "v":
                positions.append(numbers(words[1:4], 3, "a position needs three numbers"))
            elif words[0] == "vt":
                coordinates.append(numbers(words[1:3], 2, "a UV needs two numbers"))
            elif words[0] == "f":
                faces.append([corner(word, len(positions), len(coordinates)) for word in words[1:]])
                if len(faces[-1]) < 3:
                    raise ValueError("a face needs three corners")
                material.append(current)
            elif words[0] == "usemtl":
                current = materials.setdefault(" ".join(words[1:]), len(materials))
        except ValueError as exc:
            raise InputError(f"The mesh {path} cannot be read at line {number}: {exc}.") from None
    if not faces:
        raise InputError(f"The mesh {path} has no faces to paint.")
    if any(uv < 0 for face in faces for _, uv in face):
        raise InputError(f"The mesh {path} has faces without texture coordinates: unwrap it (a UV map) first.")
    points, uvs = np.array(positions, np.float64), np.array(coordinates, np.float64)
    cut = [polygon_triangles(points[[p for p, _ in face]]) for face in faces]
    triangles = np.array([(face[a], face[b], face[c]) for face, parts in zip(faces, cut, strict=True)
                          for a, b, c in parts])
    source = np.repeat(np.array(material, np.int64), [len(parts) for parts in cut])
    return check_mesh(SurfaceMesh(uvs[triangles[..., 1]], points[triangles[..., 0]],
                                  source if materials else None), str(path))


def numbers(words: List[str], count: int, need: str) -> List[float]:
    """``count`` numbers of ``words``; ValueError ``need`` when there are fewer or one is not a finite number."""
    try:
        values = [float(word) for word in words]
    except ValueError:
        raise ValueError(need) from None
    if len(values) != count or not np.isfinite(values).all():
        raise ValueError(need)
    return values


def corner(word: str, positions: int, coordinates: int) -> tuple:
    """(position index, UV index or -1) of an OBJ face corner ``v``, ``v/vt``, ``v//vn`` or ``v/vt/vn``, 1-based
    or negative (counted back from the last read); ValueError naming an index that points nowhere."""
    parts = word.split("/")
    position = resolved(parts[0], positions, "position")
    uv = resolved(parts[1], coordinates, "UV") if len(parts) > 1 and parts[1] else -1
    return position, uv


def resolved(text: str, count: int, what: str) -> int:
    """The 0-based index of an OBJ index ``text`` among ``count`` items read so far; ValueError when it points
    nowhere."""
    index = int(text)
    found = index - 1 if index > 0 else count + index
    if index == 0 or not 0 <= found < count:
        raise ValueError(f"the face's {what} index {index} points to none of the {count} read so far")
    return found
