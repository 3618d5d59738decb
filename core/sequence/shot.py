"""Painting a whole shot into one folder, frame after frame, every frame committed whole, resumable (ALGORITHM §9).

``paint_sequence`` reads each frame, takes the motion from the frame before
(Blender's Vector pass when every frame has one, else optical flow), paints
it (``frame_step``) and commits the frame's maps, the sequence's report and
the state the next frame needs all together (``staging``); the strokes' lives
are appended to one file whose committed length the state records. A run
stopped anywhere leaves complete frames only, and the same command resumes
after the last of them with the same bytes as a run never stopped.

How a run knows the frames in a folder are its own: report.json records the
sequence's fingerprint (the SHA-256 of the painter's version, the parameters,
seed included, the fade and normal-map settings and the motion's source) and
every committed frame's number, file name and SHA-256 of its input file. A
run resumes only when the fingerprint is its own and each frame already
painted is the same frame of the same input; otherwise it refuses with one
sentence and touches nothing.
"""

from __future__ import annotations

import hashlib
import json
import time
from pathlib import Path
from typing import Dict, List, Optional

import numpy as np

from ..errors import Cancelled, OutputError, ParameterError
from ..files import reading
from ..files.export import file_digests, map_attributes, map_tasks, run_all, write_normal_map
from ..files.frames import Frames, carry_vector_passes, read_vector_pass
from ..files.lives import LIVES_FILE, append_frame
from ..files.staging import output_folder
from ..files.writing import write_json
from ..measures.metrics import psnr
from ..motion import comes_back, motion_boundary, motion_pair, optical_flow, still_pixels, stillness, warping_error
from ..motion.optical_flow import SEQUENCE_MEGAPIXELS
from ..params import Params, SequenceSettings, scaled_sizes
from ..progress import CancelFn, ProgressFn, Stage
from ..version import __version__
from .frame_step import FrameMotion, PaintedFrame, first_frame, frame_tips, laid, next_frame, unchanged
from .state import STATE_FILE, load_state, save_state

REPORT_FILE = "report.json"
VECTOR_PASS_MOTION = "vector pass"
OPTICAL_FLOW_MOTION = "optical flow"


def frame_names(number: int, normal_map: bool) -> List[str]:
    """The files of frame ``number``: painting_0016.png, color_0016.exr, height, opacity, orientation (and
    normal_0016.exr), as Blender numbers an image sequence (at least 4 digits)."""
    suffix = frame_suffix(number)
    names = [f"painting{suffix}.png", f"color{suffix}.exr", f"height{suffix}.exr", f"opacity{suffix}.exr",
             f"orientation{suffix}.exr"]
    return names + ([f"normal{suffix}.exr"] if normal_map else [])


def frame_suffix(number: int) -> str:
    """"_0016" for frame 16: the frame number zero-padded to 4 digits (more when it needs them)."""
    return f"_{number:04d}"


