"""The lives of a painted sequence's strokes: one file recording, frame after frame, which strokes are alive and
their control points, so each stroke's birth, death and path per frame can be read back (ALGORITHM §9).

``core sequence`` appends one record per painted frame with ``append_frame`` and commits the file's length it
returns; the next append first cuts the file to the committed length, so a record appended by a run killed before
its frame was committed is dropped. ``read_lives`` gives every stroke's birth and death frame, ``stroke_paths``
one stroke's control points frame by frame and ``frame_record`` one frame's strokes (``LivesFile`` indexes a file
once for several of these). Reading errors raise ``InputError`` and writing errors ``OutputError``, each one
sentence naming the file.

The file (``strokes.lives``)
----------------------------
All integers are little-endian. The file is a 12-byte header followed by one record per frame, in the order the
frames were appended (frame numbers strictly increasing)::

    header   8 bytes   magic b"PRLIVES\\0" (50 52 4C 49 56 45 53 00)
             4 bytes   format version, uint32 = 1

    record   8 bytes   frame number, int64
             4 bytes   N, the frame's stroke count, uint32
            32 bytes   8 x uint32: the byte length of each of the 8 sections below, as stored (compressed)
             4 bytes   CRC-32 (zlib's crc32, as PNG's) of the 44 bytes above, uint32
           ... bytes   the 8 sections, back to back
             4 bytes   the record's length in bytes, uint32 = 52 + the sections' lengths

Each section is one zlib stream (RFC 1950) of an array of n unsigned integers of w bytes, stored byte-plane by
byte-plane: the lowest byte of every value in order, then the next byte of every value, and so on (plane k holds
byte k of value i at position k * n + i), which lets zlib see the many zero high bytes of small numbers. A
section's uncompressed length is exactly n * w bytes. The strokes are stored in ascending id order; x and y are in
pixels (x right, y down), quantised to q = round(16 v) (round half to even): 1/16 px steps, so a read coordinate
is within 1/32 px of the one written; |q| <= 2^27, that is coordinates within +-2^23 px (2^27 / 16). A stroke of
count c keeps only its c control points (no padding). Signed values are zigzag-coded into uint32:
z = 2 v for v >= 0, -2 v - 1 for v < 0.

    section  w  n              values
    0        8  N              id gaps: id[0], then id[i] - id[i - 1] - 1 (ids are >= 0 and unique)
    1        4  N              control point count c[i] >= 1
    2, 3     4  N              first point, x then y: q[i, 0] - q[i - 1, 0] (q[-1, 0] = 0), zigzag
    4, 5     4  N2             first step, x then y, of each stroke with c >= 2: q[i, 1] - q[i, 0], zigzag
    6, 7     4  M              bends, x then y, stroke by stroke and point by point for 2 <= j < c[i]:
                               (q[i, j] - q[i, j - 1]) - (q[i, j - 1] - q[i, j - 2]), zigzag

N2 is the number of strokes with c >= 2 and M the sum of max(c - 2, 0). A stroke's points follow from its first
point, its first step and its bends by running sums. The same frame (same ids, counts and quantised points, in any
stroke order) gives the same bytes with the same zlib library (level ``COMPRESSION``).

A record is complete when all its bytes lie within the part of the file read: when the file is read whole, an
incomplete last record (a run killed while appending it) is ignored; when a length is given, the records must end
exactly there. A record whose header fails its CRC, whose length field disagrees with its sections, or whose
sections do not decompress to their lengths is damaged: the file is refused. A stroke is alive from the first
record that holds it to the last one in a row; a stroke born twice (absent from a frame between two that hold it)
makes the file invalid.

Size and speed: 20,000 strokes of 2 to 8 control points spaced by a brush radius of 2 to 16 px along a smooth
field on a 1920 x 1080 frame, moving 1.5 to 4.5 px a frame, ids in random order of position (the test's
``moving_strokes``), take 10.8 bytes per stroke per frame (216 kB a frame); zlib takes 4.5 ms of the 13 ms a
record takes to make on one core. Level 6 makes the records 4 % smaller for 2.3 times zlib's time. Reading a
frame's strokes back takes about 12 ms; ``read_lives`` about 1.3 ms a frame (it decompresses the ids only).
"""

