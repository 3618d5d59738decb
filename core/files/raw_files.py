"""Uncompressed image files held in memory as their own bytes, changed pixel by pixel and written whole: the
time-lapse's frames.

A time-lapse writes a hundred frames of four files each, which differ from
one frame to the next only where the strokes between them fell. These files
are kept as the bytes of the simplest valid file of each format, so a frame
is made by storing the pixels that changed and written by one call, no
encoder run over the whole picture:

- ``HalfPlanes``: the scanlines of an OpenEXR 2 single-part scanline file of
  half floats without compression (one scanline a chunk: its y, its byte
  count, then each channel's W halves, channels in alphabetical order);
- ``StoredRows``: the rows of an 8-bit RGB PNG (each row its filter byte,
  None, then its pixels), written as a zlib stream of stored blocks.

OpenImageIO, Blender and every reader of the formats read them; they are
larger than compressed ones (2 bytes a channel a pixel for the EXRs, 3 a
pixel for the PNG). Each file is written through ``writing.atomic_path`` (a
temporary name, then renamed); a failure raises OutputError naming the file.
"""

from __future__ import annotations

import os
import struct
import zlib
from pathlib import Path
from typing import Dict, Sequence

import numpy as np

from ..errors import OutputError, plain_cause
from .image_files import CHANNEL_ORDER_ATTR
from .writing import _attribute_value, atomic_path, write_failure_cause

EXR_MAGIC = 20000630
"""The first four bytes of every OpenEXR file, as a little-endian int32."""

EXR_LONG_NAMES = 0x400
"""The version field's flag for attribute names longer than 31 bytes."""

HALF = 1
"""OpenEXR's pixel type code of a 16-bit half float."""

LINE_HEAD = 4
"""The uint16 words before a scanline's pixels: its y and its byte count, two int32."""

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def exr_attribute(name: str, kind: str, value: bytes) -> bytes:
    """One header attribute: its name and type as NUL-terminated text, the value's byte count, the value."""
    return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(value)) + value


def header_value(value) -> tuple:
    """(type name, bytes) of a header attribute value: str → string, int → int, float → float
    (``writing._attribute_value`` first: NumPy scalars and bools, and integers beyond 32 bits as text)."""
    value = _attribute_value(value)
    if isinstance(value, str):
        return "string", value.encode()
    if isinstance(value, int):
        return "int", struct.pack("<i", value)
    return "float", struct.pack("<f", value)


def exr_header(width: int, height: int, channels: Sequence[str], attributes: Dict[str, object]) -> bytes:
    """The magic number, version field and header of an uncompressed half-float scanline EXR of ``width`` x
    ``height`` pixels whose channels are ``channels`` in the file's (alphabetical) order."""
    window = struct.pack("<iiii", 0, 0, width - 1, height - 1)
    chlist = b"".join(name.encode() + b"\0" + struct.pack("<iB3xii", HALF, 0, 1, 1) for name in channels) + b"\0"
    fields = [("channels", "chlist", chlist), ("compression", "compression", b"\0"),
              ("dataWindow", "box2i", window), ("displayWindow", "box2i", window),
              ("lineOrder", "lineOrder", b"\0"), ("pixelAspectRatio", "float", struct.pack("<f", 1.0)),
              ("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0)),
              ("screenWindowWidth", "float", struct.pack("<f", 1.0))]
    fields += [(str(name), *header_value(value)) for name, value in attributes.items()]
    flags = EXR_LONG_NAMES if any(len(name) > 31 for name, _, _ in fields) else 0
    return (struct.pack("<ii", EXR_MAGIC, 2 | flags) + b"".join(exr_attribute(*field) for field in fields)
            + b"\0")


def write_pieces(path: Path, pieces: list) -> None:
    """Write the bytes-like ``pieces`` one after another as the file ``path`` (``atomic_path``), flushed to the
    disk (the writer thread waits for the disk while the others work, and the commit's own flush finds nothing
    left to do); OutputError naming it on failure."""
    path = Path(path)
    with atomic_path(path) as temp:
        try:
            with open(temp, "wb") as f:
                for piece in pieces:
                    f.write(piece)
                f.flush()
                os.fsync(f.fileno())
        except OSError as exc:
            cause = write_failure_cause(temp) or plain_cause(exc)
            raise OutputError(f"Cannot write {path}: {cause}.", path=path, cause=cause) from exc


class HalfPlanes:
    """An uncompressed half-float EXR of (height, width) pixels and the channels ``channels`` (Y; R, G, B), held
    as its scanlines: ``plane(c)`` is channel c's (H, W) uint16 view of them (half-float bit patterns, little
    endian), all 0 (+0.0) at first."""

    def __init__(self, height: int, width: int, channels: Sequence[str]):
        self.shape = (int(height), int(width))
        self.channels = tuple(channels)
        self.order = sorted(self.channels)
        words = LINE_HEAD + len(self.channels) * self.shape[1]
        self.lines = np.zeros((self.shape[0], 2 * words), np.uint8)
        heads = np.stack([np.arange(self.shape[0]), np.full(self.shape[0], 2 * (words - LINE_HEAD))], axis=1)
        self.lines[:, :2 * LINE_HEAD] = heads.astype("<i4").view(np.uint8)
        self.words = self.lines.view("<u2")

    def plane(self, channel: str) -> np.ndarray:
        """Channel ``channel``'s (H, W) uint16 view into the scanlines."""
        start = LINE_HEAD + self.order.index(channel) * self.shape[1]
        return self.words[:, start:start + self.shape[1]]

    def write(self, path, attributes: Dict[str, object]) -> None:
        """Write the file at ``path`` with the header ``attributes`` (str / int / float values) and the order of
        ``channels`` as ``CHANNEL_ORDER_ATTR`` (``image_files.read_exr`` returns the channels in it)."""
        height, width = self.shape
        header = exr_header(width, height, self.order, {CHANNEL_ORDER_ATTR: ",".join(self.channels), **attributes})
        line = self.lines.shape[1]
        offsets = (len(header) + 8 * height + line * np.arange(height, dtype=np.int64)).astype("<u8")
        write_pieces(Path(path), [header, offsets, self.lines])


def png_chunk(kind: bytes, data: bytes) -> bytes:
    """A PNG chunk: length, type, data, CRC-32 of type and data."""
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


class StoredRows:
    """An 8-bit RGB PNG of (height, width) pixels held as its rows: ``pixels`` is their (H, W, 3) uint8 view,
    all 0 at first; the file's zlib stream stores them as they are (level 0)."""

    def __init__(self, height: int, width: int):
        self.shape = (int(height), int(width))
        self.rows = np.zeros((self.shape[0], 1 + 3 * self.shape[1]), np.uint8)   # filter byte 0: None
        self.pixels = self.rows[:, 1:].reshape(self.shape[0], self.shape[1], 3)

    def write(self, path) -> None:
        """Write the PNG at ``path``."""
        height, width = self.shape
        write_pieces(Path(path), [PNG_SIGNATURE,
                                  png_chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)),
                                  png_chunk(b"IDAT", zlib.compress(self.rows, 0)), png_chunk(b"IEND", b"")])
