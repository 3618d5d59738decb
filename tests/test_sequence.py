"""Strokes that live across frames (ALGORITHM §9): carry, birth, stillness, resume and refusals of ``core sequence``.

Frames are made here with a known motion: a photograph moved by a sub-pixel
translation (every pixel of frame t+1 is frame t's from d px away, sampled
from the larger photograph, so what enters at the border is real content),
a still clip (one picture repeated) and a square entering a still
background. The painter is given the true motion where the test is about
what strokes do with it, and finds it itself (optical flow) where the test
is about the command.
"""

import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import held_run
import numpy as np
import pytest
from oracles import folder_bytes, one_sentence_run, same_bytes

from core.api import paint_sequence_files
from core.errors import Cancelled
from core.files.frames import find_frames
from core.files.reading import read_exr, read_image
from core.files.shot_files import read_report
from core.files.writing import write_png
from core.motion import comes_back, visible_in_both
from core.motion.warp import bilinear, pixel_positions
from core.params import Params, SequenceSettings
from core.progress import Stage
from core.sequence.frame_step import (
    FrameMotion,
    analyse_frame,
    carried_frame,
    first_frame,
    joined_rows,
    next_frame,
    settled_rows,
    shown_canvas,
    unchanged,
)
from core.sequence.pieces import LifeStep, judging_bands, row_bands
from core.sequence.shot import paint_sequence
from core.sequence.shot_folder import ShotFolder
from core.strokes.stroke_list import PAINTING_BRUSH, reaching_rows

ROOT = Path(__file__).resolve().parents[1]
PHOTO = ROOT / "sample_scenes" / "chelsea.png"
NO_STAGE = Stage(None, None)


def moved_photo(shape: tuple, offset: tuple) -> np.ndarray:
    """An (H, W) = ``shape`` window of the sample photograph whose pixel x shows the photograph at x + ``offset``
    (x, y) px, sampled bilinearly: the window moved by -offset."""
    photo = read_image(PHOTO)
    h, w = shape
    return np.clip(bilinear(photo, pixel_positions(h, w) + np.float32(offset) + np.float32([120, 60])), 0, 1)


def uniform_motion(shape: tuple, step: tuple) -> FrameMotion:
    """Every pixel moves by ``step`` (x, y) px from frame t to t+1; visibility from where they land."""
    h, w = shape
    forward = np.broadcast_to(np.float32(step), (h, w, 2)).copy()
    positions = pixel_positions(h, w)
    seen = lambda motion: np.all((positions + motion >= 0) & (positions + motion <= [w - 1, h - 1]), axis=-1)  # noqa: E731
    return FrameMotion(forward, -forward, seen(forward), seen(forward), seen(-forward))


def test_a_translated_photo_carries_its_strokes_and_is_born_on_only_where_new_content_enters():
    shape, step = (150, 200), (1.3, 0.6)
    params = Params(seed=3)
    first = first_frame(moved_photo(shape, (0, 0)), params, 3, NO_STAGE)
    second = next_frame(first, 1, moved_photo(shape, (-step[0], -step[1])), uniform_motion(shape, step), params,
                        NO_STAGE)
    before = dict(zip(first.living.ident.tolist(), first.living.strokes.anchor, strict=True))
    carried = second.living.birth == 0
    assert carried.sum() > 0.9 * len(first.living)
    moved = second.living.strokes.anchor[carried]
    expected = np.array([before[i] for i in second.living.ident[carried].tolist()]) + step
    assert np.max(np.abs(moved - expected)) < 0.5
    born = second.living.strokes.anchor[~carried]
    near_entry = (born[:, 0] < 2 * step[0] + 1) | (born[:, 1] < 2 * step[1] + 1)
    near_exit = (born[:, 0] > shape[1] - 1 - max(params.stroke_sizes)) | (born[:, 1] > shape[0] - 1 - max(params.stroke_sizes))
    assert np.all(near_entry | near_exit), born[~(near_entry | near_exit)]


