"""Animated GIF writing, checked with an independent decoder written here."""

import numpy as np

from core.figures.gif import palette, quantise, write_gif


def lzw_decode(data: bytes, min_code_size: int, count: int) -> np.ndarray:
    """Textbook GIF LZW decoder (variable code width, LSB first)."""
    clear, end = 1 << min_code_size, (1 << min_code_size) + 1
    pos = 0
    out = []
    width = min_code_size + 1
    table = None
    previous = None
    bits = int.from_bytes(data, "little")
    while True:
        code = (bits >> pos) & ((1 << width) - 1)
        pos += width
        if code == clear:
            table = [[i] for i in range(clear)] + [None, None]
            width = min_code_size + 1
            previous = None
            continue
        if code == end:
            break
        if previous is None:
            entry = table[code]
        elif code < len(table):
            entry = table[code]
            table.append(table[previous] + [entry[0]])
        else:
            entry = table[previous] + [table[previous][0]]
            table.append(entry)
        out.extend(entry)
        previous = code
        if len(table) == (1 << width) and width < 12:
            width += 1
    assert len(out) == count
    return np.array(out, dtype=np.uint8)


def read_gif(blob: bytes):
    """(palette (256, 3), list of (H, W) index frames, delays) of a GIF written by write_gif."""
    assert blob[:6] == b"GIF89a" and blob[-1:] == b"\x3b"
    w, h = int.from_bytes(blob[6:8], "little"), int.from_bytes(blob[8:10], "little")
    table = np.frombuffer(blob[13:13 + 768], np.uint8).reshape(256, 3)
    pos = 13 + 768
    frames, delays = [], []
    while blob[pos] != 0x3B:
        if blob[pos] == 0x21:  # extension: skip its sub-blocks, keep the delay of graphic control ones
            if blob[pos + 1] == 0xF9:
                delays.append(int.from_bytes(blob[pos + 4:pos + 6], "little"))
            pos += 2
            while blob[pos]:
                pos += blob[pos] + 1
            pos += 1
        else:
            assert blob[pos] == 0x2C
            pos += 10
            min_code = blob[pos]
            pos += 1
            data = b""
            while blob[pos]:
                data += blob[pos + 1:pos + 1 + blob[pos]]
                pos += blob[pos] + 1
            pos += 1
            frames.append(lzw_decode(data, min_code, w * h).reshape(h, w))
    return table, frames, delays


def test_gif_round_trip(tmp_path):
    rng = np.random.default_rng(2)
    gradient = np.dstack([*np.meshgrid(np.linspace(0, 1, 70), np.linspace(0, 1, 50))[::-1], np.full((50, 70), 0.4)])
    noise = rng.random((50, 70, 3))
    flat = np.full((50, 70, 3), 0.5)
    path = tmp_path / "anim.gif"
    write_gif(path, [gradient, noise, flat], seconds_per_frame=0.25)
    table, frames, delays = read_gif(path.read_bytes())
    assert np.array_equal(table, palette())
    assert delays == [25, 25, 25]
    for source, decoded in zip([gradient, noise, flat], frames, strict=True):
        assert np.array_equal(decoded, quantise(source))
        # Dithering keeps local means: a 4x4 box average is close to the source.
        shown = table[decoded].astype(np.float64) / 255.0
        box = lambda a: a[:48, :68].reshape(12, 4, 17, 4, 3).mean(axis=(1, 3))  # noqa: E731
        assert np.abs(box(shown) - box(source)).max() < 0.12


def test_quantise_hits_palette_corners():
    frame = np.zeros((4, 4, 3))
    assert np.all(palette()[quantise(frame)] == 0)
    assert np.all(palette()[quantise(frame + 1.0)] == 255)


def test_long_frames_restart_the_code_table(tmp_path):
    noise = np.random.default_rng(3).random((160, 200, 3))  # far more than 4096 codes
    path = tmp_path / "noise.gif"
    write_gif(path, [noise])
    _, frames, _ = read_gif(path.read_bytes())
    assert np.array_equal(frames[0], quantise(noise))
