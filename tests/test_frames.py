"""The frames of a sequence (core.files.frames): discovery, numbers, --frames, header checks, multilayer EXR."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import OpenImageIO as oiio
import pytest

from core.errors import InputError, ParameterError
from core.files import frames, reading, writing

W, H = 8, 6


def picture(seed: int, w: int = W, h: int = H, c: int = 3) -> np.ndarray:
    """A float32 (h, w, c) image in [0, 1] that differs with ``seed``."""
    return np.random.default_rng(seed).random((h, w, c), dtype=np.float32)


def png_frames(folder: Path, names, w: int = W, h: int = H):
    """Write one small PNG per name in ``folder`` (made if needed); their paths in the order given."""
    folder.mkdir(parents=True, exist_ok=True)
    paths = [folder / name for name in names]
    for seed, path in enumerate(paths):
        writing.write_png(path, picture(seed, w, h))
    return paths


def write_multilayer(path: Path, parts) -> Path:
    """A multi-part EXR as Blender writes it: ``parts`` is [(part name, channel letters, float32 (H, W, C))], each
    part's spec naming it ('ViewLayer.Combined') and its channels ('ViewLayer.Combined.R')."""
    specs = []
    for name, letters, data in parts:
        spec = oiio.ImageSpec(data.shape[1], data.shape[0], len(letters), "float")
        spec.channelnames = tuple(f"{name}.{letter}" for letter in letters)
        spec.attribute("name", name)
        specs.append(spec)
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), specs), oiio.geterror()
    for i, (spec, (_, _, data)) in enumerate(zip(specs, parts, strict=True)):
        assert i == 0 or out.open(str(path), spec, "AppendSubimage"), out.geterror()
        assert out.write_image(np.ascontiguousarray(data, dtype=np.float32)), out.geterror()
    out.close()
    return path


def write_exr(path: Path, data: np.ndarray, names) -> Path:
    """One single-part float EXR with channels ``names``."""
    spec = oiio.ImageSpec(data.shape[1], data.shape[0], data.shape[2], "float")
    spec.channelnames = tuple(names)
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), spec), oiio.geterror()
    assert out.write_image(np.ascontiguousarray(data, dtype=np.float32)), out.geterror()
    out.close()
    return path


def tree(root: Path):
    """Every file and folder under ``root`` with its size and modification time."""
    return sorted((str(p), p.stat().st_size, p.stat().st_mtime_ns) for p in root.rglob("*"))


def refused(error, tmp_path, monkeypatch, inputs, frame_range=None) -> str:
    """The sentence of ``error`` that ``find_frames`` raises, checked to be one sentence that wrote nothing."""
    monkeypatch.chdir(tmp_path)
    before = tree(tmp_path)
    with pytest.raises(error) as caught:
        frames.find_frames([str(i) for i in inputs], frame_range)
    assert tree(tmp_path) == before
    text = str(caught.value)
    assert text.endswith(".") and "\n" not in text
    return text


# --- which files, in which order, with which numbers ---------------------------------------------------------


def test_a_folder_gives_its_image_files_ordered_by_number(tmp_path):
    folder = tmp_path / "shot"
    paths = png_frames(folder, ["frame_10.png", "frame_9.png", "frame_11.PNG", "frame_8.png"])
    png_frames(folder, [".frame_12.png"])
    (folder / "notes_13.txt").write_text("not a frame")
    (folder / "frame_14.png").mkdir()
    found = frames.find_frames([str(folder)])
    assert found.paths == (paths[3], paths[1], paths[0], paths[2])
    assert found.numbers == (8, 9, 10, 11)
    assert (found.width, found.height) == (W, H)


def test_a_folder_of_unnumbered_names_is_numbered_by_place_in_name_order(tmp_path):
    folder = tmp_path / "shot"
    paths = png_frames(folder, ["take10.png", "intro.png", "take9.jpg"])
    found = frames.find_frames([str(folder)])
    assert found.paths == (paths[1], paths[2], paths[0])
    assert found.numbers == (1, 2, 3)


def test_a_pattern_gives_the_files_with_its_digits_ordered_by_number(tmp_path):
    wanted = png_frames(tmp_path, ["f_98.png", "f_99.png", "f_100.png"])
    png_frames(tmp_path, ["f_7.png", "f_007.png", "g_97.png", "f_97.jpg", "f_96_b.png"])
    found = frames.find_frames([str(tmp_path / "f_##.png")])
    assert found.paths == tuple(wanted)
    assert found.numbers == (98, 99, 100)


def test_a_blender_pattern_takes_its_number_from_the_hashes(tmp_path):
    wanted = png_frames(tmp_path, ["shot2_v3_0001.png", "shot2_v3_0002.png"])
    png_frames(tmp_path, ["shot2_v3_1.png"])
    found = frames.find_frames([str(tmp_path / "shot2_v3_####.png")])
    assert (found.paths, found.numbers) == (tuple(wanted), (1, 2))


