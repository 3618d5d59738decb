"""The lives file of a painted sequence's strokes: what is appended frame by frame is read back.

Births, deaths and paths are checked against a sequence worked out by hand; points come back within 1/32 px;
cutting to a committed length gives the bytes of a run that never wrote what followed; an incomplete last record
is ignored, a damaged or foreign file is refused naming it; a failed write is an OutputError that leaves the
committed file; a realistic moving sequence stays below 12 bytes per stroke per frame; the same frame gives the
same bytes.
"""

import os
import sys
import zlib

import numpy as np
import pytest
from oracles import one_sentence

from core.errors import InputError, OutputError
from core.files import lives
from core.files.lives import LIVES_FILE, append_frame, encode_record, frame_record, read_lives, stroke_paths


def padded(paths: dict, width: int = None):
    """(ids int64 (N,), control float64 (N, P, 2) NaN-padded, control_count int32 (N,)) of {id: (c, 2) points}."""
    ids = np.array(list(paths), np.int64)
    counts = np.array([len(p) for p in paths.values()], np.int32)
    width = width or (int(counts.max()) if len(counts) else 1)
    control = np.full((len(ids), width, 2), np.nan)
    for i, points in enumerate(paths.values()):
        control[i, :len(points)] = points
    return ids, control, counts


def write(path, frames: dict, width: int = None) -> list:
    """Append {frame: {id: (c, 2) points}} to a new file at ``path``; the lengths after each frame."""
    lengths, committed = [], 0
    for frame, paths in frames.items():
        committed = append_frame(path, frame, *padded(paths, width), committed)
        lengths.append(committed)
    return lengths


def on_grid(rng, count: int, scale: float = 1000.0) -> np.ndarray:
    """(count, 2) random points on the 1/16 px grid (stored exactly)."""
    return np.round(rng.uniform(-scale, scale, (count, 2)) * 16) / 16


# Stroke: the frames it lives in (inclusive) and its control point count.
HAND = {10: (1, 7, 3), 20: (3, 5, 2), 30: (1, 1, 4), 40: (7, 7, 1), 5: (2, 6, 5)}
HAND_LIVES = {10: (1, -1), 20: (3, 6), 30: (1, 2), 40: (7, -1), 5: (2, 7)}   # stroke: (birth, death)


@pytest.fixture()
def hand(tmp_path):
    """(path, {frame: {id: points}}) of frames 1..7 holding HAND's strokes, each with new points every frame."""
    rng = np.random.default_rng(3)
    frames = {frame: {sid: on_grid(rng, count) for sid, (a, b, count) in HAND.items() if a <= frame <= b}
              for frame in range(1, 8)}
    path = tmp_path / LIVES_FILE
    write(path, frames, width=6)
    return path, frames


def test_births_and_deaths_worked_out_by_hand(hand):
    path, _ = hand
    found = read_lives(path)
    assert found.frames.tolist() == list(range(1, 8))
    assert found.ids.tolist() == sorted(HAND_LIVES)
    assert {i: (b, d) for i, b, d in zip(found.ids.tolist(), found.birth.tolist(), found.death.tolist(),
                                         strict=True)} == HAND_LIVES
    assert all(a.dtype == np.int64 for a in found)


def test_paths_and_frames_come_back(hand):
    path, frames = hand
    for sid, (a, b, _) in HAND.items():
        paths = stroke_paths(path, sid)
        assert list(paths) == list(range(a, b + 1))
        for frame, points in paths.items():
            assert points.dtype == np.float64 and np.array_equal(points, frames[frame][sid])
    assert stroke_paths(path, 99) == {}
    for frame, strokes in frames.items():
        ids, control, counts = frame_record(path, frame)
        expected = dict(sorted(strokes.items()))
        assert ids.dtype == np.int64 and ids.tolist() == list(expected)
        assert counts.dtype == np.int32 and counts.tolist() == [len(p) for p in expected.values()]
        assert control.shape == (len(ids), max(counts), 2)
        assert np.array_equal(control, padded(expected, max(counts))[1], equal_nan=True)


