"""Optical flow candidates against the true motion of a Blender render: seconds per megapixel and errors.

The render is a folder of multilayer EXR frames with the Vector pass, as
sample_scenes/sequence_scene.py writes them (frame_0001.exr, ...). For each
pair of consecutive frames t, t+1 the true forward motion is (−Z, +W) of frame
t's Vector part and the true backward motion (X, −Y) of frame t+1's
(ALGORITHM §9, "Motion"); the frames are the Combined part turned to
sRGB (clipped to [0, 1]). Pixels are scored where the true motion passes the
forward-backward check of ALGORITHM §9 (visible in both frames, not on a
motion boundary, landing inside the frame). Per candidate, averaged over the
pairs:

- s/MP: median over the pairs of the seconds per megapixel of one pair, at
  the render's size and at the frames upscaled bilinearly to --megapixels
  (the first --timing-pairs pairs), on --cores cores;
- EPE: mean end-point error |w − w_true| in pixels; "EPE <10" the same where
  the true motion is under 10 px (the camera's motion, not the ball's);
  ">3 px": the share of pixels whose error is over 3 px;
- E: the warping error, the mean over those pixels and the channels of
  (V_t(x) − V_t+1(x + w(x)))² (bilinear), and E / E_true, the same for the
  true motion.

Candidates: core.motion.optical_flow (TV-L1 in NumPy and SciPy), a
pyramidal Lucas-Kanade in NumPy and SciPy written here, OpenCV's DIS flow
(three presets) and Farneback (opencv-python-headless), scikit-image's
optical_flow_tvl1 and optical_flow_ilk. A library that is not installed is
listed as skipped with the reason. Zero motion and the true motion are the
two reference rows.
Usage: python bench/flow.py FRAMES_DIR [--megapixels MP] [--timing-pairs N] [--cores N]
"""

from __future__ import annotations

import argparse
import math
import statistics
import time
from pathlib import Path
from typing import Callable, Dict, List, Tuple

import numpy as np
from scipy import ndimage
from threadpoolctl import threadpool_limits

from common import ROOT  # noqa: F401  (puts the repository on sys.path)
from core.colour import luminance
from core.files.frames import read_vector_pass
from core.files.reading import read_image
from core.motion import backward_motion, forward_motion, visible_in_both, warp_back, warping_error
from core.motion.optical_flow import optical_flow

Flow = Callable[[np.ndarray, np.ndarray], np.ndarray]
FAST_MOTION = 10.0
"""Pixels a frame: the "EPE <10" column keeps the pixels whose true motion is slower."""
OUTLIER = 3.0
"""End-point error in pixels above which a pixel counts in the ">3 px" column."""


def read_frame(path: Path) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(sRGB (H, W, 3) in [0, 1], forward motion (H, W, 2), backward motion (H, W, 2)) of one rendered frame."""
    vector = read_vector_pass(path)
    if vector is None:
        raise SystemExit("{} has no Vector pass: render the frames with sample_scenes/sequence_scene.py".format(path))
    return read_image(path), forward_motion(vector), backward_motion(vector)


def pyramidal_lucas_kanade(first: np.ndarray, second: np.ndarray, sigma: float = 3.0, warps: int = 3) -> np.ndarray:
    """A compact coarse-to-fine Lucas-Kanade (Gaussian window ``sigma`` px, ``warps`` warps a level), (H, W, 2)."""
    firsts, seconds = [luminance(first)], [luminance(second)]
    while min(firsts[-1].shape) >= 48:
        shape = tuple((n + 1) // 2 for n in firsts[-1].shape)
        for levels in (firsts, seconds):
            blurred = ndimage.gaussian_filter(levels[-1], 0.8, mode="nearest")
            levels.append(ndimage.zoom(blurred, np.divide(shape, blurred.shape), order=1, mode="nearest",
                                       grid_mode=True, output=np.float32))
    flow = np.zeros(firsts[-1].shape + (2,), np.float32)
    for a, b in zip(reversed(firsts), reversed(seconds), strict=True):
        if flow.shape[:2] != a.shape:
            scale = np.divide(a.shape, flow.shape[:2])
            flow = np.stack([ndimage.zoom(flow[..., c], scale, order=1, mode="nearest", grid_mode=True,
                                          output=np.float32) * np.float32(scale[1 - c]) for c in range(2)], axis=-1)
        for _ in range(warps):
            warped = warp_back(b, flow)[0]
            gy, gx = np.gradient((a + warped) * 0.5)
            dt = warped - a
            sxx, sxy, syy, sxt, syt = (ndimage.gaussian_filter(p, sigma) for p in
                                       (gx * gx, gx * gy, gy * gy, gx * dt, gy * dt))
            sxx += 1e-4
            syy += 1e-4
            det = sxx * syy - sxy * sxy
            flow[..., 0] += (sxy * syt - syy * sxt) / det
            flow[..., 1] += (sxy * sxt - sxx * syt) / det
    return flow


def gray8(image: np.ndarray) -> np.ndarray:
    """Luminance of an sRGB (H, W, 3) image as uint8 (H, W), as OpenCV's flows take it."""
    return np.clip(np.round(luminance(image) * 255), 0, 255).astype(np.uint8)


