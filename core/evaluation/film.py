"""The relit painted film against the paper's 2-D lighting in time: how steady each is from frame to frame.

A painted sequence (``python -m core sequence``) is lit two ways: Blender
renders its animated canvas under one fixed raking light (``relit``, the
extension's ``animate`` command writes ``relit/NNNN.png``), and the paper's
Eq. 6-7 lights each frame in 2-D (``paper``, written here as
``paper/NNNN.png``). Both films, the footage and the unlit painting are
brought to the relit film's size (area averaging, in sRGB) and measured with
the warping error (``core.motion.warping_error``, Lai et al. 2018) under the
painter's own motion (``core.motion.source.two_way_motion``): Blender's
Vector pass of the footage when it has one, else optical flow as the painter
computes it, scaled to the film's size; only pixels visible in both frames count.

Frames are float32 (h, w, 3) sRGB in [0, 1]; motions float32 (h, w, 2) in
film pixels, x right, y down. ``run_film`` writes paper/, side_by_side/
(footage | relit | paper, one PNG a frame), animation.gif, animation.json
and animation.md.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Dict, List, Optional, Sequence

import numpy as np

from ..colour import linear_to_srgb
from ..errors import InputError
from ..figures.gif import write_gif
from ..figures.sheet import contact_sheet
from ..files import reading, shot_files, writing
from ..files.frames import read_vector_pass
from ..lighting import paper_lighting
from ..motion import mean_over_pairs, visible_in_both, warping_error
from ..motion.source import VECTOR_PASS_MOTION, two_way_motion
from ..progress import ProgressFn, Stage
from ..resample import resize_area
from .film_files import frame_file

FILMS = ("footage", "relit", "paper", "painting")
"""The films measured: the footage, the Cycles renders, the paper's 2-D lighting, the unlit painting."""
GIF_SECONDS_PER_FRAME = 0.1
"""The side-by-side GIF plays at 10 frames a second."""


def resize_motion(motion: np.ndarray, width: int, height: int) -> np.ndarray:
    """A (H, W, 2) motion in px resampled to (height, width, 2) and measured in the new size's pixels."""
    h, w = motion.shape[:2]
    scaled = resize_area(motion, width, height)
    scaled[..., 0] *= np.float32(width / w)
    scaled[..., 1] *= np.float32(height / h)
    return scaled


def read_sequence_report(painted_dir: Path) -> dict:
    """The sequence report of a painted folder; InputError (one sentence) when it holds no painted sequence."""
    try:
        report = shot_files.read_report(painted_dir)
    except (OSError, ValueError):
        report = None
    if report is None or not shot_files.is_shot_report(report) or not report.get("frames"):
        raise InputError(f"The folder {painted_dir} holds no painted sequence (a report.json listing painted "
                         f"frames); paint the footage with `python -m core sequence` first.")
    return report


def footage_paths(report: dict, painted_dir: Path) -> List[Path]:
    """The footage frame of each painted frame, from the report; InputError naming the first one missing."""
    inputs = [Path(p) for p in report["input"]][:len(report["frames"])]
    for path in inputs:
        if not path.is_file():
            raise InputError(f"The footage frame {path} that {painted_dir} was painted from is gone; the warping "
                             f"errors are measured against the footage.")
    return inputs


def painted_maps(painted_dir: Path, number: int) -> Dict[str, np.ndarray]:
    """Frame ``number``'s maps: colour (H, W, 3) sRGB [0, 1], height (H, W) and orientation (H, W) radians."""
    def read(name):
        return reading.read_exr(Path(painted_dir) / shot_files.numbered_name(name, number))[0]

    return {"srgb": linear_to_srgb(read("color.exr")[..., :3]), "height": read("height.exr")[..., 0],
            "orientation": read("orientation.exr")[..., 0]}


def read_relit(relit_dir: Path, number: int, size: Optional[tuple] = None) -> np.ndarray:
    """The relit film's frame ``number`` (h, w, 3) sRGB; InputError when missing or not of ``size`` (w, h)."""
    path = Path(relit_dir) / frame_file(number)
    if not path.is_file():
        raise InputError(f"The relit frame {path} is missing: render every frame of the film first.")
    image = reading.read_image(path)
    if size is not None and (image.shape[1], image.shape[0]) != tuple(size):
        raise InputError(f"The relit frame {path} is {image.shape[1]} x {image.shape[0]} px, but the film's first "
                         f"frame is {size[0]} x {size[1]} px.")
    return image


