"""How much a texture steps across its mesh's UV seams, against the step across edges inside its islands
(ALGORITHM §10, seams).

Where two triangles meet in 3-D along an edge, a point on either side of it,
``offset`` metres into each triangle, lies on the surface as close to the
other as the offset allows; read in the texture, the two colours differ by
what the texture steps there. Across an edge inside an island both points
read one stretch of the texture; across a UV seam they read two islands that
were filled apart, so a seam shows in a render exactly as far as this step
is larger than the inner edges'. It is measured on the surface, independent
of a camera, a light or the mesh's creases.
"""

from __future__ import annotations

from typing import NamedTuple, Optional

import numpy as np

OFFSET_TEXELS = 2.0
"""How far from an edge its two sides are read: texels of the island whose texels are largest."""


class EdgeSamples(NamedTuple):
    """Pairs of texture points facing each other across the mesh's edges."""

    sides: np.ndarray           # (S, 2, 2) float64: the UV of each sample's point in either triangle
    seam: np.ndarray            # (S,) bool: the sample's edge is a UV seam (its ends' UVs differ between the two)
    edges: np.ndarray           # (2,) int: the seam edges and the inner edges sampled
    offset_m: float             # metres: the distance of either point from the edge


def shared_edges(position: np.ndarray) -> tuple:
    """(triangles, first, second), each (E, 2) int: the E edges that exactly two of the triangles ``position``
    (T, 3, 3) share in 3-D (both ends the same points), as the two triangles and, in each, the corner of the
    edge's first end and of its second. An edge of one triangle (a border) or of more than two is left out."""
    count = len(position)
    _, vertex = np.unique(position.reshape(-1, 3), axis=0, return_inverse=True)
    vertex = vertex.reshape(count, 3).astype(np.int64)
    triangle = np.tile(np.arange(count), 3)
    start = np.repeat(np.arange(3), count)
    end = (start + 1) % 3
    a, b = vertex[triangle, start], vertex[triangle, end]
    first, second = np.where(a < b, start, end), np.where(a < b, end, start)
    key = np.minimum(a, b) * (int(vertex.max(initial=0)) + 1) + np.maximum(a, b)
    _, group, counts = np.unique(key, return_inverse=True, return_counts=True)
    order = np.argsort(group.reshape(-1), kind="stable")
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])[counts == 2]
    pairs = order[np.stack([starts, starts + 1], axis=1)]
    return triangle[pairs], first[pairs], second[pairs]


