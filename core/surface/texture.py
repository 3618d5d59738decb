"""A mesh's texture painted in its UV space, island by island, with strokes of one size in the world and across the
UV seams (ALGORITHM §10).

Each island is painted as a canvas of its own. Its box in the texture,
widened by its largest stroke and the bleed, is cut out, and every texel of
the box outside the island takes the colour of the nearest island texel, so
the importance, the partition and the orientation see no border. Strokes
are anchored only on the island's texels, as a shot's births are anchored
only where they may happen, and only the island's texels are kept from its
canvas. Where the layout has seam charts (``apron``), an island that leads
across a seam paints across it: its box shows, beyond the seam, the
neighbour's picture and paint unfolded (its apron), its strokes are anchored
on the apron's inner part too, and what they lay there is composited over
the neighbour's own texels, feathered at the apron's far side, so the
strokes run on over the surface and both sides of the seam agree. The
stroke sizes are given in millimetres on the surface and turned into texels
by the island's texel density. Once every island is painted, the maps bleed
``bleed_texels`` past the islands' borders. Beyond the bleed the opacity and
height are 0 and the colour is the canvas colour. The reference's bilateral
filter spans as many millimetres on every island as it spans texels on the
texture's median texel.
"""

from __future__ import annotations

import dataclasses
import time
from typing import Dict, List, NamedTuple, Optional, Sequence, Tuple

import numpy as np
from scipy import ndimage

from ..analysis.run import analyze, check_image
from ..errors import InputError
from ..measures import psnr
from ..methods.registry import stroke_painter
from ..params import Params, scaled_sizes
from ..progress import CancelFn, ProgressFn, Stage
from ..resample import resize_area
from ..results import Painting
from ..strokes.canvas import Canvas
from ..strokes.stroke import Stroke
from .apron import (
    Apron,
    Carry,
    SeamCharts,
    apron_reach,
    carried,
    island_apron,
    island_bilinear,
    leads_any,
    seam_charts,
    widest_stretch,
)
from .atlas import Atlas, repeated_parts
from .islands import NO_ISLAND, TexelDensity, bled, bleed_texels, island_map, texel_density, uv_islands
from .mesh import SurfaceMesh
from .seams import OFFSET_TEXELS, EdgeSamples, edge_samples, seam_figures


class SurfaceLayout(NamedTuple):
    """Where a texture lies on a mesh: its island map and the islands' texel densities."""

    islands: np.ndarray         # (N, N) int32, 0 (no surface) or the island 1 .. K of each texel
    density: TexelDensity       # the islands' metres per UV unit (``islands.texel_density``)
    edges: Optional[EdgeSamples] = None     # where the texture's steps across seams and inner edges are read
    charts: Optional[SeamCharts] = None     # the chart maps across the seams (``apron.seam_charts``); None: apart
    cell_texels: Optional[int] = None       # the side of an atlas cell (``atlas``) in texels; None: one cell


def surface_layout(mesh: SurfaceMesh, size: int, across_seams: bool = True,
                   atlas: Optional[Atlas] = None) -> SurfaceLayout:
    """The layout of a ``size`` x ``size`` texture on ``mesh``: its islands rasterised, their densities, the
    samples across its edges ``OFFSET_TEXELS`` of the coarsest island's texels from them, and, with
    ``across_seams``, the chart maps strokes run on across its seams by (else each island is painted apart).
    With an ``atlas`` of several cells (whose UV ``mesh`` then holds, ``size`` a whole number of cells): islands
    end where cells change, the edges there are seams, and each triangle's texels stay within its cell. With an
    ``atlas`` (of one cell or several), a triangle of a repeating source that crosses its cell's border covers its
    texels past it on the cell's far side, where the repeated image shows them (``atlas.repeated_parts``)."""
    several = atlas is not None and len(atlas.cells) > 1
    cell = atlas.cell if several else None
    islands = uv_islands(mesh.uv, cell)
    density = texel_density(mesh.uv, mesh.position, islands)
    offset_m = OFFSET_TEXELS * float(np.nanmax(density.island, initial=0.0)) / size
    charts = seam_charts(mesh.uv, mesh.position, islands, size) if across_seams else None
    cell_texels = size // atlas.columns if several else None
    limits = None
    if several:
        place = np.array([[c.column, c.row] for c in atlas.cells], np.int64)[cell] * cell_texels
        limits = np.stack([place, place + cell_texels - 1], axis=1)
    raster_uv, raster_islands = mesh.uv, islands
    if atlas is not None:
        copied, parts = repeated_parts(atlas)
        if len(copied):
            raster_uv, raster_islands = np.concatenate([mesh.uv, parts]), np.concatenate([islands, islands[copied]])
            limits = None if limits is None else np.concatenate([limits, limits[copied]])
    return SurfaceLayout(island_map(raster_uv, raster_islands, size, limits), density,
                         edge_samples(mesh.uv, mesh.position, offset_m, None if cell is None else islands), charts,
                         cell_texels)


