"""``core.files.raw_files``: uncompressed EXRs and PNGs written from their own bytes, read back by OpenImageIO."""

import numpy as np
import OpenImageIO as oiio
import pytest
from oracles import one_sentence

from core.errors import OutputError
from core.files import raw_files, reading


def test_a_half_float_exr_reads_back_as_written(tmp_path):
    values = np.random.default_rng(0).normal(0.0, 3.0, (5, 7, 3)).astype(np.float16)
    planes = raw_files.HalfPlanes(5, 7, ("R", "G", "B"))
    for c, name in enumerate("RGB"):
        planes.plane(name)[...] = values[..., c].view(np.uint16)
    long_name = "paint_relief:" + "x" * 40                   # past 31 bytes: the long-names flag
    planes.write(tmp_path / "c.exr", {"paint_relief:frame": "3", "count": 12, "scale": 0.5, long_name: "yes"})
    data, names, attributes = reading.read_exr(tmp_path / "c.exr")
    assert names == ["R", "G", "B"] and data.shape == (5, 7, 3)
    assert np.array_equal(data, values.astype(np.float32))
    assert attributes["paint_relief:frame"] == "3" and attributes["count"] == 12 and attributes["scale"] == 0.5
    assert attributes[long_name] == "yes"
    spec = oiio.ImageInput.open(str(tmp_path / "c.exr")).spec()
    assert spec.format == oiio.HALF and spec.get_string_attribute("compression") == "none"


def test_one_channel_exr_and_channels_out_of_alphabetical_order(tmp_path):
    height = raw_files.HalfPlanes(3, 4, ("Y",))
    height.plane("Y")[...] = np.arange(12, dtype=np.float16).reshape(3, 4).view(np.uint16)
    height.write(tmp_path / "h.exr", {})
    data, names, _ = reading.read_exr(tmp_path / "h.exr")
    assert names == ["Y"] and np.array_equal(data[..., 0], np.arange(12, dtype=np.float32).reshape(3, 4))
    mixed = raw_files.HalfPlanes(2, 2, ("Z", "A"))
    mixed.plane("Z")[...] = np.float16(2.0).view(np.uint16)
    mixed.plane("A")[...] = np.float16(-1.0).view(np.uint16)
    mixed.write(tmp_path / "m.exr", {})
    data, names, _ = reading.read_exr(tmp_path / "m.exr")
    assert names == ["Z", "A"] and np.all(data[..., 0] == 2.0) and np.all(data[..., 1] == -1.0)


def test_a_stored_png_reads_back_as_written(tmp_path):
    pixels = np.random.default_rng(1).integers(0, 256, (9, 11, 3), dtype=np.uint8)
    png = raw_files.StoredRows(9, 11)
    png.pixels[...] = pixels
    png.write(tmp_path / "p.png")
    buf = oiio.ImageBuf(str(tmp_path / "p.png"))
    assert buf.spec().format == oiio.UINT8 and buf.spec().nchannels == 3
    assert np.array_equal(buf.get_pixels(oiio.UINT8), pixels)


def test_the_same_pixels_give_the_same_bytes(tmp_path):
    planes = raw_files.HalfPlanes(4, 4, ("Y",))
    planes.plane("Y")[...] = 7
    planes.write(tmp_path / "a.exr", {"k": "v"})
    planes.write(tmp_path / "b.exr", {"k": "v"})
    assert (tmp_path / "a.exr").read_bytes() == (tmp_path / "b.exr").read_bytes()


def test_a_file_that_cannot_be_written_is_named_in_one_sentence(tmp_path):
    png = raw_files.StoredRows(2, 2)
    with pytest.raises(OutputError) as error:
        png.write(tmp_path / "missing" / "p.png")
    one_sentence(str(error.value))
    assert "p.png" in str(error.value)