from __future__ import annotations

import os
import pathlib
import struct
import zlib
from typing import Dict, Iterator, List, NamedTuple, Optional, Tuple

import numpy as np

from ..errors import InputError, OutputError, plain_cause, reading_error
from .image_files import PathLike
from .staging import fsync_folder
from .writing import atomic_path

LIVES_FILE = "strokes.lives"
"""The lives file's name in a sequence's output folder."""

MAGIC = b"PRLIVES\0"
VERSION = 1
FILE_HEADER = struct.Struct("<8sI")
RECORD_HEADER = struct.Struct("<qI8I")
CHECKED_HEADER_BYTES = RECORD_HEADER.size + 4   # the record header and its CRC-32
TRAILER = struct.Struct("<I")
RECORD_OVERHEAD = CHECKED_HEADER_BYTES + TRAILER.size   # 52 bytes besides the sections

SECTIONS = 8
SUBPIXELS = 16
"""Control points are stored in 1/SUBPIXELS px steps."""
MAX_QUANTISED = 2 ** 27
"""The largest |round(16 v)| stored: coordinates within +-2^23 px."""

COMPRESSION = 1
"""zlib level of the sections: level 1 compresses a 20,000-stroke frame in 4.5 ms; level 6 saves 4 % in 2.3 times
the time."""


class Lives(NamedTuple):
    """The strokes of a lives file and when each lived.

    frames: int64 (F,) frame numbers in file order (increasing).
    ids: int64 (S,) every stroke that lived, ascending.
    birth: int64 (S,) the first frame the stroke appears in.
    death: int64 (S,) the frame after its last appearance (the next frame number in file order); -1 when it is
           alive in the last frame.
    """

    frames: np.ndarray
    ids: np.ndarray
    birth: np.ndarray
    death: np.ndarray


class FrameRecord(NamedTuple):
    """One frame's strokes in ascending id order.

    ids: int64 (N,). control: float64 (N, P, 2) (x, y) px with P the largest count (1 when N = 0), stroke i's
    points control[i, :control_count[i]], the rest NaN. control_count: int32 (N,) >= 1.
    """

    ids: np.ndarray
    control: np.ndarray
    control_count: np.ndarray


# --- writing -----------------------------------------------------------------------------------------------------

def append_frame(path: PathLike, frame: int, ids: np.ndarray, control: np.ndarray, control_count: np.ndarray,
                 committed_bytes: int) -> int:
    """Append one frame's record to the lives file at ``path`` and return the file's length in bytes after it.

    The file is first cut to ``committed_bytes`` (the length after the last frame the caller committed; 0 for a
    new sequence: the file is then created, or replaced, through a temporary file), so a record appended by a run
    that was killed before its frame was committed is dropped. ``frame`` must be greater than the committed last
    frame's. ids: int64 (N,) the frame's strokes' identities (unique within a frame, any order, >= 0). control:
    float64 (N, P, 2) (x, y) px, NaN-padded; stroke i's path is control[i, :control_count[i]], finite, within
    +-2^23 px. control_count: int32 (N,), 1 <= count <= P. The record's bytes are flushed (os.fsync) before
    returning. Bad arguments raise ValueError; a file whose committed part is not a lives file ending in a record
    at ``committed_bytes`` raises InputError; a failed write raises OutputError (the file is cut back to
    ``committed_bytes`` when it can be).
    """
    path = pathlib.Path(path)
    record = encode_record(frame, ids, control, control_count)
    committed_bytes = int(committed_bytes)
    if committed_bytes < 0:
        raise ValueError(f"committed_bytes must be >= 0, got {committed_bytes}.")
    if committed_bytes == 0:
        return _create(path, FILE_HEADER.pack(MAGIC, VERSION) + record)
    return _append(path, record, int(frame), committed_bytes)