def square_texture(image: np.ndarray, size: int) -> np.ndarray:
    """(H, W, 3) ``image`` resampled to (size, size, 3): averaged over each new texel's area where it shrinks,
    bilinear where it grows (texel centres aligned)."""
    h, w = image.shape[:2]
    if (h, w) == (size, size):
        return image
    if h >= size and w >= size:
        return resize_area(image, size, size)
    rows = (np.arange(size) + 0.5) * (h / size) - 0.5
    cols = (np.arange(size) + 0.5) * (w / size) - 0.5
    grid = np.meshgrid(rows, cols, indexing="ij")
    return np.stack([ndimage.map_coordinates(image[..., c], grid, order=1, mode="nearest") for c in range(3)],
                    axis=-1).astype(np.float32)


def texel_mm(layout: SurfaceLayout) -> np.ndarray:
    """(K,) float64 mm: how much of island k + 1's surface one texel spans, 1000 ρ_k / N."""
    return 1000.0 * layout.density.island / layout.islands.shape[0]


def median_texel_mm(layout: SurfaceLayout) -> float:
    """mm: the texel size (``texel_mm``) of the texture's median texel, counting the texels each island covers."""
    islands = layout.islands
    counts = np.bincount(islands[islands != NO_ISLAND], minlength=len(layout.density.island) + 1)[1:]
    spans = texel_mm(layout)
    order = np.argsort(spans, kind="stable")
    weights = np.cumsum(counts[order])
    return float(spans[order][int(np.searchsorted(weights, 0.5 * weights[-1]))])


def default_stroke_mm(params: Params, layout: SurfaceLayout) -> Tuple[float, ...]:
    """The stroke widths (mm, descending) a texture is painted with unless told: the still's widths for an N x N
    picture (``scaled_sizes``) at the median texel's size (``median_texel_mm``)."""
    median = median_texel_mm(layout)
    return tuple(float(size * median) for size in scaled_sizes(params, *layout.islands.shape))


def island_sizes(stroke_mm: Sequence[float], island_texel_mm: float) -> Tuple[int, ...]:
    """The stroke widths (texels, descending, distinct, >= 2) of an island whose texel spans ``island_texel_mm``."""
    return tuple(sorted({max(2, int(round(size / island_texel_mm))) for size in stroke_mm}, reverse=True))


class IslandPainting(NamedTuple):
    """One island painted on a canvas of its own: its box in the texture and what was laid there."""

    rows: slice
    cols: slice
    mask: np.ndarray            # (h, w) bool, the island's texels in the box
    canvas: Canvas
    orientation: np.ndarray     # (h, w) radians [0, pi)
    strokes: List[Stroke]       # in the texture's texel coordinates
    per_layer: List[int]
    sizes: Tuple[int, ...]      # its stroke widths (texels)
    carry: Optional[Carry] = None   # the paint it laid beyond its seams, for the neighbours' texels


def island_box(mask: np.ndarray, margin: int, clipped: bool = True) -> Tuple[slice, slice]:
    """The rows and columns of the box around ``mask`` (H, W) bool's True texels, widened by ``margin`` texels
    (within the texture when ``clipped``, else reaching past it as far as the margin does)."""
    rows, cols = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
    h, w = mask.shape
    if not clipped:
        return slice(rows[0] - margin, rows[-1] + 1 + margin), slice(cols[0] - margin, cols[-1] + 1 + margin)
    return (slice(max(0, rows[0] - margin), min(h, rows[-1] + 1 + margin)),
            slice(max(0, cols[0] - margin), min(w, cols[-1] + 1 + margin)))


