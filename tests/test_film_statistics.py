"""The relit film's figures (core/evaluation/film.py), without Blender.

A tiny shot is painted with ``core.paint_sequence_files``; a stand-in "relit"
film (the painted frames' own painting_NNNN.png, scaled by area) is measured
with ``run_film``, so its figures must equal the unlit painting's,
measured the same way.
"""

import json

import numpy as np
import pytest
from tiny_shot import FIRST, FRAMES, shot

import core
from core.colour import linear_to_srgb
from core.errors import InputError
from core.evaluation.film import film_statistics, resize_motion, run_film
from core.evaluation.film_files import frame_file
from core.files import reading, writing
from core.lighting import paper_lighting
from core.motion import optical_flow, visible_in_both, warping_error
from core.motion.optical_flow import SEQUENCE_MEGAPIXELS
from core.resample import area_weights, resize_area

FILM_W, FILM_H = 64, 43  # the tiny shot's 96 x 64 with a longer side of 64 px


def test_area_weights_average_the_pixels_under_each_output_pixel():
    weights = area_weights(4, 2)
    assert np.allclose(weights, [[0.5, 0.5, 0, 0], [0, 0, 0.5, 0.5]])
    weights = area_weights(640, 480)
    assert np.allclose(weights.sum(axis=1), 1.0)
    assert np.allclose(weights[0, :2], [0.75, 0.25])  # 4/3 input px under each output px


def test_resize_area_keeps_the_mean_and_block_means():
    rng = np.random.default_rng(1)
    image = rng.random((12, 16, 3), dtype=np.float32)
    half = resize_area(image, 8, 6)
    assert half.shape == (6, 8, 3)
    assert np.allclose(half, image.reshape(6, 2, 8, 2, 3).mean(axis=(1, 3)), atol=1e-6)
    assert resize_area(image, 11, 7).mean() == pytest.approx(image.mean(), abs=1e-5)


def test_resize_motion_measures_in_the_new_pixels():
    motion = np.zeros((36, 64, 2), np.float32)
    motion[..., 0], motion[..., 1] = 4.0, -2.0
    small = resize_motion(motion, 48, 27)
    assert small.shape == (27, 48, 2)
    assert np.allclose(small[..., 0], 3.0) and np.allclose(small[..., 1], -1.5)


def test_film_statistics_give_ratios_to_the_footage():
    errors = {"footage": [0.001, 0.002], "relit": [0.002, 0.002], "paper": [0.003, 0.006], "painting": [0.001, 0.001]}
    statistics = film_statistics(errors, [11, 12])
    assert statistics["footage"]["mean"] == pytest.approx(0.0015)
    assert statistics["relit"]["ratio"] == pytest.approx(0.002 / 0.0015)
    assert [e["ratio"] for e in statistics["paper"]["per_frame"]] == pytest.approx([3.0, 3.0])
    assert [e["frame"] for e in statistics["relit"]["per_frame"]] == [11, 12]


@pytest.fixture(scope="module")
def painted(tmp_path_factory):
    work = tmp_path_factory.mktemp("animation_figures")
    frames = shot(work / "frames")
    core.paint_sequence_files([str(frames)], str(work / "painted"), core.Params(seed=2))
    relit = work / "relit"
    relit.mkdir()
    for number in range(FIRST, FIRST + FRAMES):  # a stand-in relit film: the unlit painting at the film's size
        colour = linear_to_srgb(reading.read_exr(work / "painted" / f"color_{number:04d}.exr")[0][..., :3])
        writing.write_png(relit / frame_file(number), resize_area(colour, FILM_W, FILM_H))
    result = run_film(work / "painted", relit, work / "out", 135.0, 30.0, render={"samples": 4})
    return {"work": work, "frames": frames, "result": result}