def fingerprint(params: Params, settings: SequenceSettings, motion: str) -> str:
    """The SHA-256 (hex) of what makes a sequence's frames: the version, the parameters, the settings, the motion."""
    text = json.dumps({"version": __version__, "params": params.to_dict(), "fade_frames": settings.fade_frames,
                       "normal_map": settings.normal_map, "motion": motion}, sort_keys=True)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def input_digest(path: Path) -> str:
    """The SHA-256 (hex) of a frame's input file."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def paint_sequence(frames: Frames, output_dir, params: Params, settings: Optional[SequenceSettings] = None,
                   progress: ProgressFn = None, cancel: CancelFn = None) -> dict:
    """Paint ``frames`` into ``output_dir`` (module docstring) with ``settings`` (default ``SequenceSettings()``);
    return the sequence's report.

    Refusals (one sentence, the folder untouched): parameters out of range or a layout other than the paper's;
    frames of which only some carry a Vector pass; a folder holding another sequence's frames or a still
    painting. progress(fraction, message) reports the frame and the work within it; cancel() stops between
    stages (complete frames stay).
    """
    settings = settings or SequenceSettings()
    params.validate()
    settings.validate()
    if params.layout != "paper":
        raise ParameterError(f"A sequence is painted with the paper's layout; the layout {params.layout} paints "
                             f"still images only.")
    motion = VECTOR_PASS_MOTION if carry_vector_passes(frames.paths) else OPTICAL_FLOW_MOTION
    run = Run(frames, params, settings, motion, fingerprint(params, settings, motion))
    with output_folder(output_dir) as folder:
        report = run.resumed_report(folder.folder)
        folder.check_names([name for number in frames.numbers for name in frame_names(number, settings.normal_map)]
                           + [REPORT_FILE, STATE_FILE])
        done = len(report["per_frame"])
        if done < len(frames.paths):
            try:
                run.paint_from(done, report, folder, progress, cancel)
            except Cancelled:
                raise Cancelled(f"The run was cancelled; the frames in {output_dir} are complete, and painting the "
                                f"sequence again goes on after the last of them.") from None
    report["output_dir"] = str(Path(output_dir).resolve())
    return report


class Run:
    """One run of ``paint_sequence``: its frames, settings and the report it keeps up to date."""

    def __init__(self, frames: Frames, params: Params, settings: SequenceSettings, motion: str, key: str):
        self.frames, self.params, self.settings, self.motion, self.key = frames, params, settings, motion, key

    def resumed_report(self, folder: Path) -> dict:
        """The report of the frames already committed in ``folder`` when they are this run's (a new report when
        it holds none); OutputError naming the folder when it holds another sequence's frames or a still."""
        path = folder / REPORT_FILE
        if not path.exists():
            return self.new_report()
        try:
            report = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise OutputError(f"The output folder {folder} holds a report.json that cannot be read ({exc}); "
                              f"paint into another folder.") from exc
        if "sequence" not in report:
            raise OutputError(f"The output folder {folder} holds a still painting; paint the sequence into "
                              f"another folder.")
        if report["sequence"] != self.key:
            raise OutputError(f"The output folder {folder} holds frames painted with other settings (parameters, "
                              f"seed, fade or motion); paint into another folder, or repeat that run's command to "
                              f"go on with it.")
        for i, entry in enumerate(report["per_frame"][:len(self.frames.paths)]):
            path, number = self.frames.paths[i], self.frames.numbers[i]
            if entry["frame"] != number or entry["input_sha256"] != input_digest(path):
                raise OutputError(f"The output folder {folder} holds frame {entry['frame']} painted from another "
                                  f"input than {path}; paint into another folder.")
        return report

    def new_report(self) -> dict:
        """The report of a sequence with no frame painted yet."""
        return {"version": __version__, "sequence": self.key, "input": [str(p) for p in self.frames.paths],
                "frame_count": len(self.frames.paths), "width": self.frames.width, "height": self.frames.height,
                "motion": self.motion, "fade_frames": self.settings.fade_frames, "params": self.params.to_dict(),
                "frames": [], "per_frame": [], "lives": {"file": LIVES_FILE, "bytes": 0}, "complete": False}

    def paint_from(self, start: int, report: dict, folder, progress: ProgressFn, cancel: CancelFn) -> None:
        """Paint frames ``start`` .. the last, committing each, ``report`` kept up to date."""
        paths, numbers = self.frames.paths, self.frames.numbers
        count = len(paths)
        previous = image = vectors = None
        if start > 0:
            saved = load_state(folder.folder / STATE_FILE)
            image = reading.read_image(paths[start - 1], self.params.max_megapixels, self.params.canvas_colour)
            vectors = read_vector_pass(paths[start - 1]) if self.motion == VECTOR_PASS_MOTION else None
            shape = image.shape[:2]
            tips = frame_tips(self.params, scaled_sizes(self.params, *shape))
            previous = saved.frame._replace(canvas=laid(saved.frame.living, tips, self.params, shape))
        for index in range(start, count):
            stage = Stage(frame_progress(progress, numbers[index], index, count), cancel, index / count,
                          (index + 1) / count)
            seconds: Dict[str, float] = {}
            clock = time.perf_counter()
            next_image = reading.read_image(paths[index], self.params.max_megapixels, self.params.canvas_colour)
            next_vectors = read_vector_pass(paths[index]) if self.motion == VECTOR_PASS_MOTION else None
            seconds["reading"] = time.perf_counter() - clock
            stage.report(0.0, "motion" if index else "painting")
            if index == 0:
                painted = first_frame(next_image, self.params, self.settings.fade_frames, stage)
                measures = {}
            else:
                clock = time.perf_counter()
                motion = frame_motion(image, next_image, vectors, next_vectors)
                seconds["motion"] = time.perf_counter() - clock
                if unchanged(previous, image, next_image, motion):
                    painted = previous._replace(born=0, died=0, seconds={})
                else:
                    painted = next_frame(previous, index, next_image, motion, self.params, stage)
                clock = time.perf_counter()
                measures = pair_measures(image, next_image, previous.canvas, painted.canvas, motion)
                seconds["measures"] = time.perf_counter() - clock
            seconds.update(painted.seconds)
            self.commit(folder, index, painted, next_image, measures, seconds, report)
            previous, image, vectors = painted, next_image, next_vectors

    def commit(self, folder, index: int, painted: PaintedFrame, image: np.ndarray, measures: dict,
               seconds: Dict[str, float], report: dict) -> None:
        """Append frame ``index``'s strokes to the lives file and commit its maps, the report and the state."""
        clock = time.perf_counter()
        number, path = self.frames.numbers[index], self.frames.paths[index]
        strokes = painted.living.strokes
        lives_bytes = append_frame(folder.folder / LIVES_FILE, number, painted.living.ident, strokes.control,
                                   strokes.control_count, report["lives"]["bytes"])
        canvas = painted.canvas
        attributes = dict(map_attributes(self.params), **{"paint_relief:frame": str(number)})
        entry = {"frame": number, "input": path.name, "input_sha256": input_digest(path),
                 "alive": len(painted.living), "born": painted.born, "died": painted.died,
                 "dying": int(np.count_nonzero(painted.living.dying)), "psnr": round(psnr(canvas.colour, image), 4),
                 "height_range": [float(np.min(canvas.height)), float(np.max(canvas.height))], **measures}
        with folder.staged() as staging:
            names = frame_names(number, self.settings.normal_map)
            run_all(map_tasks(staging, frame_suffix(number), canvas.colour, canvas.height, canvas.opacity,
                              painted.orientation, attributes))
            files = file_digests(staging, names[:5])
            if self.settings.normal_map:
                write_normal_map(staging / names[5], canvas.height, attributes, files[names[2]]["sha256"])
            save_state(staging / STATE_FILE, painted, index, lives_bytes)
            seconds["writing"] = time.perf_counter() - clock
            entry["seconds"] = {name: round(value, 4) for name, value in seconds.items()}
            entry["files"] = files
            report["per_frame"].append(entry)
            report["frames"].append(number)
            report["lives"]["bytes"] = lives_bytes
            report.update(sequence_figures(report["per_frame"], len(self.frames.paths)))
            write_json(staging / REPORT_FILE, report)