def opencv_candidates(cores: int) -> Dict[str, object]:
    """OpenCV's DIS presets and Farneback, or the reason they are skipped."""
    try:
        import cv2
    except ImportError as error:
        reason = "skipped: {} (pip install opencv-python-headless)".format(error)
        return {name: reason for name in ("OpenCV DIS ultrafast", "OpenCV DIS fast", "OpenCV DIS medium",
                                          "OpenCV Farneback")}
    cv2.setNumThreads(cores)
    out: Dict[str, object] = {}
    for preset in ("ULTRAFAST", "FAST", "MEDIUM"):
        dis = cv2.DISOpticalFlow_create(getattr(cv2, "DISOPTICAL_FLOW_PRESET_" + preset))
        out["OpenCV DIS " + preset.lower()] = lambda a, b, dis=dis: dis.calc(gray8(a), gray8(b), None)
    out["OpenCV Farneback"] = lambda a, b: cv2.calcOpticalFlowFarneback(gray8(a), gray8(b), None, 0.5, 5, 15, 3, 5,
                                                                        1.2, 0)
    return out


def scikit_image_candidates() -> Dict[str, object]:
    """scikit-image's TV-L1 and iterative Lucas-Kanade, or the reason they are skipped."""
    try:
        from skimage.registration import optical_flow_ilk, optical_flow_tvl1
    except ImportError as error:
        reason = "skipped: {} (pip install scikit-image)".format(error)
        return {"scikit-image TV-L1": reason, "scikit-image iLK": reason}

    def image_axes(method: Callable) -> Flow:
        def flow(a: np.ndarray, b: np.ndarray) -> np.ndarray:
            rows, columns = method(luminance(a), luminance(b))
            return np.stack([columns, rows], axis=-1).astype(np.float32)
        return flow
    return {"scikit-image TV-L1": image_axes(optical_flow_tvl1), "scikit-image iLK": image_axes(optical_flow_ilk)}


def candidates(cores: int) -> Dict[str, object]:
    """{name: flow function or the reason it is skipped}, the project's own first."""
    return {"core.motion TV-L1": optical_flow, "Lucas-Kanade (here)": pyramidal_lucas_kanade,
            **opencv_candidates(cores), **scikit_image_candidates()}


def upscaled(image: np.ndarray, megapixels: float) -> np.ndarray:
    """``image`` resampled bilinearly to about ``megapixels``, float32 in [0, 1]."""
    scale = math.sqrt(megapixels * 1e6 / (image.shape[0] * image.shape[1]))
    return np.clip(ndimage.zoom(image, (scale, scale, 1), order=1), 0.0, 1.0).astype(np.float32)


def megapixels_of(image: np.ndarray) -> float:
    """Pixels of (H, W, ...) ``image`` in millions."""
    return image.shape[0] * image.shape[1] / 1e6


def estimates(flow: Flow, pairs: List[Tuple[np.ndarray, np.ndarray]]) -> Tuple[List[np.ndarray], float]:
    """The motion ``flow`` finds for each (first, second) pair, and the median seconds of a pair per megapixel."""
    found, seconds = [], []
    for first, second in pairs:
        start = time.perf_counter()
        found.append(flow(first, second))
        seconds.append(time.perf_counter() - start)
    return found, statistics.median(seconds) / megapixels_of(pairs[0][0])


