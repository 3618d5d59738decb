"""Animated GIF writing (OpenImageIO reads GIF but does not write it).

Frames are float (H, W, 3) sRGB in [0, 1]; they share one 252-colour
palette (a 6 x 7 x 6 colour cube) with ordered dithering, and are compressed
with the GIF variant of LZW.
"""

from __future__ import annotations

import struct
from pathlib import Path
from typing import Sequence

import numpy as np

LEVELS = (6, 7, 6)  # red, green, blue steps of the palette cube (252 colours)
BAYER4 = np.array([[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]], dtype=np.float32) / 16.0 - 0.46875


def palette() -> np.ndarray:
    """(256, 3) uint8 palette: the colour cube, then black padding."""
    r, g, b = np.meshgrid(*[np.linspace(0, 255, n) for n in LEVELS], indexing="ij")
    cube = np.stack([r.ravel(), g.ravel(), b.ravel()], axis=1)
    table = np.zeros((256, 3), dtype=np.uint8)
    table[: len(cube)] = np.rint(cube).astype(np.uint8)
    return table


def quantise(frame: np.ndarray) -> np.ndarray:
    """(H, W) uint8 palette indices of an (H, W, 3) [0, 1] frame, with 4x4 ordered dithering."""
    h, w = frame.shape[:2]
    threshold = np.tile(BAYER4, (h // 4 + 1, w // 4 + 1))[:h, :w, None]
    steps = np.array(LEVELS, dtype=np.float32) - 1.0
    level = np.clip(np.floor(np.clip(frame, 0.0, 1.0) * steps + 0.5 + threshold), 0, steps).astype(np.int32)
    return ((level[..., 0] * LEVELS[1] + level[..., 1]) * LEVELS[2] + level[..., 2]).astype(np.uint8)


def lzw_compress(indices: np.ndarray, min_code_size: int = 8) -> bytes:
    """GIF LZW code stream (variable-width codes, least significant bit first) of uint8 ``indices``."""
    clear = 1 << min_code_size
    end = clear + 1
    out = bytearray()
    bit_buffer = 0
    bit_count = 0

    def emit(code: int, width: int) -> None:
        nonlocal bit_buffer, bit_count
        bit_buffer |= code << bit_count
        bit_count += width
        while bit_count >= 8:
            out.append(bit_buffer & 0xFF)
            bit_buffer >>= 8
            bit_count -= 8

    width = min_code_size + 1
    table = {bytes([i]): i for i in range(clear)}
    next_code = end + 1
    emit(clear, width)
    data = indices.tobytes()
    current = data[:1]
    for value in data[1:]:
        candidate = current + bytes([value])
        if candidate in table:
            current = candidate
            continue
        emit(table[current], width)
        if next_code < 4096:
            table[candidate] = next_code
            next_code += 1
            if next_code > (1 << width) and width < 12:
                width += 1
        else:
            emit(clear, width)
            table = {bytes([i]): i for i in range(clear)}
            next_code = end + 1
            width = min_code_size + 1
        current = bytes([value])
    if current:
        emit(table[current], width)
    emit(end, width)
    if bit_count:
        out.append(bit_buffer & 0xFF)
    return bytes(out)


def sub_blocks(data: bytes) -> bytes:
    """Data split into GIF sub-blocks of at most 255 bytes, ended by a zero-length block."""
    chunks = [bytes([len(data[i:i + 255])]) + data[i:i + 255] for i in range(0, len(data), 255)]
    return b"".join(chunks) + b"\x00"


def write_gif(path, frames: Sequence[np.ndarray], seconds_per_frame: float = 0.5) -> None:
    """Write looping animated GIF ``path`` from equally sized (H, W, 3) [0, 1] frames, atomically."""
    from ..files.writing import atomic_path

    h, w = frames[0].shape[:2]
    delay = max(2, int(round(seconds_per_frame * 100)))
    parts = [b"GIF89a", struct.pack("<HHBBB", w, h, 0xF7, 0, 0), palette().tobytes(),
             b"\x21\xFF\x0BNETSCAPE2.0\x03\x01\x00\x00\x00"]
    for frame in frames:
        if frame.shape[:2] != (h, w):
            raise ValueError("All GIF frames must have the same size.")
        parts.append(b"\x21\xF9\x04\x04" + struct.pack("<H", delay) + b"\x00\x00")
        parts.append(b"\x2C" + struct.pack("<HHHHB", 0, 0, w, h, 0))
        parts.append(b"\x08" + sub_blocks(lzw_compress(quantise(frame))))
    parts.append(b"\x3B")
    with atomic_path(Path(path)) as temp:
        Path(temp).write_bytes(b"".join(parts))