def edge_samples(uv: np.ndarray, position: np.ndarray, offset_m: float,
                 islands: Optional[np.ndarray] = None) -> EdgeSamples:
    """The sample pairs across the shared edges (``shared_edges``) of the triangles ``uv`` (T, 3, 2) and
    ``position`` (T, 3, 3) m: one every ``offset_m`` along the stretch of an edge where both points stay inside
    their triangles (at least one, centred), each point ``offset_m`` from the edge, straight across it in its
    triangle's plane, so the two face each other. An edge is a seam where its ends' UVs differ in the two
    triangles or, given their ``islands`` (T,), where the two lie in two islands (as across atlas cells). An edge with no such stretch, or of a triangle of no UV area,
    is left out."""
    triangles, first, second = shared_edges(position)
    opposite = 3 - first - second
    start, end = position[triangles[:, 0], first[:, 0]], position[triangles[:, 0], second[:, 0]]
    edge = end - start
    length2 = np.einsum("ij,ij->i", edge, edge)
    apex = position[triangles, opposite] - start[:, None]                         # (E, 2, 3)
    with np.errstate(divide="ignore", invalid="ignore"):
        foot = np.einsum("ikj,ij->ik", apex, edge) / length2[:, None]             # (E, 2): the apex's foot, along
        height = np.linalg.norm(apex - foot[..., None] * edge[:, None], axis=2)
        reach = offset_m / height                                                  # (E, 2): of the apex's height
    low = np.max(reach * foot, axis=1)                                             # both points inside: s in [low,
    high = np.min(1.0 - reach * (1.0 - foot), axis=1)                              # high] along the edge
    uv_start, uv_end, uv_apex = uv[triangles, first], uv[triangles, second], uv[triangles, opposite]
    along, across = uv_end - uv_start, uv_apex - uv_start
    uv_area = np.abs(along[..., 0] * across[..., 1] - along[..., 1] * across[..., 0])
    kept = (length2 > 0) & (high > low) & np.all((height > 0) & (uv_area > 0), axis=1)
    seam = np.any(uv_start[:, 0] != uv_start[:, 1], axis=1) | np.any(uv_end[:, 0] != uv_end[:, 1], axis=1)
    if islands is not None:
        seam |= islands[triangles[:, 0]] != islands[triangles[:, 1]]
    edge_index = np.flatnonzero(kept)
    stretch = high[edge_index] - low[edge_index]
    per_edge = np.maximum(1, np.rint(stretch * np.sqrt(length2[edge_index]) / offset_m).astype(np.int64))
    sample_edge = np.repeat(edge_index, per_edge)
    index = np.arange(len(sample_edge)) - np.repeat(np.cumsum(per_edge) - per_edge, per_edge)
    fraction = low[sample_edge] + (index + 0.5) / np.repeat(per_edge, per_edge) * np.repeat(stretch, per_edge)
    on_edge = uv_start[sample_edge] + fraction[:, None, None] * along[sample_edge]
    feet = uv_start[sample_edge] + foot[sample_edge][..., None] * along[sample_edge]
    sides = on_edge + reach[sample_edge][..., None] * (uv_apex[sample_edge] - feet)
    counts = np.array([np.sum(seam[edge_index]), np.sum(~seam[edge_index])])
    return EdgeSamples(sides, seam[sample_edge], counts, float(offset_m))


def bilinear(texture: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """(S, C): ``texture`` (N, N, C) read bilinearly at ``uv`` (S, 2), texel centres at ((c + 0.5) / N, 1 - (r +
    0.5) / N), clamped at the borders."""
    size = texture.shape[0]
    x = np.clip(uv[:, 0] * size - 0.5, 0, size - 1)
    y = np.clip((1.0 - uv[:, 1]) * size - 0.5, 0, size - 1)
    x0, y0 = np.minimum(x.astype(np.int64), size - 2), np.minimum(y.astype(np.int64), size - 2)
    fx, fy = (x - x0)[:, None], (y - y0)[:, None]
    top = texture[y0, x0] * (1 - fx) + texture[y0, x0 + 1] * fx
    bottom = texture[y0 + 1, x0] * (1 - fx) + texture[y0 + 1, x0 + 1] * fx
    return top * (1 - fy) + bottom * fy


def texture_steps(texture: np.ndarray, samples: EdgeSamples) -> dict:
    """{"seam": step, "inner": step}: the mean absolute difference, over the samples and the channels, between
    ``texture`` (N, N, C) read on either side of the seams' samples and the inner edges' (None without any)."""
    sides = samples.sides
    step = np.abs(bilinear(texture, sides[:, 0]) - bilinear(texture, sides[:, 1])).mean(axis=1)

    def mean(values: np.ndarray) -> Optional[float]:
        return round(float(values.mean()), 5) if len(values) else None

    return {"seam": mean(step[samples.seam]), "inner": mean(step[~samples.seam])}


def seam_figures(samples: EdgeSamples, source: np.ndarray, painted: np.ndarray) -> dict:
    """The report's "seam_steps": the offset (mm), the seam and inner edges sampled, and the steps
    (``texture_steps``) of the texture's ``source`` and of the ``painted`` texture, both (N, N, 3) sRGB."""
    return {"offset_mm": round(samples.offset_m * 1000.0, 3),
            "edges": {"seam": int(samples.edges[0]), "inner": int(samples.edges[1])},
            "samples": {"seam": int(samples.seam.sum()), "inner": int((~samples.seam).sum())},
            "source": texture_steps(source, samples), "painted": texture_steps(painted, samples)}