def test_death_is_the_next_frame_in_file_order_and_a_frame_may_be_empty(tmp_path):
    rng = np.random.default_rng(4)
    path = tmp_path / LIVES_FILE
    write(path, {10: {1: on_grid(rng, 2), 2: on_grid(rng, 3)}, 20: {2: on_grid(rng, 3)}, 35: {},
                 36: {3: on_grid(rng, 1)}})
    found = read_lives(path)
    assert found.frames.tolist() == [10, 20, 35, 36]
    assert found.ids.tolist() == [1, 2, 3]
    assert found.birth.tolist() == [10, 10, 36]
    assert found.death.tolist() == [20, 35, -1]
    ids, control, counts = frame_record(path, 35)
    assert ids.shape == (0,) and control.shape == (0, 1, 2) and counts.shape == (0,)


def test_a_committed_length_reads_the_frames_before_it(hand):
    path, _ = hand
    found = read_lives(path, length=_length_after(path, 5))
    assert found.frames.tolist() == [1, 2, 3, 4, 5]
    assert dict(zip(found.ids.tolist(), found.death.tolist(), strict=True)) == {5: -1, 10: -1, 20: -1, 30: 2}
    assert list(stroke_paths(path, 10, length=_length_after(path, 2))) == [1, 2]
    with pytest.raises(InputError) as error:
        frame_record(path, 6, length=_length_after(path, 5))
    assert "frame 6" in one_sentence(str(error.value), path)
    with pytest.raises(InputError) as error:
        read_lives(path, length=_length_after(path, 5) - 1)
    assert "no record ending" in one_sentence(str(error.value), path)
    with pytest.raises(InputError) as error:
        read_lives(path, length=os.path.getsize(path) + 1)
    assert "shorter" in one_sentence(str(error.value), path)


def _length_after(path, frame: int) -> int:
    """The file's length after ``frame``'s record (from the records' offsets)."""
    index = lives.LivesFile(path)
    following = np.flatnonzero(index.frames > frame)
    return int(index.offsets[following[0]]) if len(following) else os.path.getsize(path)


def test_points_come_back_within_a_32nd_of_a_pixel(tmp_path):
    rng = np.random.default_rng(5)
    path = tmp_path / LIVES_FILE
    control = rng.uniform(-2.0 ** 23 + 1, 2.0 ** 23 - 1, (500, 6, 2))
    control[:100] = rng.uniform(-3, 3, (100, 6, 2))
    counts = rng.integers(1, 7, 500).astype(np.int32)
    control[np.arange(6)[None, :] >= counts[:, None]] = np.nan
    append_frame(path, 0, np.arange(500), control, counts, 0)
    ids, read, read_counts = frame_record(path, 0)
    assert np.array_equal(read_counts, counts)
    error = np.abs(read - control)
    assert np.array_equal(np.isnan(error), np.isnan(control))
    assert np.nanmax(error) <= 1 / 32 + 1e-9
    with pytest.raises(ValueError, match="beyond"):
        append_frame(path, 0, np.arange(1), np.full((1, 1, 2), 2.0 ** 23 + 1), np.ones(1, np.int32), 0)


def test_cutting_to_a_committed_length_gives_the_bytes_of_a_run_that_never_wrote_what_followed(tmp_path):
    rng = np.random.default_rng(6)
    frames = [{i: on_grid(rng, 1 + i % 5) for i in range(j, j + 30)} for j in range(5)]
    again = {i: on_grid(rng, 2) for i in [*range(2, 32), *range(100, 110)]}
    killed, clean = tmp_path / "killed.lives", tmp_path / "clean.lives"
    lengths = write(killed, dict(enumerate(frames[:4])))
    committed = append_frame(killed, 2, *padded(again), lengths[1])
    assert committed < lengths[3]
    committed = append_frame(killed, 3, *padded(frames[4]), committed)
    write(clean, {0: frames[0], 1: frames[1], 2: again, 3: frames[4]})
    assert killed.read_bytes() == clean.read_bytes()
    assert os.path.getsize(killed) == committed
    assert read_lives(killed).frames.tolist() == [0, 1, 2, 3]


