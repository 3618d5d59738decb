"""The lighting comparison: the paper's 2-D lighting against the same painting relit as true impasto.

For each light azimuth, Blender renders the canvas with relief and without it
(flat) under the same light. The 3-D shading is S3D = relief / flat - 1 on
luminance; each 2-D model gives S2D = lit / unlit - 1 the same way. All
ratios are taken in linear light. Angles follow the painter: degrees in the
image plane from +x (right) towards +y (down).
"""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Dict, List, Optional, Sequence

import numpy as np

from ..colour import linear_to_srgb, luminance, srgb_to_linear
from ..errors import InputError, ParameterError
from ..figures.chart import line_chart
from ..figures.gif import write_gif
from ..figures.sheet import contact_sheet
from ..files import reading, writing
from ..files.staging import staged_outputs
from ..lighting import DEFAULT_RELIEF, bump_lighting, directional_lighting, paper_lighting
from ..measures.metrics import pearson, ssim
from ..progress import ProgressFn, Stage

MODELS = ("paper", "directional", "bump")
MODEL_LABELS = {"paper": "paper (Eq. 6-7)", "directional": "directional Eq. 7", "bump": "bump (Blinn-Phong)"}
DARK = 0.01
"""Pixels whose linear luminance is below this in the unlit image or the flat render are left out."""


def render_path(renders_dir: Path, kind: str, azimuth_deg: float) -> Path:
    """Where the ``kind`` ('flat' or 'relief') render at ``azimuth_deg`` lives."""
    return Path(renders_dir) / f"{kind}_{azimuth_deg:03.0f}.exr"


def read_rgb_exr(path: Path, shape: Optional[tuple] = None) -> np.ndarray:
    """(H, W, 3) float32 of an RGB(A) EXR; InputError if missing or of another (H, W)."""
    if not Path(path).exists():
        raise InputError(f"{path} is missing.")
    data, _, _ = reading.read_exr(path)
    if data.shape[2] < 3 or (shape is not None and data.shape[:2] != tuple(shape)):
        raise InputError(f"{path} must be an RGB image of {shape[1]}x{shape[0]} pixels, got {data.shape[1]}x"
                         f"{data.shape[0]} with {data.shape[2]} channels.")
    return data[..., :3]


def read_painting(painting_dir: Path) -> Dict[str, np.ndarray]:
    """The maps of a painted folder: colour (sRGB and linear), height, orientation, each (H, W[, 3])."""
    folder = Path(painting_dir)
    maps = {}
    for name in ("color", "height", "orientation"):
        path = folder / f"{name}.exr"
        if not path.exists():
            raise InputError(f"{path} is missing: paint into {folder} first.")
        maps[name] = reading.read_exr(path)[0]
    linear = maps["color"][..., :3]
    return {"linear": linear, "srgb": linear_to_srgb(linear), "height": maps["height"][..., 0],
            "orientation": maps["orientation"][..., 0]}


def shading(lit_linear: np.ndarray, base_linear: np.ndarray) -> np.ndarray:
    """(H, W) lum(lit) / lum(base) - 1 of two (H, W, 3) linear images (0 where base is dark)."""
    base = luminance(base_linear)
    return np.where(base > DARK, luminance(lit_linear) / np.maximum(base, DARK) - 1.0, 0.0).astype(np.float32)


def lit_2d(model: str, maps: Dict[str, np.ndarray], azimuth_deg: float, elevation_deg: float,
           relief_px: float) -> np.ndarray:
    """(H, W, 3) sRGB painting lit by a 2-D ``model`` with the light at the given angles (degrees)."""
    if model == "paper":
        return paper_lighting(maps["srgb"], maps["height"], maps["orientation"])
    if model == "directional":
        return directional_lighting(maps["srgb"], maps["height"], math.radians(azimuth_deg))
    return bump_lighting(maps["srgb"], maps["height"], math.radians(azimuth_deg), math.radians(elevation_deg),
                         relief=relief_px)


def exposure(flat_linear: np.ndarray, unlit_linear: np.ndarray) -> float:
    """Scalar k with flat ~ k * unlit: the ratio of mean luminances of the flat render and the painting."""
    return float(luminance(flat_linear).mean() / max(float(luminance(unlit_linear).mean()), 1e-6))


