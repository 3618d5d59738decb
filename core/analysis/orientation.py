"""Orientation field of the strokes (ALGORITHM §4, Eq. 3).

    O = Ẽ · O_GN + (1 − Ẽ) · O_RBF

O_GN is the edge tangent from a smoothed structure tensor; O_RBF is a local
radial-basis-function interpolation of O_GN known at key points (the strongest
pixel of each cell of a coarse grid), evaluated on a coarse grid and
upsampled. Orientations are axial (θ ≡ θ + π): they
are always interpolated and blended as doubled-angle vectors (cos 2θ, sin 2θ)
and the angle of the result is halved.

Conventions: x = column, y = row (downwards); angles in radians from +x towards
+y; every orientation returned is float32 in [0, π).
"""

from __future__ import annotations

import math
from typing import Tuple

import numpy as np
from scipy import ndimage
from scipy.spatial import cKDTree
from threadpoolctl import threadpool_limits

from .. import tuning
from ..workers import in_row_blocks, run_all

_PI32 = np.float32(math.pi)
_TINY = 1e-12
_SMOOTHING = 1e-6


def _wrap_axial(theta: np.ndarray) -> np.ndarray:
    """Angles (any shape, radians) -> float32 in [0, π) (mod π, with float32 rounding fixed)."""
    t = np.mod(np.asarray(theta, dtype=np.float64), math.pi).astype(np.float32)
    t[(t >= _PI32) | ~np.isfinite(t)] = 0.0
    return t


