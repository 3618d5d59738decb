"""Strokes across UV seams: each island's apron, the surface beyond its seams unfolded into its texture frame
(ALGORITHM §10, strokes across seams).

Where two triangles meet in 3-D along an edge whose ends have other UVs in
the two (a seam), the neighbour triangle is unfolded rigidly across the edge
into the island's UV frame: its edge's ends laid on the island's, its apex on
the far side, as far from the edge and as far along it as on the surface, at
the island's own scale (metres per UV unit of the island's triangle along
the edge). That places the neighbour's triangle by an affine map of texture
coordinates, neighbour frame -> island frame, the seam's chart map. The
island's apron is the texels of its box beyond its seams: each takes the
seam nearest to it among the island's border edges, and reads the surface
through that seam's chart map in the neighbour island's own texels. A texel
whose nearest border edge is no seam (a border of the surface), or which the
map sends outside the neighbour island, is no apron texel. The chart map of
the one triangle along the seam goes on beyond it in the apron, which is
exact on a developable strip and near it elsewhere.

Of a seam's two sides one leads (``seam_charts``): the leading island's
strokes are anchored in the inner part of its apron too, and the paint laid
in its apron is carried back (``carried``) to the neighbour's own texels
through the same chart map, feathered over the apron's outer part, so both
sides of the seam show the same strokes.

Texel coordinates throughout: texel (r, c) of an N x N texture has its
centre at x = c, y = r (u = (x + 0.5) / N, v = 1 - (y + 0.5) / N).
"""

from __future__ import annotations

from typing import NamedTuple, Tuple

import numpy as np
from scipy import ndimage

from .islands import NO_ISLAND, box_texels
from .seams import shared_edges

FEATHER_START = 0.75
"""Paint carried back from an apron keeps full weight up to this fraction of the apron's width from the seam,
then fades linearly to none at its far side, so where the apron ends no line shows."""

MAX_STRETCH = 2.0
"""An apron reaches past a seam as many of the neighbour's texels as of the island's: wider, up to this many times,
where the neighbour's texels are coarser (``stretch``), so that what is carried covers as many of its texels."""

CARRY_REACH = 4.0
"""The neighbours' texels looked at for paint carried back lie within this many apron widths of the seam (a bound
for charts that shrink the neighbour's texels a lot, as at a sphere's poles)."""

APRON_AREA = 1.2
"""An island's canvas across its seams, its box widened to hold its apron, spans at most this many times the
texels of its box painted apart (``apron_reach``): an island whose strokes are wide against it gets a shorter
apron rather than a canvas up to twice as wide again."""

REACH_STEPS = 24
"""Halvings of the interval the apron's reach is searched in (``apron_reach``): to about 1e-7 of the margin."""

BAND_CHUNK = 1 << 22
"""(texel, edge) pairs measured at once while the texels near edges are found: bounds the memory."""


class SeamCharts(NamedTuple):
    """A mesh's UV border edges and, for those that are seams, the chart maps across them (texel coordinates)."""

    ends: np.ndarray            # (B, 2, 2) float64: each border edge's two ends (x, y) in its island's frame
    island: np.ndarray          # (B,) int32: the island 1 .. K of each border edge's triangle
    neighbour: np.ndarray       # (B,) int32: the island across a seam, NO_ISLAND across a border of the surface
    partner: np.ndarray         # (B,) int64: the same 3-D edge's border edge in the neighbour's frame, -1 if none
    chart: np.ndarray           # (B, 2, 3) float64: neighbour frame -> island frame, (x, y, 1) -> (x, y)
    leads: np.ndarray           # (B,) bool: paint laid beyond this edge is carried to the neighbour (module doc)


def texel_xy(uv: np.ndarray, size: int) -> np.ndarray:
    """(..., 2) texel coordinates (x, y) of UV points ``uv`` (..., 2) in a ``size`` x ``size`` texture."""
    return np.stack([uv[..., 0] * size - 0.5, (1.0 - uv[..., 1]) * size - 0.5], axis=-1)