def test_a_still_clip_paints_every_frame_as_the_first(tmp_path):
    picture = moved_photo((90, 120), (0, 0))
    (tmp_path / "in").mkdir()
    for number in (1, 2, 3):
        write_png(tmp_path / f"in/frame_{number:04d}.png", picture, bits=16)
    frames = find_frames([str(tmp_path / "in")])
    report = paint_sequence(frames, tmp_path / "out", Params(seed=2))
    assert report["motion"] == "optical flow" and report["complete"]
    assert [entry["born"] for entry in report["per_frame"][1:]] == [0, 0]
    for name in ("color", "height", "opacity"):
        first = read_exr(tmp_path / f"out/{name}_0001.exr")[0]
        for number in (2, 3):
            assert read_exr(tmp_path / f"out/{name}_{number:04d}.exr")[0].tobytes() == first.tobytes(), name
    pngs = [(tmp_path / f"out/painting_{n:04d}.png").read_bytes() for n in (1, 2, 3)]
    assert pngs[0] == pngs[1] == pngs[2]


def test_next_frame_of_a_still_frame_is_the_frame_before_so_a_still_stretch_is_painted_once():
    picture = moved_photo((90, 120), (0, 0))
    params = Params(seed=2)
    first = first_frame(picture, params, 3, NO_STAGE)
    still = uniform_motion(picture.shape[:2], (0.0, 0.0))
    assert unchanged(first, still._replace(same_picture=True))
    second = next_frame(first, 1, picture, still, params, NO_STAGE)
    assert second.born == 0 and second.died == 0
    shown, shown_before = (shown_canvas(frame, params, picture.shape[:2]) for frame in (second, first))
    for name in ("colour", "height", "opacity", "coverage"):
        assert getattr(shown, name).tobytes() == getattr(shown_before, name).tobytes(), name
    for name in ("error", "opacity"):
        assert getattr(second, name).tobytes() == getattr(first, name).tobytes(), name
    assert np.array_equal(second.living.ident, first.living.ident)
    assert second.living.strokes.bristles.tobytes() == first.living.strokes.bristles.tobytes()
    assert not unchanged(first, still)
    assert not unchanged(first, uniform_motion(picture.shape[:2], (0.5, 0.0))._replace(same_picture=True))


def square_scene(shape: tuple, left: int, size: int = 36) -> np.ndarray:
    """A still, smoothly shaded background with a checkered square whose left side is at column ``left``."""
    h, w = shape
    y, x = np.mgrid[0:h, 0:w].astype(np.float32)
    image = np.stack([0.3 + 0.3 * x / w, 0.4 + 0.2 * y / h, 0.6 - 0.2 * x / w], axis=-1)
    top = (h - size) // 2
    inside = (x >= left) & (x < left + size) & (y >= top) & (y < top + size)
    checks = ((np.floor((x - left) / 9) + np.floor((y - top) / 9)) % 2).astype(np.float32)
    image[inside] = np.stack([0.9 * checks, 0.2 + 0.0 * checks, 0.9 - 0.8 * checks], axis=-1)[inside]
    return image


def square_motion(shape: tuple, left: int, step: int, size: int = 36) -> FrameMotion:
    """The square (left side at ``left`` on frame t) moves ``step`` px right; the background stands still."""
    h, w = shape
    y, x = np.mgrid[0:h, 0:w]
    top = (h - size) // 2
    on = lambda a: (x >= a) & (x < a + size) & (y >= top) & (y < top + size)  # noqa: E731
    forward = np.zeros((h, w, 2), np.float32)
    forward[on(left), 0] = step
    backward = np.zeros((h, w, 2), np.float32)
    backward[on(left + step), 0] = -step
    return FrameMotion(forward, backward, visible_in_both(forward, backward), comes_back(forward, backward),
                       comes_back(backward, forward))


def test_an_object_entering_the_frame_is_born_on_only_where_it_and_the_background_it_uncovers_are():
    """Births lie on the square, on the strip of background it uncovered, or near them: within three of the
    largest strokes' widths (a stroke that lay across the square's edge is torn by its motion and dies; the
    strokes born in its place lie where it lay). The still background beyond gets none."""
    shape, step, size = (120, 240), 8, 36
    params = Params(seed=4)
    frame = first_frame(square_scene(shape, -20), params, 3, NO_STAGE)
    top = (shape[0] - size) // 2
    reach = 3 * max(frame.living.strokes.size.tolist())
    for t in range(3):
        left = -20 + t * step
        frame = next_frame(frame, t + 1, square_scene(shape, left + step), square_motion(shape, left, step), params,
                           NO_STAGE)
        born = frame.living.strokes.anchor[frame.living.birth == t + 1]
        assert len(born) > 0
        outside_x = np.maximum(np.maximum(left - born[:, 0], born[:, 0] - (left + step + size - 1)), 0)
        outside_y = np.maximum(np.maximum(top - born[:, 1], born[:, 1] - (top + size - 1)), 0)
        assert np.all(np.hypot(outside_x, outside_y) <= reach), born
    assert left + step + size + reach < shape[1] / 2    # half the background lies beyond reach



