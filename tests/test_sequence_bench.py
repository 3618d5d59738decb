"""The pictures and folder names of bench/sequence.py: which painting lands in which panel of the strip, and which
folder holds which frame painted alone by `core batch`."""

import sys
from pathlib import Path

import numpy as np

from core.files.frames import Frames

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "bench"))
from sequence import LABEL_HEIGHT, animation, frame_name, paint_alone, strip  # noqa: E402

GAP = 6  # core.figures.sheet.contact_sheet's default gap


def flat(value, h=10, w=14):
    return np.full((h, w, 3), value, np.float32)


def rows_of_values(rows, columns):
    """Row r, column c filled with the value (10 r + c) / 100."""
    return [[flat((10 * r + c) / 100) for c in range(columns)] for r in range(rows)]


def panel_centre(sheet, r, c, h=10, w=14):
    y = GAP + r * (LABEL_HEIGHT + h + GAP) + LABEL_HEIGHT + h // 2
    x = GAP + c * (w + GAP) + w // 2
    return sheet[y, x]


def test_strip_puts_rows_down_and_frames_across_at_one_to_one():
    sheet = strip(rows_of_values(3, 4), [7, 8, 9, 10])
    assert sheet.shape == (3 * (LABEL_HEIGHT + 10) + 4 * GAP, 4 * 14 + 5 * GAP, 3)
    for r in range(3):
        for c in range(4):
            np.testing.assert_allclose(panel_centre(sheet, r, c), (10 * r + c) / 100, atol=1e-6)


def test_animation_stacks_the_rows_of_one_frame_per_picture():
    pictures = animation(rows_of_values(3, 4), [7, 8, 9, 10])
    assert len(pictures) == 4
    for c, picture in enumerate(pictures):
        assert picture.shape == (3 * (LABEL_HEIGHT + 10) + 4 * GAP, 14 + 2 * GAP, 3)
        for r in range(3):
            np.testing.assert_allclose(panel_centre(picture, r, 0), (10 * r + c) / 100, atol=1e-6)


def test_frame_names_share_one_width_of_at_least_four_digits():
    short = Frames((Path("a"), Path("b")), (9, 10), 4, 4)
    long = Frames((Path("a"), Path("b")), (9999, 10000), 4, 4)
    assert [frame_name(n, short) for n in short.numbers] == ["frame_0009", "frame_0010"]
    assert [frame_name(n, long) for n in long.numbers] == ["frame_09999", "frame_10000"]


def test_the_frames_alone_are_painted_by_one_batch_each_into_the_folder_named_for_it(tmp_path):
    from core.files.frames import find_frames
    from core.files.writing import write_png

    rng = np.random.default_rng(3)
    (tmp_path / "clip").mkdir()
    pictures = [rng.random((24, 32, 3)).astype(np.float32) for _ in range(3)]
    for number, picture in zip((7, 8, 9), pictures, strict=True):
        write_png(tmp_path / "clip" / f"frame_{number:04d}.png", picture, bits=16)
    frames = find_frames([str(tmp_path / "clip")])
    painted = paint_alone(frames, tmp_path / "alone", 5, 2)
    assert len(painted["walls"]) == 2 and len(painted["peaks"]) == 2
    assert [folder.name for folder in painted["folders"]] == ["frame_0007_001", "frame_0008_001", "frame_0009_001"]
    for folder, path, strokes in zip(painted["folders"], frames.paths, painted["strokes"], strict=True):
        report = (folder / "report.json").read_text()
        assert path.name in report and strokes > 0