def affine(source: np.ndarray, target: np.ndarray) -> np.ndarray:
    """(M, 2, 3): the affine maps taking the triangles ``source`` (M, 3, 2) onto ``target`` (M, 3, 2), corner by
    corner; a source triangle of no area gives NaN."""
    lifted = np.concatenate([source, np.ones(source.shape[:2] + (1,))], axis=2)          # (M, 3, 3)
    with np.errstate(divide="ignore", invalid="ignore"):
        solved = np.full(lifted.shape[:1] + (3, 2), np.nan)
        fine = np.abs(np.linalg.det(lifted)) > 1e-12
        solved[fine] = np.linalg.solve(lifted[fine], target[fine])
    return np.swapaxes(solved, 1, 2)


def apply(chart: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(M, 2): the affine maps ``chart`` (M, 2, 3) applied to ``points`` (M, 2)."""
    return np.einsum("mij,mj->mi", chart[:, :, :2], points) + chart[:, :, 2]


def inverted(chart: np.ndarray) -> np.ndarray:
    """(M, 2, 3): the inverse maps of the affine maps ``chart`` (M, 2, 3)."""
    linear = np.linalg.inv(chart[:, :, :2])
    return np.concatenate([linear, -np.einsum("mij,mj->mi", linear, chart[:, :, 2])[..., None]], axis=2)


def unfolded_apex(edge_xy: np.ndarray, apex_side_xy: np.ndarray, edge_3d: np.ndarray,
                  apex_3d: np.ndarray) -> np.ndarray:
    """(M, 2): where a neighbour triangle's apex ``apex_3d`` (M, 3) m, across the 3-D edge ``edge_3d`` (M, 2, 3),
    lands unfolded into a frame where that edge lies at ``edge_xy`` (M, 2, 2): as far along the edge and from it
    as on the surface, in the frame's scale along the edge, on the side away from ``apex_side_xy`` (M, 2), the
    apex of the frame's own triangle."""
    edge = edge_3d[:, 1] - edge_3d[:, 0]
    length2 = np.einsum("ij,ij->i", edge, edge)
    relative = apex_3d - edge_3d[:, 0]
    along = np.einsum("ij,ij->i", relative, edge) / length2
    away = np.linalg.norm(relative - along[:, None] * edge, axis=1) / np.sqrt(length2)
    flat = edge_xy[:, 1] - edge_xy[:, 0]
    normal = np.stack([-flat[:, 1], flat[:, 0]], axis=1)
    own = np.einsum("ij,ij->i", apex_side_xy - edge_xy[:, 0], normal)
    normal *= np.where(own > 0, -1.0, 1.0)[:, None]
    return edge_xy[:, 0] + along[:, None] * flat + away[:, None] * normal


def seam_charts(uv: np.ndarray, position: np.ndarray, islands: np.ndarray, size: int) -> SeamCharts:
    """The border edges of the islands ``islands`` (T,) of the triangles ``uv`` (T, 3, 2) and ``position`` (T, 3, 3)
    m in a ``size``-texel texture, and the chart map across each seam (module docstring). A border edge is a UV
    edge of one triangle of its island alone (an edge two islands share in UV, as at the border of two atlas
    cells, is a border of both); it is a seam when another triangle shares its ends in 3-D. Of a seam's two sides,
    one leads: its island's strokes are anchored beyond it and carried over the other side. Islands are painted
    in their order, so between two islands the later leads and lays its strokes over the earlier's paint; within
    one island (both sides painted at once) the side whose triangle comes first leads."""
    count = len(uv)
    _, point = np.unique(uv.reshape(-1, 2), axis=0, return_inverse=True)
    point = point.reshape(count, 3)
    triangle, start = np.repeat(np.arange(count), 3), np.tile(np.arange(3), count)
    end = (start + 1) % 3
    pair = np.sort(np.stack([point[triangle, start], point[triangle, end]], axis=1), axis=1)
    pair = np.concatenate([pair, islands[triangle][:, None].astype(pair.dtype)], axis=1)    # none across islands
    _, group, uses = np.unique(pair, axis=0, return_inverse=True, return_counts=True)
    border = np.flatnonzero(uses[group.reshape(-1)] == 1)
    slot = np.full(3 * count, -1, np.int64)                             # border edge of (triangle, corner) 3 t + c
    slot[3 * triangle[border] + start[border]] = np.arange(len(border))
    xy = texel_xy(uv, size)
    ends = np.stack([xy[triangle[border], start[border]], xy[triangle[border], end[border]]], axis=1)
    neighbour = np.full(len(border), NO_ISLAND, np.int32)
    partner = np.full(len(border), -1, np.int64)
    chart = np.full((len(border), 2, 3), np.nan)
    leads = np.zeros(len(border), bool)
    shared, first, second = shared_edges(position)
    for side in (0, 1):
        here, there = shared[:, side], shared[:, 1 - side]
        lower = np.minimum(first[:, side], second[:, side])
        upper = np.maximum(first[:, side], second[:, side])
        corner = np.where((lower == 0) & (upper == 2), 2, lower)       # the edge's corner: start of edge c -> c + 1
        mine = slot[3 * here + corner]
        lower_t = np.minimum(first[:, 1 - side], second[:, 1 - side])
        upper_t = np.maximum(first[:, 1 - side], second[:, 1 - side])
        yours = slot[3 * there + np.where((lower_t == 0) & (upper_t == 2), 2, lower_t)]
        kept = (mine >= 0) & (yours >= 0)
        mine, yours, here, there = mine[kept], yours[kept], here[kept], there[kept]
        f_here, s_here = first[kept, side], second[kept, side]
        f_there, s_there = first[kept, 1 - side], second[kept, 1 - side]
        apex_there = 3 - f_there - s_there
        edge_xy = np.stack([xy[here, f_here], xy[here, s_here]], axis=1)
        apex = unfolded_apex(edge_xy, xy[here, 3 - f_here - s_here],
                             np.stack([position[here, f_here], position[here, s_here]], axis=1),
                             position[there, apex_there])
        source = np.stack([xy[there, f_there], xy[there, s_there], xy[there, apex_there]], axis=1)
        target = np.stack([edge_xy[:, 0], edge_xy[:, 1], apex], axis=1)
        neighbour[mine] = islands[there]
        partner[mine] = yours
        chart[mine] = affine(source, target)
        leads[mine] = (islands[here] > islands[there]) | ((islands[here] == islands[there]) & (here < there))
    fine = np.isfinite(chart).all(axis=(1, 2))
    neighbour[~fine], partner[~fine], leads[~fine] = NO_ISLAND, -1, False
    return SeamCharts(ends, islands[triangle[border]].astype(np.int32), neighbour, partner, chart, leads)


def near_edges(ends: np.ndarray, reach: np.ndarray, shape: Tuple[int, int]) -> tuple:
    """The texels of an (H, W) grid within ``reach`` (S,) texels of the segments ``ends`` (S, 2, 2) (x, y), each with
    the segment nearest it: (rows (M,), cols (M,), segment (M,) int64, distance (M,) texels), in row-major order;
    ties go to the segment listed first."""
    h, w = shape
    low = np.clip(np.floor(ends.min(axis=1) - reach[:, None]), 0, [w - 1, h - 1]).astype(np.int64)
    high = np.clip(np.ceil(ends.max(axis=1) + reach[:, None]), 0, [w - 1, h - 1]).astype(np.int64)
    found = []
    for segment, x, y in box_texels(low, high, BAND_CHUNK):
        a, b = ends[segment, 0], ends[segment, 1]
        d = b - a
        length2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-24)
        px, py = x - a[:, 0], y - a[:, 1]
        t = np.clip((px * d[:, 0] + py * d[:, 1]) / length2, 0.0, 1.0)
        distance = np.hypot(px - t * d[:, 0], py - t * d[:, 1])
        close = distance <= reach[segment]
        found.append((y[close] * w + x[close], segment[close], distance[close]))
    flat, segment, distance = (np.concatenate(parts) for parts in zip(*found, strict=True))
    order = np.lexsort((segment, distance, flat))
    flat, segment, distance = flat[order], segment[order], distance[order]
    first = np.flatnonzero(np.concatenate([[True], flat[1:] != flat[:-1]]))
    return flat[first] // w, flat[first] % w, segment[first], distance[first]