@pytest.mark.parametrize("fade_frames", [1, 3])
def test_the_frame_shown_made_from_the_canvas_laid_while_painting_is_every_stroke_laid_anew(fade_frames,
                                                                                              monkeypatch):
    """Each frame's shown canvas, made from its judging canvas with the births laid where strokes faded, died or
    were born (``relay.relaid``), has the bytes of its strokes laid on a blank canvas; the first frame's is the
    still's canvas. The square's frames change a small part of the canvas, so most tiles are kept."""
    from core import tuning
    from core.params import scaled_sizes
    from core.sequence.frame_step import frame_tips, laid

    monkeypatch.setattr(tuning, "RELAY_TILE", 8)
    shape, step = (120, 240), 8
    params = Params(seed=4)
    tips = frame_tips(params, scaled_sizes(params, *shape))
    frame = first_frame(square_scene(shape, 20), params, fade_frames, NO_STAGE)
    for t in range(4):
        if t:
            left = 20 + (t - 1) * step
            frame = next_frame(frame, t, square_scene(shape, left + step), square_motion(shape, left, step), params,
                               NO_STAGE)
            assert len(frame.laid_on.changed) > 0
        anew = laid(frame.living, tips, params, shape)
        for name in ("colour", "height", "opacity", "coverage"):
            assert getattr(shown_canvas(frame, params, shape), name).tobytes() == getattr(anew, name).tobytes(), \
                (t, name)
        assert shown_canvas(frame._replace(laid_on=None), params, shape).colour.tobytes() == anew.colour.tobytes()

def write_moving_frames(folder: Path, count: int, shape=(96, 128), step=(1.5, 0.5)) -> None:
    """``count`` PNG frames of the photograph moving by ``step`` px a frame."""
    folder.mkdir(parents=True)
    for t in range(count):
        write_png(folder / f"frame_{t + 1:04d}.png", moved_photo(shape, (-t * step[0], -t * step[1])), bits=16)


def command(inputs, out, *options) -> list:
    return [sys.executable, "-m", "core", "sequence", *map(str, inputs), "-o", str(out), "-q", *options]


def test_a_sequence_killed_at_a_frame_resumes_to_the_same_bytes(tmp_path):
    write_moving_frames(tmp_path / "in", 5)
    whole = subprocess.run(command([tmp_path / "in"], tmp_path / "whole", "--seed", "9"), cwd=ROOT,
                           capture_output=True, text=True)
    assert whole.returncode == 0, whole.stderr
    process = held_run.start(command([tmp_path / "in"], tmp_path / "killed", "--seed", "9")[3:],
                             "core.sequence.shot_commit:commit", 2)
    held_run.held(process)                       # frame 2 committed, the run goes no further until killed
    process.send_signal(signal.SIGKILL)
    process.wait()
    report = tmp_path / "killed" / "report.json"
    done = json.loads(report.read_text())["per_frame"]
    assert len(done) == 2, "the run was not stopped midway"
    assert all((tmp_path / "killed" / f"painting_{e['frame']:04d}.png").exists() for e in done)
    rerun = subprocess.run(command([tmp_path / "in"], tmp_path / "killed", "--seed", "9"), cwd=ROOT,
                           capture_output=True, text=True)
    assert rerun.returncode == 0, rerun.stderr
    same_bytes(tmp_path / "killed", tmp_path / "whole")
    assert not [p for p in os.listdir(tmp_path / "killed") if p.startswith(".staging")]


def refusal(arguments, cwd=ROOT) -> str:
    """The one sentence a refused ``core sequence`` prints (exit status 2)."""
    run = subprocess.run([sys.executable, "-m", "core", "sequence", *map(str, arguments), "-q"], cwd=cwd,
                         capture_output=True, text=True)
    assert run.returncode == 2, run.stderr
    return one_sentence_run(run)