def scores(found: List[np.ndarray], pairs: List[dict]) -> Dict[str, float]:
    """EPE, EPE under FAST_MOTION, outlier share and warping error of the motions ``found``, over ``pairs``."""
    rows = []
    for estimate, pair in zip(found, pairs, strict=True):
        mask, truth = pair["mask"], pair["truth"]
        error = np.hypot(*(estimate - truth).transpose(2, 0, 1))
        slow = mask & (np.hypot(*truth.transpose(2, 0, 1)) < FAST_MOTION)
        rows.append((error[mask].mean(), error[slow].mean(), (error[mask] > OUTLIER).mean(),
                     warping_error(pair["first"], pair["second"], estimate, mask)))
    epe, epe_slow, outliers, warp = np.mean(rows, axis=0)
    return {"epe": epe, "epe_slow": epe_slow, "outliers": outliers, "warp": warp}


def load_pairs(folder: Path) -> List[dict]:
    """Consecutive frame pairs of the render in ``folder``: images, true forward motion and scored pixels."""
    paths = sorted(folder.glob("*.exr"))
    if len(paths) < 2:
        raise SystemExit("{} holds fewer than two EXR frames".format(folder))
    frames = [read_frame(path) for path in paths]
    return [{"first": a[0], "second": b[0], "truth": a[1], "mask": visible_in_both(a[1], b[2])}
            for a, b in zip(frames[:-1], frames[1:], strict=True)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("frames", type=Path, help="folder of frame_####.exr with the Vector pass "
                                                  "(sample_scenes/sequence_scene.py -o FOLDER)")
    parser.add_argument("--megapixels", type=float, default=1.0, help="size of the upscaled timing (default 1)")
    parser.add_argument("--timing-pairs", type=int, default=3, help="pairs timed at --megapixels (default 3)")
    parser.add_argument("--cores", type=int, default=1, help="threads OpenCV and BLAS may use (default 1)")
    args = parser.parse_args()
    pairs = load_pairs(args.frames)
    h, w = pairs[0]["first"].shape[:2]
    big = [(upscaled(p["first"], args.megapixels), upscaled(p["second"], args.megapixels))
           for p in pairs[:args.timing_pairs]]
    print("{} pairs of {} x {} px, {:.1%} of the pixels scored; timing also at {} x {} px; {} core(s)".format(
        len(pairs), w, h, np.mean([p["mask"].mean() for p in pairs]), big[0][0].shape[1], big[0][0].shape[0],
        args.cores))
    true_warp = scores([p["truth"] for p in pairs], pairs)["warp"]
    header = "{:24} {:>9} {:>9} {:>7} {:>8} {:>7} {:>9} {:>8}".format(
        "candidate", "s/MP", "s/MP 1MP", "EPE px", "EPE <10", ">3 px", "E", "E/E_true")
    print(header)
    print("-" * len(header))
    row = "{:24} {:>9} {:>9} {:7.2f} {:8.2f} {:6.1%} {:9.2e} {:8.2f}"
    zero = scores([np.zeros(p["truth"].shape, np.float32) for p in pairs], pairs)
    print(row.format("zero motion", "", "", zero["epe"], zero["epe_slow"], zero["outliers"], zero["warp"],
                     zero["warp"] / true_warp))
    print(row.format("true motion (Vector)", "", "", 0.0, 0.0, 0.0, true_warp, 1.0))
    with threadpool_limits(args.cores):
        for name, flow in candidates(args.cores).items():
            if isinstance(flow, str):
                print("{:24} {}".format(name, flow))
                continue
            found, native = estimates(flow, [(p["first"], p["second"]) for p in pairs])
            upscale = estimates(flow, big)[1]
            s = scores(found, pairs)
            print(row.format(name, "{:.3f}".format(native), "{:.3f}".format(upscale), s["epe"], s["epe_slow"],
                             s["outliers"], s["warp"], s["warp"] / true_warp), flush=True)


if __name__ == "__main__":
    main()