def nearest_edge(ends: np.ndarray, shape: Tuple[int, int]) -> tuple:
    """((H, W) int64, (H, W) float64): for each texel of an (H, W) grid, the segment of ``ends`` (S, 2, 2) (x, y)
    nearest it and its distance in texels, to within half a texel: the segments are drawn as texels (points every
    half texel along each, later segments over earlier) and the exact Euclidean distance transform finds the nearest
    drawn texel. -1 and infinity where no segment is drawn inside the grid."""
    h, w = shape
    lengths = np.hypot(*(ends[:, 1] - ends[:, 0]).T)
    steps = np.maximum(1, np.ceil(2.0 * lengths).astype(np.int64)) + 1
    segment = np.repeat(np.arange(len(ends)), steps)
    t = (np.arange(steps.sum()) - np.repeat(np.cumsum(steps) - steps, steps)) / np.repeat(steps - 1, steps)
    points = ends[segment, 0] + t[:, None] * (ends[segment, 1] - ends[segment, 0])
    x, y = np.rint(points[:, 0]).astype(np.int64), np.rint(points[:, 1]).astype(np.int64)
    inside = (x >= 0) & (x < w) & (y >= 0) & (y < h)
    drawn = np.full(shape, -1, np.int64)
    drawn[y[inside], x[inside]] = segment[inside]
    if not inside.any():
        return drawn, np.full(shape, np.inf)
    distance, (rows, cols) = ndimage.distance_transform_edt(drawn < 0, return_indices=True)
    return drawn[rows, cols], distance


