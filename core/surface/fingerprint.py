"""What an object's painting was painted from, as one SHA-256: how a folder is known to hold a job's painting.

``core.paint_object`` records it in report.json ("inputs_sha256"); painting
several objects (``core.objects``) computes it for each job before any work
and keeps a folder whose report records the same digest, the same parameters
and every file whole, instead of painting it again. It covers the bytes of
every source file the painting reads (each UDIM tile the mesh uses), the
mesh's arrays (UVs, positions, sources), the texture size and stroke widths
as given, the extension rules, the normal map, the kept source, painting
across the seams and the painter's version. The parameters are compared on
their own (report.json records them).
"""

from __future__ import annotations

import hashlib
import json
from typing import Optional, Sequence

import numpy as np

from ..files.export import input_sha256
from ..version import __version__
from .mesh import SurfaceMesh

FORMAT = "paint-relief object inputs 1"
"""The first line of what is digested; another when what the digest covers changes."""


def inputs_sha256(files: Sequence[str], surface: SurfaceMesh, listed: bool, texture_size: Optional[int],
                  stroke_mm, rules: Sequence[str], normal_map: bool, keep_source: bool, across_seams: bool) -> str:
    """The hex SHA-256 of an object painting's inputs (module docstring).

    files: the source files read, one per atlas cell in the atlas's order; surface: the checked mesh (float64
    (T, 3, 2) UVs, (T, 3, 3) positions in m, (T,) int64 sources or None); listed: whether the texture was given as
    a list; texture_size: texels as given (None: the default); stroke_mm: mm as given (None: the default);
    rules: each source's extension rule, checked. InputError naming a source that cannot be read."""
    digest = hashlib.sha256()
    settings = {"format": FORMAT, "version": __version__, "files": [input_sha256(f) for f in files],
                "listed": bool(listed), "texture_size": texture_size,
                "stroke_mm": None if stroke_mm is None else [float(w) for w in stroke_mm],
                "extensions": list(rules), "normal_map": bool(normal_map), "keep_source": bool(keep_source),
                "across_seams": bool(across_seams), "triangles": int(len(surface.uv)),
                "sources": surface.source is not None}
    digest.update(json.dumps(settings, sort_keys=True).encode())
    for array, kind in ((surface.uv, np.float64), (surface.position, np.float64), (surface.source, np.int64)):
        if array is not None:
            digest.update(np.ascontiguousarray(array, kind).tobytes())
    return digest.hexdigest()


def job_inputs_sha256(texture_path, mesh, texture_size: Optional[int] = None, stroke_mm=None,
                      normal_map: bool = False, keep_source: bool = False, across_seams: bool = True,
                      extensions=None) -> str:
    """``inputs_sha256`` of the painting ``core.paint_object`` would make of these arguments (its own), read and
    checked as it reads them; a PaintReliefError in one sentence for what it would refuse on the way."""
    from ..errors import ParameterError
    from .atlas import build_atlas, checked_extensions, is_tiled, tile_path
    from .mesh import check_mesh, read_obj

    listed = isinstance(texture_path, (list, tuple))
    paths = list(texture_path) if listed else [texture_path]
    if not paths:
        raise ParameterError("No texture was given to paint the mesh from.")
    rules = checked_extensions(extensions, len(paths))
    surface = check_mesh(mesh, "given") if isinstance(mesh, SurfaceMesh) else read_obj(mesh)
    if surface.source is not None and int(surface.source.max()) >= len(paths):
        raise ParameterError("A face of the mesh is painted from a source that was not given.")
    atlas = build_atlas(surface.uv, surface.source, [is_tiled(path) for path in paths], rules)
    files = [tile_path(paths[cell.source], cell.tile) for cell in atlas.cells]
    return inputs_sha256(files, surface, listed, texture_size, stroke_mm, rules, normal_map, keep_source,
                         across_seams)