def frame_progress(progress: ProgressFn, number: int, index: int, count: int) -> ProgressFn:
    """A progress callback that names the frame: "Frame 16 (3/12): <message>"."""
    if progress is None:
        return None
    return lambda fraction, message: progress(fraction, f"Frame {number} ({index + 1}/{count}): {message}")


def frame_motion(image: np.ndarray, next_image: np.ndarray, vectors: Optional[np.ndarray],
                 next_vectors: Optional[np.ndarray]) -> FrameMotion:
    """The motion between two frames: from their Vector passes (``vectors``, ``next_vectors``) when they have them,
    else optical flow both ways (none between equal frames); with which pixels of each are visible in both."""
    if vectors is not None:
        forward, backward = motion_pair(vectors, next_vectors)
    elif np.array_equal(image, next_image):
        forward = backward = np.zeros(image.shape[:2] + (2,), np.float32)
    else:
        forward = optical_flow(image, next_image, SEQUENCE_MEGAPIXELS)
        backward = optical_flow(next_image, image, SEQUENCE_MEGAPIXELS)
    kept = comes_back(forward, backward)
    return FrameMotion(forward, backward, kept & ~motion_boundary(forward), kept, comes_back(backward, forward))


def pair_measures(image: np.ndarray, next_image: np.ndarray, shown, next_shown, motion: FrameMotion) -> dict:
    """The steadiness of a pair of frames (ALGORITHM §9, "Measures"), with the painter's own motion: the warping
    error of the footage, of the painting's colour and of its raw height (normalised over the sequence by
    ``sequence_figures``), and the mean change where the footage stands still, of the footage and the painting."""
    still = still_pixels(motion.forward, motion.backward) & motion.visible
    return {"warping_error": {
        "footage": warping_error(image, next_image, motion.forward, motion.visible),
        "painting": warping_error(shown.colour, next_shown.colour, motion.forward, motion.visible),
        "height_raw": warping_error(shown.height, next_shown.height, motion.forward, motion.visible)},
        "still_pixels": int(np.count_nonzero(still)),
        "stillness": {"footage": stillness(image, next_image, still),
                      "painting": stillness(shown.colour, next_shown.colour, still)}}


def sequence_figures(per_frame: List[dict], frame_count: int) -> dict:
    """The sequence's figures from its frames' entries: stroke counts, seconds per stage, mean PSNR, the warping
    errors (the height's normalised to [0, 1] over the frames painted: divided by their height range squared) and
    their ratios to the footage's, and the stillness of the painting against the footage's."""
    pairs = [entry for entry in per_frame if "warping_error" in entry]
    low = min(entry["height_range"][0] for entry in per_frame)
    high = max(entry["height_range"][1] for entry in per_frame)
    mean = lambda values: float(np.nanmean(values)) if len(values) else float("nan")  # noqa: E731
    footage = mean([p["warping_error"]["footage"] for p in pairs])
    painting = mean([p["warping_error"]["painting"] for p in pairs])
    height = mean([p["warping_error"]["height_raw"] for p in pairs]) / max(high - low, 1e-12) ** 2
    still = [p for p in pairs if p["still_pixels"]]
    still_footage = mean([p["stillness"]["footage"] for p in still])
    still_painting = mean([p["stillness"]["painting"] for p in still])
    seconds: Dict[str, float] = {}
    for entry in per_frame:
        for name, value in entry["seconds"].items():
            seconds[name] = round(seconds.get(name, 0.0) + value, 4)
    return {"complete": len(per_frame) >= frame_count,
            "strokes": {"alive": [e["alive"] for e in per_frame], "born": [e["born"] for e in per_frame],
                        "died": [e["died"] for e in per_frame]},
            "seconds": seconds, "psnr": mean([e["psnr"] for e in per_frame]),
            "warping_error": {"footage": footage, "painting": painting, "height": height,
                              "painting_ratio": painting / footage if footage else float("nan")},
            "stillness": {"footage": still_footage, "painting": still_painting,
                          "ratio": still_painting / still_footage if still_footage else float("nan")}}