def _create(path: pathlib.Path, data: bytes) -> int:
    """Write ``data`` as the whole file ``path`` (a temporary file, flushed, renamed over it); its length."""
    with atomic_path(path) as temp:
        try:
            with open(temp, "wb") as f:
                f.write(data)
                f.flush()
                os.fsync(f.fileno())
        except OSError as exc:
            raise _output_error(path, exc) from exc
    fsync_folder(path.parent)
    return len(data)


def _append(path: pathlib.Path, record: bytes, frame: int, committed_bytes: int) -> int:
    """Cut ``path`` to ``committed_bytes``, check the committed part ends in a record of a frame before ``frame``,
    append ``record`` and flush it; the file's length after it."""
    try:
        f = open(path, "r+b")
    except OSError as exc:
        raise _output_error(path, exc) from exc
    with f:
        size = os.fstat(f.fileno()).st_size
        if size < committed_bytes:
            raise InputError(f"The lives file {path} is {size} bytes, shorter than the {committed_bytes} bytes "
                             f"committed.")
        _check_file_header(path, _read_at(path, f, 0, min(committed_bytes, FILE_HEADER.size)), committed_bytes)
        last = _last_frame(path, f, committed_bytes)
        if last is not None and frame <= last:
            raise ValueError(f"Frame {frame} cannot follow frame {last} in {path}: frames are appended in "
                             f"increasing order.")
        try:
            f.truncate(committed_bytes)
            f.seek(committed_bytes)
            f.write(record)
            f.flush()
            os.fsync(f.fileno())
            return f.tell()
        except OSError as exc:
            _cut_quietly(f, committed_bytes)
            raise _output_error(path, exc) from exc


def cut_lives(path: PathLike, length: int) -> bool:
    """Cut the lives file at ``path`` back to ``length`` bytes (a committed length; 0 removes the file, as no frame
    is committed); True when it was longer and is cut. Failures are left to the next append, which cuts the file
    first: the result is then False."""
    path = pathlib.Path(path)
    try:
        size = path.stat().st_size
        if size <= length:
            return False
        if length == 0:
            path.unlink()
        else:
            os.truncate(path, length)
        fsync_folder(path.parent)
    except OSError:
        return False
    return True


def _cut_quietly(f, length: int) -> None:
    """Cut the open file ``f`` back to ``length`` bytes after a failed append; a failure here changes nothing the
    next append does not (it cuts the file first)."""
    try:
        f.truncate(length)
    except OSError:
        pass


def _output_error(path: pathlib.Path, exc: OSError) -> OutputError:
    """The OutputError of a failed write of ``path``."""
    cause = plain_cause(exc, folder=path.parent)
    return OutputError(f"Cannot write {path}: {cause}.", path=path, cause=cause)


def _last_frame(path: pathlib.Path, f, end: int) -> Optional[int]:
    """The frame number of the record that ends at byte ``end`` of the open lives file ``f``; None when ``end``
    is the file header's end. InputError when no record ends there."""
    if end == FILE_HEADER.size:
        return None
    wrong = InputError(f"The lives file {path} has no record ending at byte {end}, the length committed.")
    if end < FILE_HEADER.size + RECORD_OVERHEAD:
        raise wrong
    (length,) = TRAILER.unpack(_read_at(path, f, end - TRAILER.size, TRAILER.size))
    start = end - length
    if length < RECORD_OVERHEAD or start < FILE_HEADER.size:
        raise wrong
    header = _record_header(_read_at(path, f, start, CHECKED_HEADER_BYTES))
    if header is None or header.length != length:
        raise wrong
    return header.frame