def shading_measures(s3d: np.ndarray, s2d: np.ndarray, mask: np.ndarray, lit_srgb: np.ndarray,
                     relief_srgb: np.ndarray) -> Dict[str, float]:
    """Pearson r and RMS difference of two shadings over ``mask``; SSIM of the lit image and the relief render."""
    return {"pearson": round(pearson(s3d[mask], s2d[mask]), 5),
            "rms": round(float(np.sqrt(np.mean((s3d[mask] - s2d[mask]) ** 2))), 5),
            "ssim": round(ssim(lit_srgb, relief_srgb), 5)}


def compare_sweep(maps: Dict[str, np.ndarray], renders_dir: Path, azimuths_deg: Sequence[float],
                  elevation_deg: float, relief_px: float, stage: Stage) -> tuple:
    """Figures for every azimuth and model, plus the images the pictures need."""
    shape = maps["height"].shape
    unlit = maps["linear"]
    per_azimuth: List[dict] = []
    frames = {}
    paper = lit_2d("paper", maps, 0.0, elevation_deg, relief_px)
    for i, az in enumerate(azimuths_deg):
        stage.report(i / len(azimuths_deg), f"Comparing the light at {az:g} degrees")
        flat = read_rgb_exr(render_path(renders_dir, "flat", az), shape)
        relief = read_rgb_exr(render_path(renders_dir, "relief", az), shape)
        s3d = shading(relief, flat)
        mask = (luminance(flat) > DARK) & (luminance(unlit) > DARK)
        relief_srgb = linear_to_srgb(relief / max(exposure(flat, unlit), 1e-6))
        entry = {"azimuth_deg": float(az), "s3d_mean": round(float(s3d[mask].mean()), 5) if mask.any() else 0.0,
                 "models": {}}
        for model in MODELS:
            lit = paper if model == "paper" else lit_2d(model, maps, az, elevation_deg, relief_px)
            s2d = shading(srgb_to_linear(lit), unlit)
            entry["models"][model] = shading_measures(s3d, s2d, mask, lit, relief_srgb)
        per_azimuth.append(entry)
        frames[az] = {"relief_srgb": relief_srgb, "s3d": s3d}
    return per_azimuth, frames, paper


def signed_map(values: np.ndarray) -> np.ndarray:
    """(H, W, 3) diverging picture of signed values: blue negative, white zero, red positive."""
    scale = max(float(np.percentile(np.abs(values), 99)), 1e-6)
    t = np.clip(values / scale, -1.0, 1.0)[..., None]
    red, blue, white = np.array([0.8, 0.1, 0.1]), np.array([0.1, 0.2, 0.8]), np.ones(3)
    return np.where(t >= 0, white + t * (red - white), white - t * (blue - white)).astype(np.float32)


def markdown(result: dict) -> str:
    """comparison.md: the figures as tables, with how to read them."""
    lines = ["# Lighting comparison", "",
             f"Light elevation {result['elevation_deg']:g} degrees; azimuths in the image plane from +x (right) "
             "towards +y (down). S3D = relief / flat - 1 from the Cycles renders; each 2-D model's "
             "S2D = lit / unlit - 1; both on linear luminance.", "",
             "| azimuth | " + " | ".join(f"r {m}" for m in MODELS) + " | " + " | ".join(f"RMS {m}" for m in MODELS)
             + " | " + " | ".join(f"SSIM {m}" for m in MODELS) + " |",
             "| ---: |" + " ---: |" * (3 * len(MODELS))]
    for entry in result["azimuths"]:
        m = entry["models"]
        lines.append(f"| {entry['azimuth_deg']:g} | " + " | ".join(f"{m[k]['pearson']:+.3f}" for k in MODELS) + " | "
                     + " | ".join(f"{m[k]['rms']:.4f}" for k in MODELS) + " | "
                     + " | ".join(f"{m[k]['ssim']:.3f}" for k in MODELS) + " |")
    lines += ["", f"The paper's model matches the relief best with the light at {result['best_azimuth_deg']:g} "
              f"degrees (r = {result['best_pearson']:+.3f}); its correlation ranges from "
              f"{result['paper_pearson_range'][0]:+.3f} to {result['paper_pearson_range'][1]:+.3f} over the sweep, "
              "because its light turns with the strokes while a real light does not.", ""]
    return "\n".join(lines)