def extended(image: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """(h, w, 3) ``image`` with every texel outside ``mask`` (h, w) bool given the colour of the nearest texel
    inside it (the exact Euclidean distance transform)."""
    if mask.all():
        return image.copy()
    _, (rows, cols) = ndimage.distance_transform_edt(~mask, return_indices=True)
    return np.ascontiguousarray(image[rows, cols])


def paint_island(texture: np.ndarray, islands: np.ndarray, island: int, sizes: Tuple[int, ...],
                 smoothing: float, params: Params, stage: Stage, charts: Optional[SeamCharts] = None,
                 maps: Optional[np.ndarray] = None) -> IslandPainting:
    """Island ``island`` of the (N, N) ``islands`` map painted from (N, N, 3) sRGB [0, 1] ``texture`` with
    strokes of ``sizes`` texels and the reference's bilateral filter ``smoothing`` texels wide (module
    docstring): a still's strokes anchored on the island's texels alone, by the method's stroke painter
    (``methods.registry.stroke_painter``; ParameterError in one sentence for a method that paints stills only).
    With the layout's seam ``charts``, the box's apron (``apron.island_apron``) shows the surface beyond the
    seams, the picture and the texture painted so far (``maps`` (N, N, 6): colour, height, opacity, coverage),
    which the canvas starts from on the island's texels too; the paint its strokes lay there is the carry."""
    margin = max(sizes) + int(np.ceil(bleed_texels(islands.shape[0])))
    across = charts is not None and leads_any(charts, island)
    rows, cols = island_box(islands == island, margin)
    apron = None
    if across:
        own = islands == island
        found = [np.flatnonzero(own.any(axis=1)), np.flatnonzero(own.any(axis=0))]
        bounds = np.array([[found[0][0], found[1][0]], [found[0][-1], found[1][-1]]])
        reach, wide_rows, wide_cols = apron_reach(charts, island, bounds, (rows, cols), margin)
        wide = island_apron(charts, islands, island, (wide_rows.start, wide_cols.start),
                            padded(islands, wide_rows, wide_cols, NO_ISLAND), reach)
        r, c = wide.rows + wide_rows.start, wide.cols + wide_cols.start
        near = ((r >= bounds[0, 0] - reach) & (r <= bounds[1, 0] + reach) & (c >= bounds[0, 1] - reach)
                & (c <= bounds[1, 1] + reach))
        rows, cols, apron = fitted(rows, cols, wide, (wide_rows.start, wide_cols.start),
                                   charts.leads[wide.edge] | near)
        carry_reach = reach * widest_stretch(charts, island)
    box = padded(islands, rows, cols, NO_ISLAND)
    mask = box == island
    image = extended(padded(texture, rows, cols, 0.0), mask)
    h, w = mask.shape
    canvas = Canvas.blank((h, w), params.canvas_colour)
    if across:
        image[apron.rows, apron.cols] = island_bilinear(texture, islands, apron.neighbour, apron.source)[0]
        start = padded(maps, rows, cols, 0.0)
        start[apron.rows, apron.cols] = island_bilinear(maps, islands, apron.neighbour, apron.source)[0]
        start_canvas(canvas, start, mask | edge_mask(apron, mask.shape))
    own = dataclasses.replace(params, stroke_sizes=sizes, size_reference_megapixels=h * w / 1e6,
                              bilateral_sigma_spatial=smoothing / float(np.hypot(h, w)))
    analysis = analyze(image, own, cancel=stage.cancel)
    anchored = mask if apron is None else mask | edge_mask(apron, mask.shape, charts.leads[apron.edge] &
                                                             (apron.feather >= 1.0))
    strokes, per_layer = stroke_painter(own, "Objects")(canvas, image, analysis, own, stage, eligible=anchored)
    shift = np.array([cols.start, rows.start], np.float32)
    placed = [Stroke(s.layer, (s.anchor[0] + cols.start, s.anchor[1] + rows.start), s.size, s.path + shift,
                     s.colour) for s in strokes]
    carry = None
    orientation = analysis.orientation
    if across:
        now = canvas_maps(canvas)
        feather = np.zeros((h, w))
        feather[apron.rows, apron.cols] = apron.feather
        carry = carried(charts, islands, apron, (rows.start, cols.start),
                        np.concatenate([now, start, transmitted(start, now)[..., None]], axis=2), feather,
                        carry_reach)
        inside = (slice(-rows.start if rows.start < 0 else 0, None), slice(-cols.start if cols.start < 0 else 0, None))
        size = islands.shape[0]
        rows, cols = slice(max(rows.start, 0), min(rows.stop, size)), slice(max(cols.start, 0), min(cols.stop, size))
        inside = (slice(inside[0].start, inside[0].start + rows.stop - rows.start),
                  slice(inside[1].start, inside[1].start + cols.stop - cols.start))
        mask, orientation = mask[inside], orientation[inside]
        canvas = Canvas(canvas.colour[inside], canvas.coverage[inside], canvas.height[inside],
                        canvas.opacity[inside])
    return IslandPainting(rows, cols, mask, canvas, orientation, placed, per_layer, tuple(analysis.sizes), carry)


def fitted(rows: slice, cols: slice, apron: Apron, origin: Tuple[int, int], leading: np.ndarray) -> tuple:
    """(rows, cols, apron): the box ``rows`` x ``cols`` (within the texture) widened to hold the ``leading`` (A,)
    bool texels of ``apron`` (those the box must hold: the leading seams' and those within the island's margin), found in a box whose texel (0, 0) is the texture's (row, col) ``origin``, and the
    apron's texels inside the new box, in its coordinates."""
    r, c = apron.rows + origin[0], apron.cols + origin[1]
    if leading.any():
        rows = slice(min(rows.start, int(r[leading].min())), max(rows.stop, int(r[leading].max()) + 1))
        cols = slice(min(cols.start, int(c[leading].min())), max(cols.stop, int(c[leading].max()) + 1))
    inside = (r >= rows.start) & (r < rows.stop) & (c >= cols.start) & (c < cols.stop)
    return rows, cols, Apron(r[inside] - rows.start, c[inside] - cols.start, apron.edge[inside],
                             apron.neighbour[inside], apron.source[inside], apron.feather[inside])


def padded(values: np.ndarray, rows: slice, cols: slice, fill) -> np.ndarray:
    """A copy of ``values`` (N, N, ...) over the box ``rows`` x ``cols``, which may reach past the texture: ``fill``
    there."""
    size_y, size_x = values.shape[:2]
    if rows.start >= 0 and cols.start >= 0 and rows.stop <= size_y and cols.stop <= size_x:
        return values[rows, cols].copy()
    out = np.full((rows.stop - rows.start, cols.stop - cols.start) + values.shape[2:], fill, values.dtype)
    r0, c0 = max(rows.start, 0), max(cols.start, 0)
    r1, c1 = min(rows.stop, size_y), min(cols.stop, size_x)
    out[r0 - rows.start:r1 - rows.start, c0 - cols.start:c1 - cols.start] = values[r0:r1, c0:c1]
    return out


def edge_mask(apron: Apron, shape: Tuple[int, int], picked: Optional[np.ndarray] = None) -> np.ndarray:
    """(h, w) bool: the apron's texels in a box of ``shape`` (those where ``picked`` (A,) bool holds, if given)."""
    out = np.zeros(shape, bool)
    out[apron.rows, apron.cols] = True if picked is None else picked
    return out


def transmitted(start: np.ndarray, now: np.ndarray) -> np.ndarray:
    """(h, w) [0, 1]: how much of what a canvas held at ``start`` (h, w, 6) (``canvas_maps``) shows through the
    strokes laid since, which left it at ``now``: their transmittance, (1 - coverage now) / (1 - coverage then),
    0 where the canvas was covered already (what it held is then taken to be what lies beneath)."""
    before, after = 1.0 - start[..., 5], 1.0 - now[..., 5]
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(before > 1e-3, np.clip(after / before, 0.0, 1.0), 0.0)


def laid_over(here: np.ndarray, carry: Carry) -> np.ndarray:
    """(M, 6): texels holding ``here`` (M, 6) (``canvas_maps``) with the strokes of ``carry`` laid over them: its
    values are the canvas now, then, and the transmittance (``transmitted``), so the strokes composite over what
    the texels hold as they did over what the apron held, taken with the carry's weight."""
    now, start, through = carry.values[:, :6], carry.values[:, 6:12], carry.values[:, 12:]
    return here + carry.weight[:, None] * (now + (here - start) * through - here)


def canvas_maps(canvas: Canvas) -> np.ndarray:
    """(h, w, 6) float32: the canvas's colour (3), height, opacity and coverage, stacked."""
    return np.concatenate([canvas.colour, canvas.height[..., None], canvas.opacity[..., None],
                           canvas.coverage[..., None]], axis=2)


def start_canvas(canvas: Canvas, maps: np.ndarray, where: np.ndarray) -> None:
    """Set ``canvas`` to ``maps`` (h, w, 6) (``canvas_maps``'s stacking) where ``where`` (h, w) bool holds."""
    canvas.colour[where] = maps[where, :3]
    canvas.height[where] = maps[where, 3]
    canvas.opacity[where] = maps[where, 4]
    canvas.coverage[where] = maps[where, 5]


def check_layout(texture: np.ndarray, layout: SurfaceLayout) -> None:
    """InputError (one sentence) when the ``texture`` and the ``layout``'s island map do not fit together."""
    if layout.islands.shape != texture.shape[:2] or texture.shape[0] != texture.shape[1]:
        raise InputError(f"The texture is {texture.shape[1]} x {texture.shape[0]} texels and its island map "
                         f"{layout.islands.shape[1]} x {layout.islands.shape[0]}: both must be the same square.")
    if not (layout.islands != NO_ISLAND).any():
        raise InputError("No face of the mesh covers a texel of the texture: its UV map is empty, or lies outside "
                         "the square 0..1 where its image does not repeat (Clip or Extend).")
    present = np.unique(layout.islands[layout.islands != NO_ISLAND])
    density = layout.density.island[present - 1]
    if not (np.isfinite(density) & (density > 0)).all():
        flat = int(present[~(np.isfinite(density) & (density > 0))][0])
        raise InputError(f"UV island {flat} of the mesh has no area on the surface, so its strokes have no size: "
                         f"remove its collapsed faces or unwrap them again.")


def paint_texture(texture: np.ndarray, layout: SurfaceLayout, params: Params,
                  stroke_mm: Optional[Sequence[float]] = None, progress: ProgressFn = None,
                  cancel: CancelFn = None) -> Painting:
    """Paint the (N, N, 3) sRGB [0, 1] ``texture`` of a mesh laid out as ``layout`` says, island by island, with
    strokes ``stroke_mm`` wide on the surface (``default_stroke_mm`` when None). The Painting's maps are the
    texture's (N, N); its ``analysis`` is None (each island has its own); its statistics add "islands", each
    island's figures (``island_figures``), and "stroke_mm". ParameterError in one sentence, before any work, for a
    method or layout that paints stills only (``Params.validate_object``)."""
    params.validate_object()
    texture = check_image(texture)
    check_layout(texture, layout)
    clock = time.perf_counter()
    stroke_mm = tuple(default_stroke_mm(params, layout) if stroke_mm is None else stroke_mm)
    spans = texel_mm(layout)
    size = texture.shape[0]
    smoothing_mm = params.bilateral_sigma_spatial * size * np.sqrt(2.0) * median_texel_mm(layout)
    maps = np.zeros((size, size, 6), np.float32)          # colour, height, opacity, coverage (``canvas_maps``)
    maps[..., :3] = np.asarray(params.canvas_colour, np.float32)
    orientation = np.zeros((size, size), np.float32)
    present = np.unique(layout.islands[layout.islands != NO_ISLAND]).tolist()
    painted: Dict[int, IslandPainting] = {}
    for position, island in enumerate(present):
        named = None if progress is None else (
            lambda fraction, message, position=position: progress(
                fraction, f"Island {position + 1}/{len(present)}: {message}"))
        part = paint_island(texture, layout.islands, island, island_sizes(stroke_mm, spans[island - 1]),
                            smoothing_mm / spans[island - 1], params,
                            Stage(named, cancel, position / len(present), (position + 1) / len(present)),
                            layout.charts, maps)
        maps[part.rows, part.cols][part.mask] = canvas_maps(part.canvas)[part.mask]
        orientation[part.rows, part.cols][part.mask] = part.orientation[part.mask]
        if part.carry is not None and len(part.carry.rows):
            maps[part.carry.rows, part.carry.cols] = laid_over(maps[part.carry.rows, part.carry.cols], part.carry)
        painted[island] = part
    colour, height, opacity, coverage = (np.ascontiguousarray(maps[..., :3]), maps[..., 3].copy(),
                                         maps[..., 4].copy(), maps[..., 5].copy())
    reach = bleed_texels(size)
    colour, height, opacity, coverage, orientation = (cell_bled(values, layout, reach) for values in
                                                       (colour, height, opacity, coverage, orientation))
    np.clip(colour, 0.0, 1.0, out=colour)
    strokes = [stroke for island in present for stroke in painted[island].strokes]
    return Painting(colour, height, opacity, coverage, orientation, strokes, None, params,
                    texture_statistics(texture, colour, layout, painted, stroke_mm, params,
                                       time.perf_counter() - clock))


def cell_bled(values: np.ndarray, layout: SurfaceLayout, texels: float) -> np.ndarray:
    """``values`` (N, N, ...) bled ``texels`` past the islands of ``layout`` (``islands.bled``), within each atlas
    cell apart (``layout.cell_texels``), so no cell takes paint from another's islands."""
    side = layout.cell_texels
    if side is None or side >= layout.islands.shape[0]:
        return bled(values, layout.islands, texels)
    out = values.copy()
    for top in range(0, layout.islands.shape[0], side):
        for left in range(0, layout.islands.shape[1], side):
            block = (slice(top, top + side), slice(left, left + side))
            out[block] = bled(values[block], layout.islands[block], texels)
    return out


def texture_statistics(texture: np.ndarray, colour: np.ndarray, layout: SurfaceLayout,
                       painted: Dict[int, IslandPainting], stroke_mm: Sequence[float], params: Params,
                       seconds: float) -> dict:
    """The report's figures of a painted texture: the method, layout and renderer it was painted with, strokes, the
    PSNR over the islands' texels, and each island's
    figures (``island_figures``); with the layout's edges, the steps across seams and inner edges
    (``seams.seam_figures``)."""
    surface = layout.islands != NO_ISLAND
    layers = max(len(part.per_layer) for part in painted.values())
    per_layer = [sum(part.per_layer[k] for part in painted.values() if k < len(part.per_layer))
                 for k in range(layers)]
    seams = {} if layout.edges is None else {"seam_steps": seam_figures(layout.edges, texture, colour)}
    return {"method": params.method, "layout": params.layout, "renderer": params.renderer,
            "strokes": int(sum(per_layer)), "strokes_per_layer": per_layer,
            "psnr_db": round(psnr(colour[surface], texture[surface]), 3),
            "seconds": {"painting": round(seconds, 4)}, "width": int(texture.shape[1]),
            "height": int(texture.shape[0]), "seed": params.seed, "stroke_mm": [round(s, 3) for s in stroke_mm],
            "bleed_texels": bleed_texels(texture.shape[0]),
            "islands": [island_figures(island, part, layout) for island, part in painted.items()], **seams}


def island_figures(island: int, part: IslandPainting, layout: SurfaceLayout) -> dict:
    """Island ``island``'s figures: texels, texel density (m per UV unit) and texel size (mm), how far its faces'
    densities stray from it, its stroke widths (texels) and its strokes' widths in mm (median and quartiles, all
    and per layer)."""
    span = float(texel_mm(layout)[island - 1])
    widths = np.array([stroke.size for stroke in part.strokes], float) * span
    layers = np.array([stroke.layer for stroke in part.strokes], int)

    def spread(values: np.ndarray) -> Optional[List[float]]:
        return None if len(values) == 0 else [round(float(v), 3) for v in np.percentile(values, [25, 50, 75])]

    return {"island": island, "texels": int(part.mask.sum()),
            "density_m_per_uv": round(float(layout.density.island[island - 1]), 6), "texel_mm": round(span, 4),
            "face_density_stray": round(float(layout.density.stray[island - 1]), 4),
            "sizes_texels": list(part.sizes), "strokes": len(part.strokes),
            "stroke_mm_quartiles": spread(widths),
            "stroke_mm_median_per_layer": [None if not np.any(layers == k) else
                                           round(float(np.median(widths[layers == k])), 3)
                                           for k in range(len(part.per_layer))]}