def encode_record(frame: int, ids: np.ndarray, control: np.ndarray, control_count: np.ndarray) -> bytes:
    """The record of one frame (the module's format): header, 8 sections and trailer. ValueError on bad input."""
    frame, ids, quantised, counts = _checked(frame, ids, control, control_count)
    order = np.argsort(ids)
    ids, quantised, counts = ids[order], quantised[order], counts[order]
    if np.any(ids[1:] == ids[:-1]):
        raise ValueError(f"Stroke ids must be unique within frame {frame}.")
    sections = [zlib.compress(_planes(values), COMPRESSION)
                for values in _section_values(ids, quantised, counts)]
    lengths = [len(s) for s in sections]
    length = RECORD_OVERHEAD + sum(lengths)
    if length >= 2 ** 32:
        raise ValueError(f"Frame {frame}'s record of {len(ids)} strokes would be {length} bytes, beyond the 4 GiB "
                         f"a record may hold.")
    header = RECORD_HEADER.pack(frame, len(ids), *lengths)
    return b"".join([header, struct.pack("<I", zlib.crc32(header)), *sections, TRAILER.pack(length)])


def _checked(frame, ids, control, control_count) -> Tuple[int, np.ndarray, np.ndarray, np.ndarray]:
    """(frame, ids int64 (N,), quantised points int64 (N, P, 2) with 0 past each count, counts int64 (N,)) of
    ``append_frame``'s arguments; ValueError naming what is wrong."""
    frame = int(frame)
    if not -2 ** 63 <= frame < 2 ** 63:
        raise ValueError(f"Frame number {frame} does not fit in 64 bits.")
    ids = np.asarray(ids)
    control = np.asarray(control, np.float64)
    counts = np.asarray(control_count)
    if ids.ndim != 1 or not np.issubdtype(ids.dtype, np.integer):
        raise ValueError(f"ids must be a 1-D integer array, got {ids.dtype} of shape {ids.shape}.")
    n = len(ids)
    if control.ndim != 3 or control.shape[0] != n or control.shape[2] != 2 or control.shape[1] < 1:
        raise ValueError(f"control must be ({n}, P, 2) with P >= 1, got shape {control.shape}.")
    if counts.shape != (n,) or not np.issubdtype(counts.dtype, np.integer):
        raise ValueError(f"control_count must be ({n},) integers, got {counts.dtype} of shape {counts.shape}.")
    ids, counts = ids.astype(np.int64), counts.astype(np.int64)
    if n and ids.min() < 0:
        raise ValueError(f"Stroke ids must be >= 0, got {ids.min()}.")
    points = control.shape[1]
    if n and (counts.min() < 1 or counts.max() > points):
        raise ValueError(f"control_count must be within 1 .. {points}, got {counts.min()} .. {counts.max()}.")
    kept = np.arange(points)[None, :] < counts[:, None]
    scaled = control * SUBPIXELS
    if not np.all(np.isfinite(scaled[kept])):
        raise ValueError(f"Frame {frame} has a NaN or infinite control point among those counted.")
    quantised = np.where(kept[:, :, None], np.rint(scaled), 0.0)
    if n and np.abs(quantised).max() > MAX_QUANTISED:
        raise ValueError(f"Frame {frame} has a control point beyond +-{MAX_QUANTISED // SUBPIXELS} px.")
    return frame, ids, quantised.astype(np.int64), counts


def _section_values(ids: np.ndarray, quantised: np.ndarray, counts: np.ndarray) -> List[np.ndarray]:
    """The 8 sections' values (uint64 id gaps, then uint32) of strokes sorted by id: ids int64 (N,), quantised
    int64 (N, P, 2) with 0 past each count, counts int64 (N,)."""
    quantised = np.pad(quantised, ((0, 0), (0, max(0, 3 - quantised.shape[1])), (0, 0)))   # room for a bend
    gaps = np.diff(ids, prepend=-1) - 1
    first = np.diff(quantised[:, 0], axis=0, prepend=np.zeros((1, 2), np.int64))
    steps = np.diff(quantised, axis=1)                       # (N, P - 1, 2)
    first_step = steps[counts >= 2, 0]
    bent = np.arange(2, quantised.shape[1])[None, :] < counts[:, None]
    bends = np.diff(steps, axis=1)[bent]                    # (M, 2), stroke by stroke, point by point
    return [gaps.astype("<u8"), counts.astype("<u4"),
            _zigzag(first[:, 0]), _zigzag(first[:, 1]),
            _zigzag(first_step[:, 0]), _zigzag(first_step[:, 1]),
            _zigzag(bends[:, 0]), _zigzag(bends[:, 1])]