@pytest.mark.parametrize("kept", [1, 30, 47, 48, 49, 400, -1])
def test_an_incomplete_last_record_is_ignored(hand, kept):
    path, frames = hand
    whole = path.read_bytes()
    before = read_lives(path)
    rng = np.random.default_rng(11)
    last = padded({10: np.zeros((3, 2)), **{i: on_grid(rng, 4) for i in range(77, 127)}})
    record = encode_record(8, *last)
    assert len(record) > 400
    path.write_bytes(whole + record[:kept])
    after = read_lives(path)
    assert all(np.array_equal(a, b) for a, b in zip(before, after, strict=True))
    assert list(stroke_paths(path, 10)) == list(range(1, 8))
    with pytest.raises(InputError) as error:
        frame_record(path, 8)
    one_sentence(str(error.value), path)
    with pytest.raises(InputError) as error:
        read_lives(path, length=len(whole) + len(record[:kept]))
    assert "no record ending" in one_sentence(str(error.value), path)
    append_frame(path, 8, *last, len(whole))
    assert path.read_bytes() == whole + record
    assert read_lives(path).birth[-1] == 8


@pytest.mark.parametrize("content, words", [
    (b"", "empty"),
    (b"PRLIV", "not a stroke lives file"),
    (b"\x89PNG\r\n\x1a\n" + bytes(100), "not a stroke lives file"),
    (bytes(np.random.default_rng(7).integers(0, 256, 5000, dtype=np.uint8)), "not a stroke lives file"),
    (lives.MAGIC + (2).to_bytes(4, "little"), "version 2"),
    (lives.MAGIC + (1).to_bytes(4, "little") + bytes(np.random.default_rng(8).integers(0, 256, 500,
                                                                                        dtype=np.uint8)),
     "damaged"),
])
def test_a_foreign_or_garbage_file_is_refused_naming_it(tmp_path, content, words):
    path = tmp_path / "odd.lives"
    path.write_bytes(content)
    for read in (lambda: read_lives(path), lambda: stroke_paths(path, 1), lambda: frame_record(path, 0)):
        with pytest.raises(InputError) as error:
            read()
        assert words in one_sentence(str(error.value), path)


def test_a_missing_file_or_a_folder_is_refused_naming_it(tmp_path):
    with pytest.raises(InputError) as error:
        read_lives(tmp_path / "none.lives")
    assert "does not exist" in one_sentence(str(error.value), tmp_path / "none.lives")
    with pytest.raises(InputError) as error:
        read_lives(tmp_path)
    assert "folder" in one_sentence(str(error.value), tmp_path)


@pytest.mark.parametrize("where", ["header", "ids", "points", "trailer"])
def test_a_damaged_record_is_refused(hand, where):
    path, _ = hand
    index = lives.LivesFile(path)
    start, end = int(index.offsets[3]), int(index.offsets[4])
    sections = np.cumsum(np.frombuffer(path.read_bytes()[start + 12:start + 44], "<u4"))
    at = {"header": start + 9, "ids": start + 48 + int(sections[0]) // 2,
          "points": start + 48 + int(sections[5]) - 3, "trailer": end - 2}[where]
    data = bytearray(path.read_bytes())
    data[at] ^= 0x5A
    path.write_bytes(bytes(data))
    with pytest.raises(InputError) as error:
        if where == "points":
            frame_record(path, 4)
        else:
            read_lives(path)
    assert "damaged" in one_sentence(str(error.value), path)


def test_a_stroke_born_twice_is_refused(tmp_path):
    path = tmp_path / LIVES_FILE
    write(path, {1: {4: np.zeros((1, 2))}, 2: {5: np.zeros((1, 2))}, 3: {4: np.zeros((1, 2))}})
    with pytest.raises(InputError) as error:
        read_lives(path)
    assert "stroke 4 is born twice, in frames 1 and 3" in one_sentence(str(error.value), path)


def test_a_committed_length_that_ends_no_record_is_refused_and_the_file_kept(hand):
    path, _ = hand
    whole = path.read_bytes()
    stroke = padded({1: np.zeros((1, 2))})
    for committed, words in ((len(whole) - 5, "no record ending"), (len(whole) + 1, "shorter"),
                             (5, "not a stroke lives file"), (lives.FILE_HEADER.size + 10, "no record ending")):
        with pytest.raises(InputError) as error:
            append_frame(path, 9, *stroke, committed)
        assert words in one_sentence(str(error.value), path)
        assert path.read_bytes() == whole