class FootageMotion:
    """The painter's motion between footage frames, at the film's size (``pair``), read frame by frame."""

    def __init__(self, paths: Sequence[Path], kind: str, size: tuple, max_megapixels: float):
        self.paths, self.kind, self.size, self.max_megapixels = list(paths), kind, size, max_megapixels
        self._cached: Dict[int, object] = {}

    def _frame(self, index: int):
        """Frame ``index``'s Vector pass (vector pass motion) or its full-size sRGB picture (optical flow)."""
        if index not in self._cached:
            self._cached = {k: v for k, v in self._cached.items() if k >= index - 1}
            if self.kind == VECTOR_PASS_MOTION:
                data = read_vector_pass(self.paths[index])
                if data is None:
                    raise InputError(f"The footage frame {self.paths[index]} has no Vector pass, but the painter "
                                     f"took its motion from one.")
            else:
                data = reading.read_image(self.paths[index], self.max_megapixels)
            self._cached[index] = data
        return self._cached[index]

    def pair(self, index: int) -> tuple:
        """(forward, backward, visible) between frames ``index`` and ``index`` + 1 at the film's size."""
        forward, backward = two_way_motion(self._frame(index), self._frame(index + 1), self.kind)
        width, height = self.size
        forward, backward = resize_motion(forward, width, height), resize_motion(backward, width, height)
        return forward, backward, visible_in_both(forward, backward)


class SheetFrames:
    """The side-by-side PNGs as a sequence of (H, W, 3) frames read when asked (for ``write_gif``)."""

    def __init__(self, paths: Sequence[Path]):
        self.paths = list(paths)

    def __len__(self) -> int:
        return len(self.paths)

    def __getitem__(self, index: int) -> np.ndarray:
        return reading.read_image(self.paths[index])

    def __iter__(self):
        return (self[i] for i in range(len(self)))


def side_by_side(number: int, footage: np.ndarray, relit: np.ndarray, paper: np.ndarray, azimuth_deg: float) -> np.ndarray:
    """One frame of the side-by-side film: footage | Cycles relief | paper lighting, labelled; (H, W, 3)."""
    return contact_sheet([(f"Footage, frame {number}", footage),
                          (f"Cycles relief, light at {azimuth_deg:g} deg", relit),
                          ("Paper 2-D lighting (Eq. 6-7)", paper)],
                         panel_height=footage.shape[0], columns=3)


def film_statistics(errors: Dict[str, List[float]], pairs: List[int]) -> dict:
    """The warping errors of every film: per pair of frames (named by its first frame) with their ratio to the
    footage's, the mean over the pairs and its ratio to the footage's mean."""
    footage = errors["footage"]
    footage_mean = mean_over_pairs(footage)
    statistics = {}
    for film in FILMS:
        mean = mean_over_pairs(errors[film])
        entry = {"mean": mean, "per_frame": [
            {"frame": frame, "error": value, **({} if film == "footage" else
                                                 {"ratio": value / footage[i] if footage[i] else float("nan")})}
            for i, (frame, value) in enumerate(zip(pairs, errors[film], strict=True))]}
        if film != "footage":
            entry["ratio"] = mean / footage_mean if footage_mean else float("nan")
        statistics[film] = entry
    return statistics


def run_film(painted_dir, relit_dir, out_dir, azimuth_deg: float, elevation_deg: float,
                  render: Optional[dict] = None, progress: ProgressFn = None) -> dict:
    """Light the painted sequence in 2-D, measure it against the relit film and the footage; write the files.

    painted_dir: a folder painted by ``python -m core sequence``; relit_dir:
    ``NNNN.png`` for every painted frame N, all of one size (the film's
    size); azimuth_deg and elevation_deg: the relit film's light (the
    painter's convention: degrees from the image's right edge towards its
    bottom); render: what the renderer reports of itself (samples, seconds
    per frame, ...), recorded as given. Writes into ``out_dir``:
    paper/NNNN.png, side_by_side/NNNN.png, animation.gif, animation.json and
    animation.md; returns the JSON dictionary. InputError (one sentence) for a
    folder holding no painted sequence, footage that is gone, or a relit frame
    missing or of another size.
    """
    clock = time.perf_counter()
    stage = Stage(progress, None)
    painted_dir, relit_dir, out = Path(painted_dir), Path(relit_dir), Path(writing.ensure_output_dir(out_dir))
    report = read_sequence_report(painted_dir)
    frames = [int(n) for n in report["frames"]]
    paths = footage_paths(report, painted_dir)
    first_relit = read_relit(relit_dir, frames[0])
    size = (first_relit.shape[1], first_relit.shape[0])
    motion = FootageMotion(paths, report.get("motion", ""), size, report.get("params", {}).get("max_megapixels", 50.0))
    for folder in ("paper", "side_by_side"):
        (out / folder).mkdir(exist_ok=True)
    errors: Dict[str, List[float]] = {film: [] for film in FILMS}
    previous: Optional[Dict[str, np.ndarray]] = None
    paper_seconds = 0.0
    for index, number in enumerate(frames):
        stage.report(index / len(frames), f"Frame {number} ({index + 1}/{len(frames)}): paper lighting and measures")
        maps = painted_maps(painted_dir, number)
        start = time.perf_counter()
        paper = resize_area(paper_lighting(maps["srgb"], maps["height"], maps["orientation"]), *size)
        paper_seconds += time.perf_counter() - start
        films = {"footage": resize_area(reading.read_image(paths[index]), *size),
                 "relit": first_relit if index == 0 else read_relit(relit_dir, number, size),
                 "paper": np.clip(paper, 0.0, 1.0), "painting": resize_area(maps["srgb"], *size)}
        writing.write_png(out / "paper" / frame_file(number), films["paper"])
        writing.write_png(out / "side_by_side" / frame_file(number),
                          side_by_side(number, films["footage"], films["relit"], films["paper"], azimuth_deg))
        if previous is not None:
            forward, _, visible = motion.pair(index - 1)
            for film in FILMS:
                errors[film].append(warping_error(previous[film], films[film], forward, visible))
        previous = films
    stage.report(0.95, "Writing the side-by-side GIF")
    write_gif(out / "animation.gif", SheetFrames([out / "side_by_side" / frame_file(n) for n in frames]),
              seconds_per_frame=GIF_SECONDS_PER_FRAME)
    result = {"painted_dir": str(painted_dir.resolve()), "frames": frames, "film_size": list(size),
              "painted_size": [int(report["width"]), int(report["height"])], "motion": report.get("motion"),
              "light": {"azimuth_deg": float(azimuth_deg), "elevation_deg": float(elevation_deg)},
              "warping_error": film_statistics(errors, frames[:-1]),
              "painter_warping_error": report.get("warping_error"),
              "render": dict(render or {}),
              "seconds": {"paper_per_frame": round(paper_seconds / len(frames), 4),
                          "measures": round(time.perf_counter() - clock, 3)}}
    writing.write_json(out / "animation.json", result)
    writing.write_text(out / "animation.md", markdown(result))
    stage.report(1.0, "Animation figures written")
    return result