def _zigzag(values: np.ndarray) -> np.ndarray:
    """int64 values within +-2^31 -> uint32: 2 v for v >= 0, -2 v - 1 for v < 0."""
    values = values.astype(np.int64)
    return ((values << 1) ^ (values >> 63)).astype("<u4")


def _unzigzag(codes: np.ndarray) -> np.ndarray:
    """uint32 zigzag codes -> int64 values."""
    codes = codes.astype(np.int64)
    return (codes >> 1) ^ -(codes & 1)


def _planes(values: np.ndarray) -> bytes:
    """The bytes of little-endian unsigned ``values`` (n,), byte-plane by byte-plane (byte k of value i at
    k * n + i)."""
    values = np.ascontiguousarray(values)
    return values.view(np.uint8).reshape(len(values), values.itemsize).T.tobytes()


# --- reading -----------------------------------------------------------------------------------------------------

class RecordHeader(NamedTuple):
    """A record's header: its frame number, stroke count, the sections' stored lengths and the record's length."""

    frame: int
    count: int
    sections: Tuple[int, ...]
    length: int


def _record_header(data: bytes) -> Optional[RecordHeader]:
    """The record header of the CHECKED_HEADER_BYTES ``data``; None when it fails its CRC-32."""
    (crc,) = struct.unpack_from("<I", data, RECORD_HEADER.size)
    if zlib.crc32(data[:RECORD_HEADER.size]) != crc:
        return None
    frame, count, *sections = RECORD_HEADER.unpack_from(data)
    return RecordHeader(frame, count, tuple(sections), RECORD_OVERHEAD + sum(sections))