def island_bilinear(values: np.ndarray, islands: np.ndarray, island: np.ndarray, xy: np.ndarray) -> tuple:
    """((M, ...), (M,)): ``values`` (N, N, ...) read bilinearly at texel points ``xy`` (M, 2) from the texels of
    island ``island`` (M,) alone (``islands`` (N, N)), the weights renormalised, and the weight those texels had
    (0: none of the four is the island's, the value then 0)."""
    size_y, size_x = islands.shape
    x0, y0 = np.floor(xy[:, 0]).astype(np.int64), np.floor(xy[:, 1]).astype(np.int64)
    fx, fy = xy[:, 0] - x0, xy[:, 1] - y0
    total = np.zeros(len(xy))
    summed = np.zeros((len(xy),) + values.shape[2:], np.float64)
    for dy, dx, weight in ((0, 0, (1 - fx) * (1 - fy)), (0, 1, fx * (1 - fy)), (1, 0, (1 - fx) * fy),
                           (1, 1, fx * fy)):
        x, y = x0 + dx, y0 + dy
        inside = (x >= 0) & (x < size_x) & (y >= 0) & (y < size_y)
        xc, yc = np.clip(x, 0, size_x - 1), np.clip(y, 0, size_y - 1)
        weight = np.where(inside & (islands[yc, xc] == island), weight, 0.0)
        total += weight
        summed += weight.reshape((-1,) + (1,) * (values.ndim - 2)) * values[yc, xc]
    with np.errstate(divide="ignore", invalid="ignore"):
        read = np.where((total > 0).reshape((-1,) + (1,) * (values.ndim - 2)),
                        summed / total.reshape((-1,) + (1,) * (values.ndim - 2)), 0.0)
    return read, total


class Apron(NamedTuple):
    """The texels of an island's box beyond its seams, and where on the neighbours' texels each reads."""

    rows: np.ndarray            # (A,) int64: the apron texels' rows in the box
    cols: np.ndarray            # (A,) int64: their columns in the box
    edge: np.ndarray            # (A,) int64: the seam (border edge of ``SeamCharts``) each lies beyond
    neighbour: np.ndarray       # (A,) int32: the island it reads
    source: np.ndarray          # (A, 2) float64: the texel point (x, y) it reads in the neighbour's frame
    feather: np.ndarray         # (A,) float [0, 1]: the weight of paint carried back from it (``FEATHER_START``)