def _half_angle(c: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Doubled-angle vector components (c, s) -> axial angle ½·atan2(s, c), float32 in [0, π).

    For float32 components the values of ``_wrap_axial`` without its float64
    copy: the half angle lies in [-π/2, π/2], so only the negative ones move
    up by π (added in float64, as there).
    """
    t = 0.5 * np.arctan2(s, c)
    if t.dtype != np.float32:
        return _wrap_axial(t)
    np.add(t, math.pi, out=t, where=t < 0, dtype=np.float64, casting="unsafe")
    t[(t >= _PI32) | ~np.isfinite(t)] = 0.0
    return t


def gradient_normal(intensity: np.ndarray, sigma: float) -> Tuple[np.ndarray, np.ndarray]:
    """O_GN: the direction normal to the local gradient (the edge tangent).

    intensity: (H, W) grayscale, any float (values in [0, 1] expected).
    sigma: Gaussian sigma in px of the structure-tensor smoothing (0 = none).

    Sobel derivatives gx, gy (divided by 8, i.e. intensity units per px) form
    the structure tensor (Jxx, Jxy, Jyy) = (gx², gx·gy, gy²), smoothed by the
    Gaussian; smoothing makes the direction well defined at stripe crests where
    the raw gradient vanishes, and averages axially (a gradient and its
    opposite agree). The dominant gradient direction is ½·atan2(2Jxy, Jxx−Jyy);
    the tangent is that + π/2.

    Returns (theta, strength):
      theta    float32 (H, W) in [0, π), the edge tangent; 0 (horizontal) where
               the tensor vanishes (flat regions, e.g. a constant image).
      strength float32 (H, W) >= 0, sqrt(λ1), the square root of the larger
               eigenvalue of the smoothed tensor: the RMS gradient magnitude
               along the dominant direction (intensity units per px, same
               units as importance.sobel_energy).
    """
    i = np.asarray(intensity, dtype=np.float32)
    gx, gy = run_all(lambda axis: ndimage.sobel(i, axis=axis, mode="nearest") / np.float32(8.0), (1, 0))
    tensor = (gx * gx, gx * gy, gy * gy)
    del gx, gy
    if sigma > 0:
        tensor = run_all(lambda j: ndimage.gaussian_filter(j, sigma, mode="nearest", truncate=3.0), tensor)
    jxx, jxy, jyy = tensor
    theta, strength = np.empty(i.shape, np.float32), np.empty(i.shape, np.float32)

    def direction(rows: slice) -> None:
        diff = jxx[rows] - jyy[rows]
        trace = jxx[rows] + jyy[rows]
        root = np.sqrt(np.maximum(0.25 * diff * diff + jxy[rows] * jxy[rows], 0.0))
        strength[rows] = np.sqrt(np.maximum(0.5 * trace + root, 0.0))
        # tangent = gradient direction + π/2, i.e. doubled angle + π: negate the doubled vector.
        theta[rows] = _half_angle(-diff, -2.0 * jxy[rows])
        theta[rows][trace <= _TINY] = 0.0

    in_row_blocks(direction, *i.shape)
    return theta, strength


def _key_grid(h: int, w: int, cells: int) -> Tuple[int, int]:
    """Cell size (cy, cx) in px for about cells × cells roughly square cells over an h × w image."""
    side = math.sqrt(h * w) / max(int(cells), 1)
    ny = min(h, max(1, int(round(h / side))))
    nx = min(w, max(1, int(round(w / side))))
    return int(math.ceil(h / ny)), int(math.ceil(w / nx))


def key_points(strength: np.ndarray, energy: np.ndarray, cells: int, threshold: float,
               max_points: int) -> Tuple[np.ndarray, np.ndarray]:
    """Key points for O_RBF: the strongest pixel (by energy) of each cell of a coarse grid.

    strength: (H, W) >= 0, the O_GN strength; ties in energy are broken by it,
              and pixels with zero strength (undefined O_GN) are never chosen.
    energy:   (H, W) normalised importance Ẽ in [0, 1].
    cells:    about cells × cells cells in all; the count along each side is
              proportional to that side, so cells are roughly square.
    threshold: a cell's pixel is kept only if its energy >= threshold.
    max_points: at most this many are kept (the highest-energy ones).

    Returns (ys, xs): int64 arrays of row and column indices, in raster order.
    Vectorised: the image is padded to whole cells and reshaped so one argmax
    per cell finds its best pixel.
    """
    e = np.asarray(energy, dtype=np.float32)
    s = np.asarray(strength, dtype=np.float32)
    h, w = e.shape
    empty = (np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64))
    if h == 0 or w == 0 or max_points < 1:
        return empty
    cy, cx = _key_grid(h, w, cells)
    ny, nx = -(-h // cy), -(-w // cx)
    smax = float(s.max()) if s.size else 0.0
    # Rank by energy; strength adds at most 1e-6, so it only reorders (near-)ties in energy.
    score = e.astype(np.float64) + (1e-6 / smax if smax > 0 else 0.0) * s
    score[~(s > 0) | ~np.isfinite(score)] = -np.inf
    padded = np.full((ny * cy, nx * cx), -np.inf)
    padded[:h, :w] = score
    blocks = padded.reshape(ny, cy, nx, cx).transpose(0, 2, 1, 3).reshape(ny, nx, cy * cx)
    best = blocks.argmax(axis=2)
    by, bx = np.divmod(best, cx)
    ys = (np.arange(ny)[:, None] * cy + by).ravel()
    xs = (np.arange(nx)[None, :] * cx + bx).ravel()
    inside = (ys < h) & (xs < w)
    ys, xs = ys[inside], xs[inside]
    ok = np.isfinite(score[ys, xs]) & (e[ys, xs] >= threshold)
    ys, xs = ys[ok], xs[ok]
    if ys.size > max_points:
        order = np.argsort(-score[ys, xs], kind="stable")[:max_points]
        order.sort()
        ys, xs = ys[order], xs[order]
    return ys.astype(np.int64), xs.astype(np.int64)


def _dominant(theta: np.ndarray) -> float:
    """Axial mean of angles (any shape): half the angle of the mean doubled-angle vector; 0 if it is ~0."""
    t = np.asarray(theta, dtype=np.float64)
    if t.size == 0:
        return 0.0
    c, s = float(np.cos(2 * t).mean()), float(np.sin(2 * t).mean())
    if math.hypot(c, s) < 1e-6:
        return 0.0
    return float(_wrap_axial(np.array([0.5 * math.atan2(s, c)]))[0])


def _coarse_axis(n: int, step: int) -> np.ndarray:
    """Sample positions 0, step, 2·step, … plus the last index n − 1."""
    pos = np.arange(0, n, step, dtype=np.int64)
    if pos[-1] != n - 1:
        pos = np.append(pos, n - 1)
    return pos


def _upsample_axis(values: np.ndarray, pos: np.ndarray, n: int, axis: int) -> np.ndarray:
    """Linear interpolation of values sampled at integer positions pos along axis to 0..n−1."""
    if len(pos) == 1:
        return np.repeat(values, n, axis=axis)
    full = np.arange(n, dtype=np.float64)
    i0 = np.clip(np.searchsorted(pos, full, side="right") - 1, 0, len(pos) - 2)
    f = ((full - pos[i0]) / (pos[i0 + 1] - pos[i0])).astype(np.float32)
    a = np.take(values, i0, axis=axis)
    b = np.take(values, i0 + 1, axis=axis)
    shape = [1] * values.ndim
    shape[axis] = n
    f = f.reshape(shape)
    return a + (b - a) * f


def _pairwise(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Euclidean distances between (..., p, 2) and (..., q, 2) point sets -> (..., p, q)."""
    dy = a[..., :, None, 0] - b[..., None, :, 0]
    dx = a[..., :, None, 1] - b[..., None, :, 1]
    return np.hypot(dy, dx)


def _solve_local(pts: np.ndarray, val: np.ndarray, sets: np.ndarray, smoothing: float) -> np.ndarray:
    """Coefficients (c, k+1, d) float64 of the interpolant −r + constant on each neighbour set (c, k).

    pts (n, 2) and val (n, d) float64; one (k+1) × (k+1) system per set, solved
    by np.linalg.solve a chunk of sets at a time. BLAS is held to one thread
    while it runs: the OpenBLAS of NumPy 1.x (Blender 4.2 to 5.0) threads every
    33 × 33 solve, and on a busy machine its threads spin against each other
    (bench/solve.py shows both).
    """
    c, k = sets.shape
    coeffs = np.empty((c, k + 1, val.shape[1]))
    eye = smoothing * np.eye(k)
    chunk = max(1, tuning.RBF_SOLVE_VALUES // ((k + 1) ** 2))
    with threadpool_limits(limits=1, user_api="blas"):
        for start in range(0, c, chunk):
            s = sets[start:start + chunk]
            p = pts[s]                                                # (c, k, 2)
            lhs = np.zeros((s.shape[0], k + 1, k + 1))
            lhs[:, :k, :k] = eye - _pairwise(p, p)
            lhs[:, :k, k] = 1.0
            lhs[:, k, :k] = 1.0
            rhs = np.zeros((s.shape[0], k + 1, val.shape[1]))
            rhs[:, :k] = val[s]
            coeffs[start:start + chunk] = np.linalg.solve(lhs, rhs)
    return coeffs


def _eval_local(pts: np.ndarray, sets: np.ndarray, coeffs: np.ndarray, query: np.ndarray,
                which: np.ndarray) -> np.ndarray:
    """Evaluate local interpolant number which[i] at query[i]: (m, 2), (m,) -> (m, d)."""
    out = np.empty((query.shape[0], coeffs.shape[2]))
    k = sets.shape[1]
    chunk = max(1, tuning.RBF_EVAL_VALUES // k)
    for start in range(0, query.shape[0], chunk):
        q = query[start:start + chunk]
        wh = which[start:start + chunk]
        r = _pairwise(q[:, None, :], pts[sets[wh]])[:, 0, :]          # (m, k)
        c = coeffs[wh]
        out[start:start + chunk] = np.einsum("mk,mkd->md", -r, c[:, :k]) + c[:, k]
    return out


def _lattice(coords: np.ndarray, spacing: float) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Centre positions covering sorted coords every ~spacing, and each coord's cell (i0) and fraction f."""
    lo, hi = float(coords[0]), float(coords[-1])
    if hi <= lo:
        return np.array([lo]), np.zeros(len(coords), dtype=np.int64), np.zeros(len(coords))
    cells = max(1, int(math.ceil((hi - lo) / spacing - 1e-9)))
    centres = np.linspace(lo, hi, cells + 1)
    u = (coords - lo) / (hi - lo) * cells
    i0 = np.clip(np.floor(u).astype(np.int64), 0, cells - 1)
    return centres, i0, u - i0


def local_rbf_grid(points: np.ndarray, values: np.ndarray, gy: np.ndarray, gx: np.ndarray,
                   neighbors: int, spacing: float, smoothing: float = _SMOOTHING) -> np.ndarray:
    """Local RBF interpolation of (n, 2) points (y, x) with (n, d) values on the grid gy × gx.

    gy (a,), gx (b,): ascending grid coordinates, same units as points.
    neighbors: points per local fit (min(neighbors, n)). spacing: distance
    between local-fit centres. Returns float64 (a, b, d).

    Each local fit is the interpolant φ(r) = −r plus a constant (scipy's
    'linear' kernel with degree=0; ``smoothing`` added to the kernel
    diagonal) on the k nearest points of a centre. The centres form a lattice
    every ~spacing over the grid, and each grid point blends the four fits of
    its lattice cell's corners with bilinear weights (a partition of unity).
    So the field is continuous (scipy's per-point ``neighbors`` mode jumps
    wherever the neighbour set changes), a constant field is reproduced
    exactly, no collinear configuration is singular, and one batched
    np.linalg.solve per ~1 000 centres replaces scipy's Python loop over ~13 000
    neighbour sets (0.1 s instead of 0.4 s at 1 MP). With k = n it is the
    single global interpolant, exactly RBFInterpolator(kernel='linear', degree=0).
    """
    pts = np.asarray(points, dtype=np.float64)
    val = np.asarray(values, dtype=np.float64)
    gy = np.asarray(gy, dtype=np.float64)
    gx = np.asarray(gx, dtype=np.float64)
    n, d = pts.shape[0], val.shape[1]
    k = max(1, min(int(neighbors), n))
    a, b = len(gy), len(gx)
    if k == n:
        sets = np.arange(n)[None, :]
        coeffs = _solve_local(pts, val, sets, smoothing)
        grid = np.stack(np.meshgrid(gy, gx, indexing="ij"), axis=-1).reshape(-1, 2)
        return _eval_local(pts, sets, coeffs, grid, np.zeros(a * b, dtype=np.int64)).reshape(a, b, d)
    cy, iy, fy = _lattice(gy, spacing)
    cx, ix, fx = _lattice(gx, spacing)
    centres = np.stack(np.meshgrid(cy, cx, indexing="ij"), axis=-1).reshape(-1, 2)
    _, sets = cKDTree(pts).query(centres, k)
    sets = np.asarray(sets, dtype=np.int64).reshape(len(centres), k)
    coeffs = _solve_local(pts, val, sets, smoothing)
    grid = np.stack(np.meshgrid(gy, gx, indexing="ij"), axis=-1).reshape(-1, 2)
    out = np.zeros((a * b, d))
    for dy in (0, 1):
        wy = fy if dy else 1.0 - fy
        jy = np.minimum(iy + dy, len(cy) - 1)
        for dx in (0, 1):
            wx = fx if dx else 1.0 - fx
            jx = np.minimum(ix + dx, len(cx) - 1)
            wgt = (wy[:, None] * wx[None, :]).ravel()
            which = (jy[:, None] * len(cx) + jx[None, :]).ravel()
            use = wgt > 0
            out[use] += wgt[use, None] * _eval_local(pts, sets, coeffs, grid[use], which[use])
    return out.reshape(a, b, d)


def rbf_orientation(theta_gn: np.ndarray, ys: np.ndarray, xs: np.ndarray, shape: Tuple[int, int],
                    neighbors: int, step: int) -> np.ndarray:
    """O_RBF: RBF interpolation of theta_gn known at the key points (ys, xs).

    theta_gn: (H, W) orientations in radians (axial). ys, xs: int key-point
    rows/columns. shape: (H, W) of the output. neighbors: key points used per
    evaluation (local fit; min(neighbors, n)). step: coarse-grid spacing in px
    (>= 1; the last row and column are always included).

    Key orientations are encoded as (cos 2θ, sin 2θ), interpolated by
    local_rbf_grid (local 'linear'-kernel RBF fits with a constant term, as
    scipy's RBFInterpolator(kernel='linear', degree=0), on the ``neighbors``
    nearest keys of centres spaced max(step, sqrt(H·W/n)) px apart, blended
    by a bilinear partition of unity; coordinates divided by max(H, W);
    smoothing 1e-6), evaluated on the coarse grid, upsampled bilinearly, and
    the angle halved.

    Fallbacks: 0 key points -> the axial mean of the whole theta_gn field
    (0 if that is undefined) everywhere; 1 or 2 key points -> their axial mean
    everywhere. Returns float32 (H, W) in [0, π).
    """
    h, w = int(shape[0]), int(shape[1])
    tg = np.asarray(theta_gn)
    ys = np.asarray(ys, dtype=np.int64).ravel()
    xs = np.asarray(xs, dtype=np.int64).ravel()
    n = ys.size
    if h == 0 or w == 0:
        return np.zeros((h, w), dtype=np.float32)
    if n == 0:
        return np.full((h, w), _dominant(tg), dtype=np.float32)
    key_theta = tg[ys, xs].astype(np.float64)
    if n <= 2:
        return np.full((h, w), _dominant(key_theta), dtype=np.float32)

    unit = float(max(h, w))
    points = np.column_stack([ys, xs]).astype(np.float64) / unit
    values = np.column_stack([np.cos(2 * key_theta), np.sin(2 * key_theta)])
    step = max(1, int(step))
    py, px = _coarse_axis(h, step), _coarse_axis(w, step)
    spacing = max(float(step), math.sqrt(h * w / n)) / unit
    coarse = local_rbf_grid(points, values, py / unit, px / unit, neighbors, spacing, _SMOOTHING)
    coarse = coarse.astype(np.float32)
    along = _upsample_axis(coarse, py, h, axis=0)
    dominant = _dominant(key_theta)
    theta = np.empty((h, w), np.float32)

    def halved(rows: slice) -> None:
        full = _upsample_axis(along[rows], px, w, axis=1)
        c, s = full[..., 0], full[..., 1]
        theta[rows] = _half_angle(c, s)
        # Where the interpolated vector vanishes the angle is meaningless: use the keys' axial mean.
        theta[rows][(c * c + s * s) < 1e-12] = dominant

    in_row_blocks(halved, h, w)
    return theta


def blend_orientations(theta_gn: np.ndarray, theta_rbf: np.ndarray, energy: np.ndarray) -> np.ndarray:
    """Eq. 3: O = Ẽ·O_GN + (1 − Ẽ)·O_RBF on doubled-angle unit vectors.

    theta_gn, theta_rbf: (H, W) radians (axial). energy: (H, W) weight Ẽ,
    clipped to [0, 1]. The weighted sum of (cos 2θ, sin 2θ) has its angle
    halved; where the sum is ~0 (opposite directions, equal weights) O_GN is
    taken. Returns float32 (H, W) in [0, π).
    """
    energy = np.asarray(energy, dtype=np.float32)
    h, w = energy.shape
    theta_gn = np.broadcast_to(theta_gn, (h, w))
    theta_rbf = np.broadcast_to(np.asarray(theta_rbf, dtype=np.float32), (h, w))
    theta = np.empty((h, w), np.float32)

    def blended(rows: slice) -> None:
        e = np.clip(energy[rows], 0.0, 1.0)
        g2 = 2.0 * np.asarray(theta_gn[rows], dtype=np.float32)
        r2 = 2.0 * theta_rbf[rows]
        c = e * np.cos(g2) + (1.0 - e) * np.cos(r2)
        s = e * np.sin(g2) + (1.0 - e) * np.sin(r2)
        theta[rows] = _half_angle(c, s)
        degenerate = (c * c + s * s) < 1e-8
        if degenerate.any():
            theta[rows][degenerate] = _wrap_axial(theta_gn[rows][degenerate])

    in_row_blocks(blended, h, w)
    return theta


def orientation_field(intensity: np.ndarray, energy: np.ndarray, params, scale: float = 1.0) -> np.ndarray:
    """The stroke orientation field of Eq. 3, float32 (H, W) in [0, π).

    intensity: float32 (H, W) grayscale reference luminance in [0, 1].
    energy:    float32 (H, W) normalised importance Ẽ in [0, 1].
    params:    core.params.Params (orientation_smoothing, key_cells,
               key_threshold, max_key_points, rbf_neighbors, rbf_grid_step).
    scale:     sqrt(pixels / 1e6) of the image being painted (1.0 at 1 MP).

    Scaling: the structure-tensor sigma is orientation_smoothing · max(scale, 0.5)
    px (it scales with the image, but stops shrinking below scale 0.5, a
    quarter megapixel, so stripe crests stay bridged); the RBF coarse
    step is max(1, round(rbf_grid_step · scale)) px, so the coarse grid has
    about the same number of samples (~16 k) at any size. Key-point settings
    are used as given.
    """
    i = np.asarray(intensity, dtype=np.float32)
    e = np.asarray(energy, dtype=np.float32)
    if i.shape != e.shape:
        raise ValueError(f"intensity {i.shape} and energy {e.shape} must have the same shape")
    sigma = float(params.orientation_smoothing) * max(float(scale), 0.5)
    step = max(1, int(round(params.rbf_grid_step * float(scale))))
    theta_gn, strength = gradient_normal(i, sigma)
    ys, xs = key_points(strength, e, params.key_cells, params.key_threshold, params.max_key_points)
    theta_rbf = rbf_orientation(theta_gn, ys, xs, i.shape, params.rbf_neighbors, step)
    return blend_orientations(theta_gn, theta_rbf, e)