def run_comparison(painting_dir, renders_dir, azimuths_deg: Sequence[float], elevation_deg: float, out_dir,
                   progress: ProgressFn = None, relief_px: float = DEFAULT_RELIEF) -> dict:
    """Compare the 2-D lighting models with the Cycles renders; write the figures and pictures.

    painting_dir: a folder written by ``python -m core paint``. renders_dir:
    ``flat_AAA.exr`` and ``relief_AAA.exr`` (scene-linear, the maps' size) for
    every azimuth AAA (degrees, painter convention). relief_px: the bump
    model's relief (pixel widths per height unit), ideally the scene's
    thickness over its pixel size. Writes comparison.json, comparison.md,
    comparison.png, correlation.png and light_sweep.gif into ``out_dir``;
    returns the JSON dictionary.
    """
    if len(azimuths_deg) == 0:
        raise ParameterError("The light sweep needs at least one azimuth.")
    t0 = time.perf_counter()
    stage = Stage(progress, None)
    maps = read_painting(Path(painting_dir))
    per_azimuth, frames, paper = compare_sweep(maps, Path(renders_dir), list(azimuths_deg), elevation_deg,
                                               relief_px, stage.sub(0.0, 0.6))
    paper_r = [e["models"]["paper"]["pearson"] for e in per_azimuth]
    best = int(np.argmax(paper_r))
    best_az = per_azimuth[best]["azimuth_deg"]
    result = {"elevation_deg": float(elevation_deg), "relief_px": float(relief_px), "models": list(MODELS),
              "azimuths": per_azimuth, "best_azimuth_deg": best_az, "best_pearson": paper_r[best],
              "paper_pearson_range": [min(paper_r), max(paper_r)]}
    stage.report(0.6, "Drawing the comparison pictures")
    out = writing.ensure_output_dir(out_dir)
    bump = lit_2d("bump", maps, best_az, elevation_deg, relief_px)
    best_frame = frames[best_az]
    s_paper = shading(srgb_to_linear(paper), maps["linear"])
    measures_at_best = per_azimuth[best]["models"]
    sheet = contact_sheet([
        ("Unlit painting", maps["srgb"]),
        (f"Paper 2-D lighting, r = {measures_at_best['paper']['pearson']:+.2f}", paper),
        (f"Bump 2-D, light {best_az:g} deg, r = {measures_at_best['bump']['pearson']:+.2f}", bump),
        (f"Cycles relief, light {best_az:g} deg", best_frame["relief_srgb"]),
        ("S3D - S2D(paper): red +, blue -", signed_map(best_frame["s3d"] - s_paper)),
    ], panel_height=min(360, maps["height"].shape[0]), columns=5)
    azimuths = [e["azimuth_deg"] for e in per_azimuth]
    chart = line_chart([(MODEL_LABELS[m], azimuths, [e["models"][m]["pearson"] for e in per_azimuth]) for m in MODELS],
                       (0, 360), (-1, 1), range(0, 361, 45), [-1, -0.5, 0, 0.5, 1],
                       title="2-D shading against the Cycles relief shading", x_label="light azimuth (degrees)",
                       y_label="Pearson r")
    gif_frames = [contact_sheet([(f"Cycles relief, light at {az:g} deg", frames[az]["relief_srgb"]),
                                 ("Paper 2-D lighting (cannot turn)", paper)],
                                panel_height=min(320, maps["height"].shape[0]), columns=2) for az in azimuths]
    result["seconds"] = round(time.perf_counter() - t0, 3)
    with staged_outputs(out) as staging:
        writing.write_png(staging / "comparison.png", sheet)
        writing.write_png(staging / "correlation.png", chart)
        write_gif(staging / "light_sweep.gif", gif_frames, seconds_per_frame=0.6)
        writing.write_json(staging / "comparison.json", result)
        writing.write_text(staging / "comparison.md", markdown(result))
    stage.report(1.0, "Comparison written")
    return result