def test_a_folder_of_another_sequence_or_a_still_is_refused_and_left_as_it_was(tmp_path):
    write_moving_frames(tmp_path / "in", 2, shape=(64, 80))
    paint_sequence(find_frames([str(tmp_path / "in")]), tmp_path / "out", Params(seed=1))
    before = folder_bytes(tmp_path / "out")
    line = refusal([tmp_path / "in", "-o", tmp_path / "out", "--seed", "2"])
    assert f"The output folder {tmp_path / 'out'} holds frames painted with other settings" in line
    line = refusal([tmp_path / "in", "-o", tmp_path / "out", "--seed", "1", "--fade-frames", "2"])
    assert "other settings" in line
    assert folder_bytes(tmp_path / "out") == before
    (tmp_path / "still").mkdir()
    (tmp_path / "still" / "report.json").write_text(json.dumps({"strokes": 3}))
    line = refusal([tmp_path / "in", "-o", tmp_path / "still"])
    assert line.endswith(f"The output folder {tmp_path / 'still'} holds a still painting; paint the sequence into "
                         f"another folder.")


def test_a_changed_input_frame_is_refused_by_name(tmp_path):
    write_moving_frames(tmp_path / "in", 2, shape=(64, 80))
    paint_sequence(find_frames([str(tmp_path / "in")]), tmp_path / "out", Params(seed=1))
    write_png(tmp_path / "in" / "frame_0001.png", moved_photo((64, 80), (5, 5)), bits=16)
    line = refusal([tmp_path / "in", "-o", tmp_path / "out", "--seed", "1"])
    assert f"holds frame 1 painted from another picture than {tmp_path / 'in' / 'frame_0001.png'} holds now" in line


@pytest.mark.parametrize("options, words", [
    (["--fade-frames", "0"], "The fade must be a whole number of frames from 1 to 100, got 0."),
    (["--frames", "7-9"], "The option --frames 7-9 selects no frame"),
])
def test_bad_options_are_refused_in_one_sentence_before_any_folder_is_made(tmp_path, options, words):
    write_moving_frames(tmp_path / "in", 2, shape=(64, 80))
    line = refusal([tmp_path / "in", "-o", tmp_path / "out", *options])
    assert words in line
    assert not (tmp_path / "out").exists()


def test_a_rerun_of_a_complete_sequence_paints_nothing_and_keeps_its_files(tmp_path):
    write_moving_frames(tmp_path / "in", 2, shape=(64, 80))
    frames = find_frames([str(tmp_path / "in")])
    paint_sequence(frames, tmp_path / "out", Params(seed=1), SequenceSettings(fade_frames=2))
    before = {p.name: p.stat().st_mtime_ns for p in (tmp_path / "out").iterdir()}
    report = paint_sequence(frames, tmp_path / "out", Params(seed=1), SequenceSettings(fade_frames=2))
    assert report["complete"] and report["frames"] == [1, 2]
    assert {p.name: p.stat().st_mtime_ns for p in (tmp_path / "out").iterdir()} == before


def test_carried_strokes_keep_their_texture_and_follow_the_light():
    shape, step = (90, 120), (1.0, 0.0)
    params = Params(seed=6)
    first = first_frame(moved_photo(shape, (0, 0)), params, 3, NO_STAGE)
    darker = moved_photo(shape, (-step[0], 0)) * np.float32(0.8)
    second = next_frame(first, 1, darker, uniform_motion(shape, step), params, NO_STAGE)
    painted = first.living.strokes
    index = {ident: i for i, ident in enumerate(first.living.ident.tolist())}
    kept = np.flatnonzero((second.living.birth == 0) & (second.living.strokes.brush == PAINTING_BRUSH))
    assert len(kept) > 20
    for i in kept[:20].tolist():
        j = index[int(second.living.ident[i])]
        old = painted.bristles[painted.bristle_starts[j]:painted.bristle_starts[j + 1]]
        new = second.living.strokes.bristles[second.living.strokes.bristle_starts[i]:
                                             second.living.strokes.bristle_starts[i + 1]]
        assert second.living.strokes.anchor_colour[i].mean() < painted.anchor_colour[j].mean()
        inside = (old > 0.02).all(axis=1) & (old < 0.98).all(axis=1) & (new > 0.02).all(axis=1)
        offsets_before = old[inside] - painted.anchor_colour[j]
        offsets_after = new[inside] - second.living.strokes.anchor_colour[i]
        assert np.allclose(offsets_before, offsets_after, atol=1e-5)