def test_run_film_writes_the_films_and_their_statistics(painted):
    out = painted["work"] / "out"
    for number in range(FIRST, FIRST + FRAMES):
        for folder in ("paper", "side_by_side"):
            assert (out / folder / frame_file(number)).is_file()
        assert reading.read_image(out / "paper" / frame_file(number)).shape == (FILM_H, FILM_W, 3)
    assert (out / "animation.gif").read_bytes()[:6] == b"GIF89a"
    result = json.loads((out / "animation.json").read_text())
    assert result["frames"] == list(range(FIRST, FIRST + FRAMES)) and result["film_size"] == [FILM_W, FILM_H]
    assert result["render"] == {"samples": 4} and result["motion"] == "optical flow"
    for film in ("footage", "relit", "paper", "painting"):
        assert [e["frame"] for e in result["warping_error"][film]["per_frame"]] == list(range(FIRST, FIRST + FRAMES - 1))
    text = (out / "animation.md").read_text()
    assert "relit film's warping error is" in text and "| mean |" in text


def test_a_relit_film_equal_to_the_painting_measures_as_the_painting(painted):
    statistics = painted["result"]["warping_error"]
    # The stand-in relit film is the painting quantised to 8 bits: the same statistics within the quantisation.
    assert statistics["relit"]["mean"] == pytest.approx(statistics["painting"]["mean"], rel=0.02)
    assert statistics["relit"]["ratio"] == pytest.approx(statistics["painting"]["ratio"], rel=0.02)


def test_figures_recomputed_from_the_written_frames(painted):
    """The footage's and the paper film's warping errors, recomputed here from the files with the painter's
    motion (optical flow at SEQUENCE_MEGAPIXELS, scaled to the film) and visibility."""
    work, result = painted["work"], painted["result"]
    footage = [reading.read_image(painted["frames"] / f"frame_{n:04d}.png") for n in range(FIRST, FIRST + FRAMES)]
    paper = [reading.read_image(work / "out" / "paper" / frame_file(n)) for n in range(FIRST, FIRST + FRAMES)]
    expected_paper = []
    for index in range(FRAMES - 1):
        forward = resize_motion(optical_flow(footage[index], footage[index + 1], SEQUENCE_MEGAPIXELS), FILM_W, FILM_H)
        backward = resize_motion(optical_flow(footage[index + 1], footage[index], SEQUENCE_MEGAPIXELS), FILM_W, FILM_H)
        visible = visible_in_both(forward, backward)
        small = [resize_area(f, FILM_W, FILM_H) for f in footage[index:index + 2]]
        entry = result["warping_error"]["footage"]["per_frame"][index]
        assert entry["error"] == pytest.approx(warping_error(small[0], small[1], forward, visible), rel=1e-4)
        expected_paper.append(warping_error(paper[index], paper[index + 1], forward, visible))
    assert [e["error"] for e in result["warping_error"]["paper"]["per_frame"]] == pytest.approx(expected_paper,
                                                                                                rel=0.02)
    # The paper frames are the paper's Eq. 6-7 of each frame's maps, scaled to the film.
    maps = {name: reading.read_exr(work / "painted" / f"{name}_{FIRST:04d}.exr")[0] for name in
            ("color", "height", "orientation")}
    lit = paper_lighting(linear_to_srgb(maps["color"][..., :3]), maps["height"][..., 0], maps["orientation"][..., 0])
    assert np.abs(resize_area(lit, FILM_W, FILM_H) - paper[0]).max() <= 0.5 / 255 + 1e-6


def test_missing_relit_frames_and_folders_are_refused_in_one_sentence(painted, tmp_path):
    work = painted["work"]
    with pytest.raises(InputError, match="holds no painted sequence"):
        run_film(tmp_path, work / "relit", tmp_path / "out", 0.0, 30.0)
    partial = tmp_path / "relit"
    partial.mkdir()
    (partial / frame_file(FIRST)).write_bytes((work / "relit" / frame_file(FIRST)).read_bytes())
    with pytest.raises(InputError, match=frame_file(FIRST + 1)):
        run_film(work / "painted", partial, tmp_path / "out", 0.0, 30.0)