class LivesFile:
    """A lives file indexed: where each frame's record lies; records are read on demand.

    ``length``: read only the file's first ``length`` bytes, which must end at a record's end (a committed
    length); None reads the whole file and ignores an incomplete last record. The file is opened anew by each
    method. frames: int64 (F,) frame numbers in file order; offsets: int64 (F,) each record's first byte.
    """

    def __init__(self, path: PathLike, length: Optional[int] = None):
        self.path = pathlib.Path(path)
        self._headers: List[RecordHeader] = []
        offsets = []
        with self._open() as f:
            for offset, header in self._scan(f, length):
                offsets.append(offset)
                self._headers.append(header)
        self.frames = np.array([h.frame for h in self._headers], np.int64)
        self.offsets = np.array(offsets, np.int64)

    def _open(self):
        """The file opened for reading; InputError when it cannot be."""
        try:
            return open(self.path, "rb")
        except OSError as exc:
            raise reading_error(f"The lives file {self.path}", exc, "a file") from None

    def _scan(self, f, length: Optional[int]) -> Iterator[Tuple[int, RecordHeader]]:
        """(offset, header) of each complete record of the open file ``f`` within ``length`` bytes."""
        path = self.path
        size = os.fstat(f.fileno()).st_size
        if length is not None:
            length = int(length)
            if length > size:
                raise InputError(f"The lives file {path} is {size} bytes, shorter than the {length} bytes to read.")
        end = size if length is None else length
        _check_file_header(path, _read_at(path, f, 0, min(end, FILE_HEADER.size)), end)
        offset, last = FILE_HEADER.size, None
        while offset < end:
            if end - offset < CHECKED_HEADER_BYTES:
                break
            header = _record_header(_read_at(path, f, offset, CHECKED_HEADER_BYTES))
            if header is None:
                raise InputError(f"The lives file {path} is damaged: the record at byte {offset} fails its "
                                 f"checksum.")
            if offset + header.length > end:
                break
            (trailer,) = TRAILER.unpack(_read_at(path, f, offset + header.length - TRAILER.size, TRAILER.size))
            if trailer != header.length:
                raise InputError(f"The lives file {path} is damaged: the record of frame {header.frame} at byte "
                                 f"{offset} ends with a wrong length.")
            if last is not None and header.frame <= last:
                raise InputError(f"The lives file {path} is damaged: frame {header.frame} at byte {offset} "
                                 f"follows frame {last}.")
            yield offset, header
            offset, last = offset + header.length, header.frame
        if length is not None and offset != length:
            raise InputError(f"The lives file {path} has no record ending at byte {length}: the record at byte "
                             f"{offset} runs past it.")

    def _sections(self, f, index: int, stop: int = SECTIONS) -> List[bytes]:
        """The stored bytes of sections 0 .. stop - 1 of record ``index`` of the open file ``f``."""
        header = self._headers[index]
        data = _read_at(self.path, f, int(self.offsets[index]) + CHECKED_HEADER_BYTES, sum(header.sections[:stop]))
        bounds = np.cumsum((0,) + header.sections[:stop])
        return [data[a:b] for a, b in zip(bounds[:-1], bounds[1:], strict=True)]

    def _ids(self, f, index: int, stored: Optional[bytes] = None) -> np.ndarray:
        """int64 (N,) ascending: the stroke ids of record ``index`` (from its stored section 0 when given)."""
        if stored is None:
            (stored,) = self._sections(f, index, 1)
        gaps = self._values(stored, index, "<u8", self._headers[index].count)
        ids = (np.cumsum(gaps + np.uint64(1)) - np.uint64(1)).view(np.int64)
        if len(ids) and (ids[0] < 0 or np.any(ids[1:] <= ids[:-1])):
            raise self._damaged(index, "holds stroke ids out of order or beyond 2^63 - 1")
        return ids

    def _values(self, stored: bytes, index: int, dtype: str, count: int) -> np.ndarray:
        """The ``count`` values of ``dtype`` of one stored section of record ``index``."""
        width = np.dtype(dtype).itemsize
        try:
            inflater = zlib.decompressobj()
            data = inflater.decompress(stored, count * width + 1)
            complete = inflater.eof and not inflater.unused_data and len(data) == count * width
        except zlib.error:
            complete = False
        if not complete:
            raise self._damaged(index, "has a section that does not decompress to its values")
        planes = np.frombuffer(data, np.uint8).reshape(width, count)
        return np.ascontiguousarray(planes.T).view(dtype).reshape(count)

    def _damaged(self, index: int, problem: str) -> InputError:
        """The InputError of record ``index`` with ``problem``."""
        return InputError(f"The lives file {self.path} is damaged: the record of frame {self.frames[index]} at "
                          f"byte {self.offsets[index]} {problem}.")

    def _decoded(self, f, index: int) -> Tuple[np.ndarray, ...]:
        """Record ``index`` of the open file ``f`` as its stored values: ids int64 (N,), counts int64 (N,), first
        point deltas (N, 2), first steps (N2, 2) and bends (M, 2), int64 in 1/SUBPIXELS px."""
        n = self._headers[index].count
        stored = self._sections(f, index)
        ids = self._ids(f, index, stored[0])
        counts = self._values(stored[1], index, "<u4", n).astype(np.int64)
        if n and counts.min() < 1:
            raise self._damaged(index, "has a stroke of no control points")
        stepped = int(np.count_nonzero(counts >= 2))
        bent = int(np.maximum(counts - 2, 0).sum())
        first, step, bend = (np.stack([_unzigzag(self._values(stored[k], index, "<u4", size)) for k in (a, a + 1)],
                                      axis=1) for a, size in ((2, n), (4, stepped), (6, bent)))
        return ids, counts, first, step, bend

    def _record(self, f, index: int) -> FrameRecord:
        """Record ``index`` of the open file ``f`` decoded."""
        ids, counts, first, step, bend = self._decoded(f, index)
        return FrameRecord(ids, _points(counts, first, step, bend), counts.astype(np.int32))

    def _index(self, frame: int) -> int:
        """The index of ``frame``'s record; InputError when the file holds none."""
        found = np.flatnonzero(self.frames == frame)
        if len(found) == 0:
            raise InputError(f"The lives file {self.path} holds no record of frame {frame}.")
        return int(found[0])

    def record(self, frame: int) -> FrameRecord:
        """Frame ``frame``'s strokes (FrameRecord, in ascending id order); InputError when it has no record."""
        index = self._index(frame)
        with self._open() as f:
            return self._record(f, index)

    def lives(self) -> Lives:
        """Every stroke's birth and death (Lives); InputError when a stroke is born twice."""
        alive = np.zeros(0, np.int64)
        born, born_at, died, died_at = [], [], [], []
        with self._open() as f:
            for index, frame in enumerate(self.frames.tolist()):
                ids = self._ids(f, index)
                new, gone = ~_within(ids, alive), ~_within(alive, ids)
                born.append(ids[new])
                born_at.append(np.full(int(new.sum()), frame, np.int64))
                died.append(alive[gone])
                died_at.append(np.full(int(gone.sum()), frame, np.int64))
                alive = ids
        ids, birth = np.concatenate([np.zeros(0, np.int64), *born]), np.concatenate([np.zeros(0, np.int64), *born_at])
        order = np.argsort(ids, kind="stable")
        ids, birth = ids[order], birth[order]
        twice = np.flatnonzero(ids[1:] == ids[:-1])
        if len(twice):
            k = int(twice[0])
            raise InputError(f"The lives file {self.path} is invalid: stroke {ids[k]} is born twice, in frames "
                             f"{birth[k]} and {birth[k + 1]}.")
        death = np.full(len(ids), -1, np.int64)
        death[np.searchsorted(ids, np.concatenate([np.zeros(0, np.int64), *died]))] = np.concatenate(
            [np.zeros(0, np.int64), *died_at])
        return Lives(self.frames.copy(), ids, birth, death)

    def ends(self) -> np.ndarray:
        """int64 (F,): the byte after each record (the file's length once that record is the last)."""
        return self.offsets + np.array([h.length for h in self._headers], np.int64)

    def record_bytes(self, index: int) -> bytes:
        """The stored bytes of record ``index`` (0-based, file order), header to trailer."""
        with self._open() as f:
            return _read_at(self.path, f, int(self.offsets[index]), self._headers[index].length)

    def check(self) -> None:
        """InputError (one sentence naming the file and the record) unless every record decodes whole: each
        section decompresses to its length (zlib's Adler-32 checks its bytes), its ids ascend, every stroke has
        control points, and no stroke is born twice."""
        with self._open() as f:
            for index in range(len(self._headers)):
                self._decoded(f, index)
        self.lives()

    def stroke_paths(self, stroke_id: int) -> Dict[int, np.ndarray]:
        """{frame: float64 (c, 2) control points (x, y) px} of stroke ``stroke_id`` in every frame it lives in, in
        frame order; empty when it never lived."""
        paths: Dict[int, np.ndarray] = {}
        with self._open() as f:
            for index, frame in enumerate(self.frames.tolist()):
                ids = self._ids(f, index)
                at = int(np.searchsorted(ids, stroke_id))
                if at < len(ids) and ids[at] == stroke_id:
                    paths[frame] = _stroke_points(at, *self._decoded(f, index)[1:])
        return paths