def test_listed_files_keep_the_order_given(tmp_path):
    paths = png_frames(tmp_path, ["c_1.png", "a_2.png", "b_3.png"])
    assert frames.find_frames([str(p) for p in paths]).paths == tuple(paths)
    unnumbered = png_frames(tmp_path, ["start.png", "z_7.png", "a_3.png"])
    found = frames.find_frames([str(p) for p in unnumbered])
    assert (found.paths, found.numbers) == (tuple(unnumbered), (1, 2, 3))


def test_a_file_whose_name_holds_a_hash_is_a_file(tmp_path):
    (path,) = png_frames(tmp_path, ["take#2_0005.png"])
    found = frames.find_frames([str(path)])
    assert (found.paths, found.numbers) == ((path,), (5,))


# --- --frames ---------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("text, numbers", [("3-5", (3, 4, 5)), ("4-", (4, 5, 6)), ("-2", (1, 2)), ("4", (4,)),
                                           ("0-9", (1, 2, 3, 4, 5, 6)), ("6-6", (6,))])
def test_frames_selects_by_number_inclusive(tmp_path, text, numbers):
    png_frames(tmp_path, [f"frame_{n:04d}.png" for n in range(1, 7)])
    found = frames.find_frames([str(tmp_path / "frame_####.png")], text)
    assert found.numbers == numbers
    assert [p.name for p in found.paths] == [f"frame_{n:04d}.png" for n in numbers]


@pytest.mark.parametrize("text", ["x", "-", "", "1-2-3", "a-3", "1.5", "3 4"])
def test_a_malformed_frames_option_is_refused(tmp_path, monkeypatch, text):
    png_frames(tmp_path / "shot", ["frame_0001.png", "frame_0002.png"])
    sentence = refused(ParameterError, tmp_path, monkeypatch, [tmp_path / "shot"], text)
    assert sentence == f"The option --frames must be A-B, A-, -B or a single frame number A, got {text!r}."


def test_a_backward_range_and_an_empty_selection_are_refused(tmp_path, monkeypatch):
    png_frames(tmp_path / "shot", ["frame_0001.png", "frame_0002.png"])
    assert (refused(ParameterError, tmp_path, monkeypatch, [tmp_path / "shot"], "2-1")
            == "The option --frames 2-1 ends before it starts: give A-B with A at most B.")
    assert (refused(ParameterError, tmp_path, monkeypatch, [tmp_path / "shot"], "3-")
            == "The option --frames 3- selects no frame: the frames are numbered 1 to 2.")


def test_frames_outside_the_selection_are_not_checked(tmp_path):
    paths = png_frames(tmp_path, ["frame_0001.png", "frame_0002.png", "frame_0005.png"])
    (tmp_path / "frame_0006.png").write_bytes(b"not an image")
    found = frames.find_frames([str(tmp_path)], "1-2")
    assert found.paths == tuple(paths[:2])


# --- refusals, from names and headers, before any pixel -----------------------------------------------------------


def test_a_gap_names_the_frames_on_both_sides(tmp_path, monkeypatch):
    shot = tmp_path / "shot"
    png_frames(shot, ["frame_0001.png", "frame_0002.png", "frame_0004.png", "frame_0008.png"])
    assert (refused(InputError, tmp_path, monkeypatch, [shot])
            == f"{shot / 'frame_0004.png'} follows {shot / 'frame_0002.png'}: frame 3 is missing.")
    assert (refused(InputError, tmp_path, monkeypatch, [shot / "frame_####.png"], "4-")
            == f"{shot / 'frame_0008.png'} follows {shot / 'frame_0004.png'}: frames 5 to 7 are missing.")


def test_two_frames_with_one_number_are_refused(tmp_path, monkeypatch):
    shot = tmp_path / "shot"
    png_frames(shot, ["beauty_0001.png", "beauty_0002.png", "depth_0002.png"])
    assert (refused(InputError, tmp_path, monkeypatch, [shot])
            == f"{shot / 'beauty_0002.png'} and {shot / 'depth_0002.png'} both have frame number 2: "
               f"give the frames of one sequence.")


def test_listed_frames_out_of_order_are_refused(tmp_path, monkeypatch):
    paths = png_frames(tmp_path / "shot", ["f_1.png", "f_10.png", "f_11.png", "f_2.png"])
    assert (refused(InputError, tmp_path, monkeypatch, paths)
            == f"{paths[3]} (frame 2) is listed after {paths[2]} (frame 11): "
               f"list the frames in the order of their numbers.")