def island_apron(charts: SeamCharts, islands: np.ndarray, island: int, origin: Tuple[int, int],
                 box: np.ndarray, reach: float) -> Apron:
    """Island ``island``'s apron in its box, whose texel (0, 0) is the texture's texel (row, col) ``origin`` and
    ``box`` (h, w) its island map (NO_ISLAND beyond the texture), of the (N, N) ``islands`` map: the box's texels
    outside the island whose nearest border edge is a seam, within ``reach`` texels of it times the seam's
    ``stretch``, which the seam's chart map sends onto a texel of the neighbour island (module docstring)."""
    own = np.flatnonzero(charts.island == island)
    if reach <= 0 or not (charts.neighbour[own] != NO_ISLAND).any():     # no reach (apron_reach may give 0)
        return Apron(*(np.zeros(0, np.int64),) * 3, np.zeros(0, np.int32), np.zeros((0, 2)), np.zeros(0))
    shift = np.array([origin[1], origin[0]], float)
    nearest, distance = nearest_edge(charts.ends[own] - shift, box.shape)
    r, c = np.nonzero((distance <= reach * MAX_STRETCH) & (nearest >= 0))
    edge, distance = own[nearest[r, c]], distance[r, c]
    keep = (charts.neighbour[edge] != NO_ISLAND) & (box[r, c] != island)
    r, c, edge, distance = r[keep], c[keep], edge[keep], distance[keep]
    reach = reach * stretch(charts, edge)
    keep = distance <= reach
    r, c, edge, distance, reach = r[keep], c[keep], edge[keep], distance[keep], reach[keep]
    source = apply(inverted(charts.chart[edge]), np.stack([c, r], axis=1) + shift)
    _, weight = island_bilinear(np.zeros(islands.shape + (1,)), islands, charts.neighbour[edge], source)
    keep = weight > 0
    feather = np.clip((1.0 - distance / reach) / (1.0 - FEATHER_START), 0.0, 1.0)
    return Apron(r[keep], c[keep], edge[keep], charts.neighbour[edge][keep], source[keep], feather[keep])


def stretch(charts: SeamCharts, edge: np.ndarray) -> np.ndarray:
    """(M,) in [1, MAX_STRETCH]: how many of the island's texels a neighbour's texel spans across the seams ``edge``
    (M,) at most (the chart map's largest singular value), at least 1."""
    if not len(edge):
        return np.ones(0)
    return np.clip(np.linalg.svd(charts.chart[edge, :, :2], compute_uv=False)[:, 0], 1.0, MAX_STRETCH)


def widest_stretch(charts: SeamCharts, island: int) -> float:
    """The largest ``stretch`` of island ``island``'s seams (1 without any)."""
    seams = np.flatnonzero((charts.island == island) & (charts.neighbour != NO_ISLAND))
    return float(np.max(stretch(charts, seams), initial=1.0))