def _ratio_words(ratio: float) -> str:
    return f"{ratio:.2f} times the footage's" if np.isfinite(ratio) else "not comparable with the footage's"


def markdown(result: dict) -> str:
    """animation.md: the warping errors per frame as a table and one paragraph reading them."""
    statistics = result["warping_error"]
    light = result["light"]
    render = result.get("render", {})
    width, height = result["film_size"]
    lines = ["# The relit painted film", "",
             f"{len(result['frames'])} frames ({result['frames'][0]} to {result['frames'][-1]}) at {width} x {height} "
             f"px, painted at {result['painted_size'][0]} x {result['painted_size'][1]} px. Warping error (mean "
             f"squared difference of a frame and the next warped back by the painter's motion, {result['motion']}, "
             "over the pixels visible in both; sRGB in [0, 1]) from each frame to the next:", "",
             "| frame | footage | relit (Cycles) | paper (Eq. 6-7) | unlit painting |", "| ---: | ---: | ---: | ---: | ---: |"]
    for i, entry in enumerate(statistics["footage"]["per_frame"]):
        lines.append(f"| {entry['frame']} | " + " | ".join(
            f"{statistics[film]['per_frame'][i]['error']:.5f}" for film in FILMS) + " |")
    lines.append("| mean | " + " | ".join(f"{statistics[film]['mean']:.5f}" for film in FILMS) + " |")
    relit, paper, painting = statistics["relit"], statistics["paper"], statistics["painting"]
    seconds = render.get("seconds_per_frame")
    timing = (f" Cycles rendered a frame in {seconds:.1f} s ({render.get('samples', '?')} samples)."
              if isinstance(seconds, (int, float)) else "")
    if paper["mean"] > relit["mean"]:
        reading_ = ("The paper's lighting changes more from one frame to the next than the relit relief does: its "
                    "light turns with every stroke, so a stroke that turns, is born or fades changes its shading "
                    "with it, while a fixed light on the relief changes only where the paint itself changes.")
    else:
        reading_ = ("Here the relit relief changes as much or more from one frame to the next than the paper's "
                    "lighting: what moves under a fixed light (shadows and highlights of the ridges as the paint "
                    "moves, and the render's noise, which stays in place while the picture moves) weighs more "
                    "than the paper's turning light.")
    lines += ["", f"Under one raking light (azimuth {light['azimuth_deg']:g} degrees, elevation "
              f"{light['elevation_deg']:g} degrees), the relit film's warping error is {relit['mean']:.5f}, "
              f"{_ratio_words(relit['ratio'])} ({statistics['footage']['mean']:.5f}); the paper's 2-D lighting gives "
              f"{paper['mean']:.5f}, {_ratio_words(paper['ratio'])}, and the unlit painting {painting['mean']:.5f} "
              f"({_ratio_words(painting['ratio'])}). {reading_}{timing}", ""]
    return "\n".join(lines)