def test_a_frame_of_another_size_is_refused_with_both_sizes(tmp_path, monkeypatch):
    shot = tmp_path / "shot"
    png_frames(shot, ["frame_0001.png", "frame_0002.png"])
    png_frames(shot, ["frame_0003.png"], w=W + 1)
    assert (refused(InputError, tmp_path, monkeypatch, [shot])
            == f"The frame {shot / 'frame_0003.png'} is {W + 1} x {H} pixels but the first frame "
               f"{shot / 'frame_0001.png'} is {W} x {H}: every frame must have the same size.")


@pytest.mark.parametrize("content, words", [(b"not an image at all", "Cannot read the frame {path}: "),
                                            (b"", "The frame file {path} is empty (0 bytes).")])
def test_an_unreadable_frame_is_refused_by_name(tmp_path, monkeypatch, content, words):
    shot = tmp_path / "shot"
    png_frames(shot, ["frame_0001.png", "frame_0003.png"])
    bad = shot / "frame_0002.png"
    bad.write_bytes(content)
    sentence = refused(InputError, tmp_path, monkeypatch, [shot / "frame_####.png"])
    assert sentence.startswith(words.format(path=bad))


def test_a_missing_listed_frame_is_refused_by_name(tmp_path, monkeypatch):
    paths = png_frames(tmp_path, ["frame_0001.png"])
    missing = tmp_path / "frame_0002.png"
    assert refused(InputError, tmp_path, monkeypatch, [paths[0], missing]) == f"The frame file {missing} does not exist."


def test_a_missing_listed_frame_is_named_before_the_frames_option_selects(tmp_path, monkeypatch):
    # a path named as if it were frame 1080, and a range that its number lies outside of
    missing = tmp_path / "shot1080"
    assert (refused(InputError, tmp_path, monkeypatch, [missing], "1-5")
            == f"The frame file {missing} does not exist.")


def test_no_frames_is_refused_naming_the_folder_or_pattern(tmp_path, monkeypatch):
    empty = tmp_path / "empty"
    empty.mkdir()
    (empty / "readme.txt").write_text("no frames here")
    png_frames(empty, [".hidden_0001.png"])
    assert (refused(InputError, tmp_path, monkeypatch, [empty])
            == f"The folder {empty} holds no frames: no PNG, JPEG, TIFF or EXR file.")
    assert (refused(InputError, tmp_path, monkeypatch, [empty / "frame_####.png"])
            == f"No file matches the frame pattern {empty / 'frame_####.png'}.")
    assert (refused(InputError, tmp_path, monkeypatch, [tmp_path / "gone" / "f_#.png"])
            == f"No file matches the frame pattern {tmp_path / 'gone' / 'f_#.png'}: "
               f"its folder {tmp_path / 'gone'} does not exist.")
    assert refused(InputError, tmp_path, monkeypatch, []).startswith("No frames were given")