def _within(values: np.ndarray, sorted_set: np.ndarray) -> np.ndarray:
    """bool (n,): which of ``values`` (n,) are in the ascending ``sorted_set``."""
    if len(sorted_set) == 0:
        return np.zeros(len(values), bool)
    at = np.minimum(np.searchsorted(sorted_set, values), len(sorted_set) - 1)
    return sorted_set[at] == values


def _points(counts: np.ndarray, first: np.ndarray, step: np.ndarray, bend: np.ndarray) -> np.ndarray:
    """float64 (N, P, 2) control points (x, y) px, NaN past each count, P = max(counts) (1 when N = 0), of N
    strokes from their counts (N,), first-point deltas (N, 2), first steps (N2, 2) and bends (M, 2), all in
    1/SUBPIXELS px."""
    n = len(counts)
    points = int(counts.max()) if n else 1
    steps = np.zeros((n, max(points - 1, 0), 2), np.int64)
    if points >= 2:
        steps[counts >= 2, 0] = step
        steps[:, 1:][np.arange(2, points)[None, :] < counts[:, None]] = bend
    steps = np.cumsum(steps, axis=1)
    starts = np.cumsum(first, axis=0)
    quantised = starts[:, None, :] + np.concatenate([np.zeros((n, 1, 2), np.int64), np.cumsum(steps, axis=1)], 1)
    control = quantised / SUBPIXELS
    control[np.arange(points)[None, :] >= counts[:, None]] = np.nan
    return control