def test_frames_are_appended_in_increasing_order_and_bad_strokes_refused(hand):
    path, _ = hand
    whole = path.read_bytes()
    one = padded({1: np.zeros((2, 2))})
    with pytest.raises(ValueError, match="increasing"):
        append_frame(path, 7, *one, len(whole))
    ids, control, counts = padded({1: np.zeros((2, 2)), 2: np.ones((3, 2))})
    bad_control = control.copy()
    bad_control[1, 1, 0] = np.nan
    for bad in ((np.array([1, 1]), control, counts), (np.array([1, -2]), control, counts),
                (ids, control, np.array([2, 0], np.int32)), (ids, control, np.array([2, 4], np.int32)),
                (ids, bad_control, counts), (ids.astype(float), control, counts)):
        with pytest.raises(ValueError):
            append_frame(path, 8, *bad, len(whole))
    assert path.read_bytes() == whole
    control[0, 2:] = np.nan   # padding past a count is not looked at
    append_frame(path, 8, ids, control, counts, len(whole))


@pytest.mark.skipif(sys.platform == "win32", reason="file size limits are POSIX")
def test_a_failed_write_is_an_output_error_and_leaves_the_committed_file(hand):
    import resource

    path, _ = hand
    whole = path.read_bytes()
    rng = np.random.default_rng(9)
    big = padded({i: on_grid(rng, 8) for i in range(2000)})
    soft, hard = resource.getrlimit(resource.RLIMIT_FSIZE)
    resource.setrlimit(resource.RLIMIT_FSIZE, (len(whole) + 1000, hard))
    try:
        with pytest.raises(OutputError) as error:
            append_frame(path, 8, *big, len(whole))
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, (soft, hard))
    assert "too large" in one_sentence(str(error.value), path)
    assert error.value.path == path
    assert path.read_bytes() == whole


def test_a_new_file_in_a_missing_folder_is_an_output_error(tmp_path):
    path = tmp_path / "nowhere" / LIVES_FILE
    with pytest.raises(OutputError) as error:
        append_frame(path, 0, *padded({1: np.zeros((1, 2))}), 0)
    one_sentence(str(error.value), path)


def test_a_new_sequence_replaces_the_file(hand):
    path, _ = hand
    length = append_frame(path, 0, *padded({1: np.zeros((1, 2))}), 0)
    assert os.path.getsize(path) == length
    assert read_lives(path).frames.tolist() == [0]
    assert [p.name for p in path.parent.iterdir()] == [path.name]


def test_the_same_frame_gives_the_same_bytes_in_any_stroke_order(tmp_path):
    rng = np.random.default_rng(10)
    ids, control, counts = padded({int(i): on_grid(rng, int(c), 500) for i, c in
                                   zip(rng.choice(10 ** 9, 300, replace=False), rng.integers(1, 9, 300),
                                       strict=True)})
    order = rng.permutation(len(ids))
    first, second = tmp_path / "a.lives", tmp_path / "b.lives"
    append_frame(first, 3, ids, control, counts, 0)
    append_frame(second, 3, ids[order], control[order], counts[order], 0)
    assert first.read_bytes() == second.read_bytes()
    assert encode_record(3, ids, control, counts) == encode_record(3, ids, control, counts)


def moving_strokes(frames: int, strokes: int = 20_000, seed: int = 1):
    """[(frame, ids, control, control_count)] of a realistic painted sequence on a 1920 x 1080 frame: ``strokes``
    strokes of 2 to 8 control points spaced by a brush radius of 2 to 16 px (mostly small) along a smooth
    orientation field, ids in random order of position, every point moving 1.5 to 4.5 px a frame with a smooth
    motion field, 2 % of the strokes dying each frame and as many born."""
    rng = np.random.default_rng(seed)

    def born(count: int, first_id: int):
        step = rng.choice([2.0, 4.0, 8.0, 16.0], p=[0.5, 0.3, 0.15, 0.05], size=count)
        counts = rng.integers(2, 9, count).astype(np.int32)
        control = np.empty((count, 8, 2))
        control[:, 0] = rng.uniform([0, 0], [1920, 1080], (count, 2))
        for j in range(1, 8):
            x, y = control[:, j - 1, 0], control[:, j - 1, 1]
            angle = np.sin(x / 200) + 2 * np.cos(y / 150) + rng.normal(0, 0.1, count)
            control[:, j] = np.stack([x + step * np.cos(angle), y + step * np.sin(angle)], axis=1)
        control[np.arange(8)[None, :] >= counts[:, None]] = np.nan
        return first_id + np.arange(count, dtype=np.int64), control, counts

    ids, control, counts = born(strokes, 0)
    sequence = []
    for frame in range(frames):
        order = rng.permutation(len(ids))
        sequence.append((frame, ids[order], control[order], counts[order]))
        x, y = control[..., 0], control[..., 1]
        control = np.stack([x + 3 + 1.5 * np.sin(y / 300 + frame / 10), y + 1 + 1.5 * np.cos(x / 400)], axis=-1)
        kept = rng.random(len(ids)) > 0.02
        new = born(int(strokes - kept.sum()), int(ids.max()) + 1)
        ids, control, counts = (np.concatenate([a[kept], b]) for a, b in zip((ids, control, counts), new,
                                                                              strict=True))
    return sequence