def apron_reach(charts: SeamCharts, island: int, bounds: np.ndarray, base: Tuple[slice, slice], margin: float,
                area: float = APRON_AREA) -> Tuple[float, slice, slice]:
    """(reach, rows, cols): how far island ``island``'s apron reaches past its seams, in its texels (times each
    seam's ``stretch`` past the seams it leads), and the box that holds every texel the apron may need, rows x cols
    of the texture's texels (reaching past the texture where the seams run on there). ``bounds`` (2, 2) int: the
    island's texels' first and last (row, col); ``base`` (rows, cols): its box painted apart (widened by
    ``margin`` texels, within the texture). The box holds the base box, the island's texels widened by the reach,
    and the texels within the reach (times the stretch) of the island's leading seams. The reach is ``margin`` when
    that box spans at most ``area`` times the base box's texels, else the largest reach in [0, margin] whose box
    does (found by halving, so the same inputs give the same reach): the apron's cost is bounded for islands whose
    strokes are wide against them."""
    rows, cols = base
    seams = np.flatnonzero((charts.island == island) & charts.leads)
    low, high = charts.ends[seams].min(axis=1), charts.ends[seams].max(axis=1)     # (S, 2) (x, y)
    grow = stretch(charts, seams)
    limit = area * (rows.stop - rows.start) * (cols.stop - cols.start)

    def box(reach: float) -> Tuple[slice, slice]:
        pad = reach * grow + 1.0
        top = min(rows.start, int(bounds[0, 0] - np.ceil(reach)), int(np.floor(np.min(low[:, 1] - pad))))
        bottom = max(rows.stop, int(bounds[1, 0] + np.ceil(reach)) + 1, int(np.ceil(np.max(high[:, 1] + pad))) + 1)
        left = min(cols.start, int(bounds[0, 1] - np.ceil(reach)), int(np.floor(np.min(low[:, 0] - pad))))
        right = max(cols.stop, int(bounds[1, 1] + np.ceil(reach)) + 1, int(np.ceil(np.max(high[:, 0] + pad))) + 1)
        return slice(top, bottom), slice(left, right)

    def fits(reach: float) -> bool:
        r, c = box(reach)
        return (r.stop - r.start) * (c.stop - c.start) <= limit

    if not len(seams) or fits(margin):
        return (float(margin), *box(margin)) if len(seams) else (float(margin), rows, cols)
    short, long = 0.0, float(margin)
    for _ in range(REACH_STEPS):
        middle = 0.5 * (short + long)
        short, long = (middle, long) if fits(middle) else (short, middle)
    return (short, *box(short))


def leads_any(charts: SeamCharts, island: int) -> bool:
    """Whether island ``island`` leads across any of its seams (``seam_charts``): only then has it an apron."""
    return bool(np.any((charts.island == island) & charts.leads))


class Carry(NamedTuple):
    """Texels of the neighbours that take the paint an island laid beyond its seams."""

    rows: np.ndarray            # (M,) int64: the texels' rows in the texture
    cols: np.ndarray            # (M,) int64: their columns
    values: np.ndarray          # (M, C) float64: what the island's canvas holds there on the surface
    weight: np.ndarray          # (M,) float [0, 1]: how much of it they take


def carried(charts: SeamCharts, islands: np.ndarray, apron: Apron, origin: Tuple[int, int], maps: np.ndarray,
            weight: np.ndarray, reach: float) -> Carry:
    """The paint an island laid in its ``apron`` (its box's texel (0, 0) the texture's (row, col) ``origin``),
    carried to the neighbours' own texels through the leading seams' chart maps: each texel of a neighbour within
    reach of a seam's far side, mapped into the island's frame, reads the box's ``maps`` (h, w, C) bilinearly from
    the apron texels that read that neighbour, and the weight it takes them with, ``weight`` (h, w) [0, 1] read
    alike (times the share of the four taps that are such apron texels). ``reach``: the apron's widest reach
    (``island_apron``) in the island's texels."""
    edges = np.unique(apron.edge[charts.leads[apron.edge]])
    none = Carry(np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros((0, maps.shape[2])), np.zeros(0))
    if not len(edges):
        return none
    shrink = np.linalg.svd(charts.chart[edges, :, :2], compute_uv=False)[:, -1]     # island texels per neighbour's
    far = charts.partner[edges]
    r, c, nearest, _ = near_edges(charts.ends[far], np.minimum(reach / shrink, CARRY_REACH * reach) + 1.0,
                                  islands.shape)
    edge = edges[nearest]
    keep = islands[r, c] == charts.neighbour[edge]
    r, c, edge = r[keep], c[keep], edge[keep]
    point = apply(charts.chart[edge], np.stack([c, r], axis=1).astype(float)) - [origin[1], origin[0]]
    beyond = np.zeros(maps.shape[:2], np.int32)
    beyond[apron.rows, apron.cols] = apron.neighbour
    values, total = island_bilinear(maps, beyond, charts.neighbour[edge], point)
    share, _ = island_bilinear(weight[..., None], beyond, charts.neighbour[edge], point)
    amount = share[:, 0] * total
    keep = amount > 0
    return Carry(r[keep], c[keep], values[keep], amount[keep])