def test_the_checks_read_headers_only(tmp_path):
    paths = png_frames(tmp_path, ["frame_0001.png", "frame_0002.png"], w=64, h=64)
    data = paths[1].read_bytes()
    paths[1].write_bytes(data[:len(data) // 2])
    assert frames.find_frames([str(tmp_path)]).paths == tuple(paths)
    with pytest.raises(InputError, match="frame_0002.png"):
        reading.read_image(paths[1])


def test_a_single_frame_is_a_sequence(tmp_path):
    (path,) = png_frames(tmp_path, ["frame_0042.png"])
    assert frames.find_frames([str(tmp_path)]) == frames.Frames((path,), (42,), W, H)


# --- Blender multilayer EXR --------------------------------------------------------------------------------------


def combined_pixels(seed: int) -> np.ndarray:
    """Scene-linear premultiplied RGBA (H, W, 4) with some transparency and values above 1."""
    rgba = picture(seed, c=4) * np.float32(1.5)
    rgba[..., 3] = np.clip(rgba[..., 3], 0.0, 1.0)
    rgba[..., :3] *= rgba[..., 3:]
    return rgba


def test_the_combined_part_is_the_picture_found_by_name(tmp_path):
    combined, vector, noisy = combined_pixels(1), picture(2, c=4) * 9 - 4, picture(3, c=4)
    frame = write_multilayer(tmp_path / "frame_0001.exr", [("ViewLayer.Vector", "XYZW", vector),
                                                           ("ViewLayer.Combined", "RGBA", combined),
                                                           ("ViewLayer.Noisy Image", "RGBA", noisy)])
    plain = write_exr(tmp_path / "plain.exr", combined, "RGBA")
    np.testing.assert_array_equal(reading.read_image(frame), reading.read_image(plain))
    np.testing.assert_array_equal(reading.read_gray(frame), reading.read_gray(plain))
    assert reading.probe(frame) == (W, H, 4)
    assert reading.image_count(frame) == 1


def test_a_single_part_multilayer_exr_is_read_by_channel_names(tmp_path):
    combined, vector = combined_pixels(4), picture(5, c=4) * 3
    names = [f"ViewLayer.Vector.{c}" for c in "XYZW"] + [f"ViewLayer.Combined.{c}" for c in "RGBA"]
    frame = write_exr(tmp_path / "frame_0001.exr", np.concatenate([vector, combined], axis=2), names)
    plain = write_exr(tmp_path / "plain.exr", combined, "RGBA")
    np.testing.assert_array_equal(reading.read_image(frame), reading.read_image(plain))
    np.testing.assert_array_equal(frames.read_vector_pass(frame), vector)


def test_several_view_layers_are_several_images_and_the_first_is_painted(tmp_path):
    first, second = combined_pixels(6), combined_pixels(7)
    frame = write_multilayer(tmp_path / "layers.exr", [("One.Combined", "RGBA", first),
                                                       ("One.Vector", "XYZW", picture(8, c=4)),
                                                       ("Two.Combined", "RGBA", second)])
    assert reading.image_count(frame) == 2
    np.testing.assert_array_equal(reading.read_image(frame),
                                  reading.read_image(write_exr(tmp_path / "plain.exr", first, "RGBA")))


def test_the_vector_pass_round_trips_as_stored(tmp_path):
    vector = (picture(9, c=4) * 200 - 100).astype(np.float32)
    frame = write_multilayer(tmp_path / "frame_0001.exr", [("ViewLayer.Combined", "RGBA", combined_pixels(1)),
                                                           ("ViewLayer.Vector", "XYZW", vector)])
    read = frames.read_vector_pass(frame)
    assert read.dtype == np.float32 and read.shape == (H, W, 4)
    np.testing.assert_array_equal(read, vector)


def test_the_vector_pass_channels_are_found_by_name(tmp_path):
    vector = picture(10, c=4)
    frame = write_multilayer(tmp_path / "frame_0001.exr", [("ViewLayer.Combined", "RGBA", combined_pixels(1)),
                                                           ("ViewLayer.Vector", "WZYX", vector[..., ::-1])])
    np.testing.assert_array_equal(frames.read_vector_pass(frame), vector)


def test_a_frame_without_a_vector_pass_gives_none(tmp_path):
    (png,) = png_frames(tmp_path, ["frame_0001.png"])
    layered = write_multilayer(tmp_path / "frame_0002.exr", [("ViewLayer.Combined", "RGBA", combined_pixels(1)),
                                                             ("ViewLayer.Depth", "Z", picture(2, c=1))])
    plain = write_exr(tmp_path / "frame_0003.exr", picture(3, c=4), ["X", "Y", "Z", "W"])
    for frame in (png, layered, plain):
        assert frames.read_vector_pass(frame) is None


def test_a_vector_pass_with_nan_is_refused_by_name(tmp_path):
    vector = picture(11, c=4)
    vector[1, 2, 0] = np.nan
    frame = write_multilayer(tmp_path / "frame_0007.exr", [("ViewLayer.Combined", "RGBA", combined_pixels(1)),
                                                           ("ViewLayer.Vector", "XYZW", vector)])
    with pytest.raises(InputError) as caught:
        frames.read_vector_pass(frame)
    assert str(caught.value) == f"The frame {frame} holds NaN or infinite values in its Vector pass."


def test_multilayer_exr_frames_are_found_and_sized_from_their_combined_part(tmp_path):
    for n in (1, 2):
        write_multilayer(tmp_path / f"frame_{n:04d}.exr", [("ViewLayer.Combined", "RGBA", combined_pixels(n)),
                                                           ("ViewLayer.Vector", "XYZW", picture(n, c=4))])
    found = frames.find_frames([os.fspath(tmp_path / "frame_####.exr")])
    assert (found.numbers, found.width, found.height) == ((1, 2), W, H)


def test_the_motion_source_is_the_vector_pass_only_when_every_frame_has_one(tmp_path):
    vector = picture(4, c=4)
    with_pass = [write_multilayer(tmp_path / f"frame_000{n}.exr", [("ViewLayer.Combined", "RGBA", combined_pixels(n)),
                                                                  ("ViewLayer.Vector", "XYZW", vector)])
                 for n in (1, 2)]
    without = write_multilayer(tmp_path / "frame_0003.exr", [("ViewLayer.Combined", "RGBA", combined_pixels(3))])
    pngs = png_frames(tmp_path / "png", ["a_0001.png", "a_0002.png"])
    assert frames.carry_vector_passes(with_pass) is True
    assert frames.carry_vector_passes(pngs + [without]) is False
    with pytest.raises(InputError) as caught:
        frames.carry_vector_passes(with_pass + [without])
    assert str(caught.value) == (f"The frame {without} has no Vector pass but {with_pass[0]} has one: render every "
                                 f"frame with the Vector pass, or none.")