def test_a_cancelled_sequence_keeps_its_complete_frames_and_goes_on_to_the_same_bytes(tmp_path):
    write_moving_frames(tmp_path / "in", 4, shape=(64, 80))
    frames = find_frames([str(tmp_path / "in")])
    paint_sequence(frames, tmp_path / "whole", Params(seed=4))
    polls = []

    def cancel() -> bool:
        polls.append(len(list((tmp_path / "part").glob("painting_*.png"))))
        return polls[-1] >= 2

    with pytest.raises(Cancelled) as caught:
        paint_sequence(frames, tmp_path / "part", Params(seed=4), cancel=cancel)
    assert str(caught.value) == (f"The run was cancelled; the frames in {tmp_path / 'part'} are complete, and "
                                 f"painting the sequence again goes on after the last of them.")
    # asked once frame 2 is committed, as frame 3's maps are written beside frame 4's life: frame 3 is committed too
    assert sorted(p.name for p in (tmp_path / "part").glob("painting_*.png")) == ["painting_0001.png",
                                                                                 "painting_0002.png",
                                                                                 "painting_0003.png"]
    assert ShotFolder(tmp_path / "part").check(read_report(tmp_path / "part")).keep == 3
    paint_sequence(frames, tmp_path / "part", Params(seed=4))
    same_bytes(tmp_path / "part", tmp_path / "whole")


def test_one_folder_given_as_a_path_is_the_shot_given_in_a_list(tmp_path):
    write_moving_frames(tmp_path / "in", 2, shape=(48, 64))
    paint_sequence_files([str(tmp_path / "in")], tmp_path / "listed", Params(seed=2))
    paint_sequence_files(str(tmp_path / "in"), tmp_path / "text", Params(seed=2))
    paint_sequence_files(tmp_path / "in", tmp_path / "path", Params(seed=2))
    same_bytes(tmp_path / "text", tmp_path / "listed")
    same_bytes(tmp_path / "path", tmp_path / "listed")


@pytest.mark.parametrize("renderer", ["bristles", "lines"])
def test_the_judging_canvas_laid_in_bands_of_rows_is_the_canvas_laid_whole(renderer):
    """A cluster lays a frame's judging canvas in bands of rows side by side: each band lays only the strokes that
    reach it (``reaching_rows``) on its own rows, and the bands joined are the same bytes as every stroke laid on
    one canvas."""
    shape, step = (96, 128), (2.5, 1.5)
    params = Params(seed=3, stroke_sizes=(32, 16, 8, 4), renderer=renderer)
    first = first_frame(moved_photo(shape, (0, 0)), params, 3, NO_STAGE)
    image = moved_photo(shape, (-step[0], -step[1]))
    carried = carried_frame(first, image, uniform_motion(shape, step), params, analyse_frame(image, params))
    whole = settled_rows(carried, params, shape, (0, shape[0])).canvas
    chosen = judging_bands(LifeStep(None, carried), shape[0], 3)      # about equal in the work of laying
    assert len(chosen) == 3 and chosen != row_bands(shape[0], 3)
    for cuts in ([0, 48, 96], [0, 7, 30, 31, 64, 96], [first for first, _ in chosen] + [shape[0]]):
        bands = list(zip(cuts[:-1], cuts[1:], strict=True))
        parts = [settled_rows(carried, params, shape, rows) for rows in bands]
        assert all(reaching_rows(carried.living.strokes, *rows).mean() < 0.95 for rows in bands if rows[1] - rows[0] < 40)
        assert all(part.canvas.height.shape == (stop - first, shape[1]) for part, (first, stop) in zip(parts, bands, strict=True))
        joined = joined_rows(parts[::-1])
        for name in ("colour", "coverage", "height", "opacity"):
            assert getattr(joined, name).tobytes() == getattr(whole, name).tobytes(), (cuts, name)