def test_a_moving_sequence_takes_under_12_bytes_per_stroke_per_frame(tmp_path):
    path = tmp_path / LIVES_FILE
    sequence = moving_strokes(3)
    committed = 0
    for frame, ids, control, counts in sequence:
        committed = append_frame(path, frame, ids, control, counts, committed)
    per_stroke = (committed - lives.FILE_HEADER.size) / sum(len(ids) for _, ids, _, _ in sequence)
    assert per_stroke < 12.0, per_stroke
    frame, ids, control, counts = sequence[-1]
    order = np.argsort(ids)
    read = frame_record(path, frame)
    assert np.array_equal(read.ids, ids[order]) and np.array_equal(read.control_count, counts[order])
    assert np.nanmax(np.abs(read.control - control[order])) <= 1 / 32 + 1e-9
    deep = int(np.flatnonzero((read.control_count == 8) & (read.ids < 20_000))[-1])   # a stroke of frame 0
    paths = stroke_paths(path, int(read.ids[deep]))
    assert np.array_equal(paths[frame], read.control[deep]) and len(paths) == len(sequence)


def test_a_record_whose_stroke_count_disagrees_with_its_sections_is_refused(tmp_path):
    path = tmp_path / LIVES_FILE
    committed = append_frame(path, 0, *padded({1: np.zeros((2, 2)), 2: np.ones((1, 2))}), 0)
    data = bytearray(path.read_bytes())
    header = bytearray(data[12:12 + lives.RECORD_HEADER.size])
    header[8:12] = (3).to_bytes(4, "little")
    data[12:12 + lives.RECORD_HEADER.size + 4] = bytes(header) + zlib.crc32(header).to_bytes(4, "little")
    path.write_bytes(bytes(data))
    assert os.path.getsize(path) == committed
    for read in (lambda: read_lives(path), lambda: frame_record(path, 0)):
        with pytest.raises(InputError) as error:
            read()
        assert "does not decompress to its values" in one_sentence(str(error.value), path)


def test_check_reads_every_record_whole_so_damaged_points_in_an_early_record_are_found(hand):
    path, frames = hand
    index = lives.LivesFile(path)
    index.check()
    assert index.ends().tolist() == _lengths(path, frames)
    assert index.record_bytes(1) == encode_record(2, *padded(frames[2], 6))
    start = int(index.offsets[1])
    sections = np.cumsum(np.frombuffer(path.read_bytes()[start + 12:start + 44], "<u4"))
    data = bytearray(path.read_bytes())
    data[start + 48 + int(sections[5]) - 3] ^= 0x5A
    path.write_bytes(bytes(data))
    lives.LivesFile(path).lives()        # the ids alone still read
    with pytest.raises(InputError) as error:
        lives.LivesFile(path).check()
    assert "the record of frame 2 at byte" in one_sentence(str(error.value), path)


def _lengths(path, frames: dict) -> list:
    """The file's length after each of ``frames`` (written again into a sibling file)."""
    return write(path.with_name("again.lives"), frames, width=6)


def test_cut_lives_cuts_to_a_committed_length_and_removes_the_file_at_0(hand):
    path, frames = hand
    lengths = _lengths(path, frames)
    assert not lives.cut_lives(path, lengths[-1])
    assert lives.cut_lives(path, lengths[2])
    assert lives.LivesFile(path).frames.tolist() == [1, 2, 3]
    assert lives.cut_lives(path, 0) and not path.exists()
    assert not lives.cut_lives(path, 0)