def _stroke_points(at: int, counts: np.ndarray, first: np.ndarray, step: np.ndarray, bend: np.ndarray) -> np.ndarray:
    """float64 (c, 2) control points (x, y) px of stroke ``at`` alone, from the record's values as ``_points``
    takes them."""
    count = int(counts[at])
    before = counts[:at]
    stroke_steps = np.zeros((count - 1, 2), np.int64)
    if count >= 2:
        stroke_steps[0] = step[np.count_nonzero(before >= 2)]
        bends_before = int(np.maximum(before - 2, 0).sum())
        stroke_steps[1:] = bend[bends_before:bends_before + count - 2]
    offsets = np.cumsum(np.cumsum(stroke_steps, axis=0), axis=0)
    quantised = first[:at + 1].sum(axis=0) + np.concatenate([np.zeros((1, 2), np.int64), offsets])
    return quantised / SUBPIXELS


def _read_at(path: pathlib.Path, f, offset: int, size: int) -> bytes:
    """``size`` bytes of the open file ``f`` from ``offset``; InputError when they cannot be read."""
    try:
        f.seek(offset)
        data = f.read(size)
    except OSError as exc:
        raise InputError(f"The lives file {path} cannot be read: {plain_cause(exc)}.") from None
    if len(data) != size:
        raise InputError(f"The lives file {path} changed while it was read: byte {offset + len(data)} is missing.")
    return data


def _check_file_header(path: pathlib.Path, data: bytes, size: int) -> None:
    """InputError unless ``data`` (the first min(size, 12) bytes of a file of ``size`` bytes) is a lives file's
    header of this version."""
    if size == 0:
        raise InputError(f"The lives file {path} is empty (0 bytes).")
    if len(data) < FILE_HEADER.size or not data.startswith(MAGIC):
        raise InputError(f"The lives file {path} is not a stroke lives file: it does not start with the mark "
                         f"{MAGIC.rstrip(bytes(1)).decode()} and a format version.")
    _, version = FILE_HEADER.unpack(data)
    if version != VERSION:
        raise InputError(f"The lives file {path} has format version {version}; this version of Paint Relief reads "
                         f"version {VERSION}.")


def read_lives(path: PathLike, length: Optional[int] = None) -> Lives:
    """Every stroke's birth and death in the lives file at ``path`` (Lives); ``length``: read only its first
    ``length`` bytes (a committed length). InputError when the file is missing, not a lives file or damaged."""
    return LivesFile(path, length).lives()


def stroke_paths(path: PathLike, stroke_id: int, length: Optional[int] = None) -> Dict[int, np.ndarray]:
    """{frame: float64 (c, 2) control points (x, y) px} of stroke ``stroke_id`` in each frame it lives in."""
    return LivesFile(path, length).stroke_paths(stroke_id)


def frame_record(path: PathLike, frame: int, length: Optional[int] = None) -> FrameRecord:
    """Frame ``frame``'s strokes in ascending id order: (ids int64 (N,), control float64 (N, P, 2) NaN-padded,
    control_count int32 (N,)); InputError when the file holds no record of it."""
    return LivesFile(path, length).record(frame)
