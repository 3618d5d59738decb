"""Tests of core.files.reading and core.files.writing: image reading, EXR/PNG/JSON writing, errors and atomic writes."""

from __future__ import annotations

import json
import math
import os

import numpy as np
import OpenImageIO as oiio
import pytest
from oracles import one_sentence

from core.colour import luminance
from core.errors import InputError, OutputError
from core.files import quiet, reading, writing

CANVAS = (0.93, 0.90, 0.84)


def oiio_write(path, pixels, fmt=None, names=None, attrs=None):
    """Write ``pixels`` (H, W, C) with OpenImageIO directly (not through core.files.writing)."""
    pixels = np.ascontiguousarray(pixels)
    h, w, c = pixels.shape
    spec = oiio.ImageSpec(w, h, c, fmt or str(pixels.dtype))
    if names:
        spec.channelnames = names
    if not str(path).endswith(".exr"):
        spec.attribute("oiio:UnassociatedAlpha", 1)  # the pixels hold straight alpha: store them as given
    for k, v in (attrs or {}).items():
        spec.attribute(k, v)
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), spec), oiio.geterror()
    assert out.write_image(pixels), out.geterror()
    out.close()
    return path


def rng_image(h=12, w=17, c=3, seed=0):
    return np.random.default_rng(seed).random((h, w, c), dtype=np.float32)


def assert_one_sentence(exc_info, path):
    text = str(exc_info.value)
    assert os.path.basename(str(path)) in text
    assert one_sentence(text) == text


# --- EXR ---------------------------------------------------------------------


@pytest.mark.parametrize("channels", [1, 3, 4])
def test_exr_float_round_trip_exact(tmp_path, channels):
    data = rng_image(c=channels) * 10 - 3
    attrs = {"paint_relief:params": json.dumps({"detail": 0.5}), "paint_relief:seed": 7,
             "paint_relief:version": "0.1.0", "paint_relief:scale": 0.25}
    path = tmp_path / "map.exr"
    writing.write_exr(path, data, attributes=attrs)
    back, names, header = reading.read_exr(path)
    assert back.dtype == np.float32 and back.shape == data.shape
    np.testing.assert_array_equal(back, data)
    assert names == list({1: "Y", 3: "RGB", 4: "RGBA"}[channels])
    for k, v in attrs.items():
        assert header[k] == v


def test_exr_2d_input_reads_back_3d(tmp_path):
    data = rng_image(c=1)[:, :, 0]
    writing.write_exr(tmp_path / "h.exr", data)
    back, names, _ = reading.read_exr(tmp_path / "h.exr")
    assert back.shape == data.shape + (1,) and names == ["Y"]
    np.testing.assert_array_equal(back[:, :, 0], data)


def test_exr_custom_channel_names_keep_their_order(tmp_path):
    data = rng_image(c=3)
    writing.write_exr(tmp_path / "m.exr", data, channels=("height", "coverage", "opacity"))
    back, names, _ = reading.read_exr(tmp_path / "m.exr")
    assert names == ["height", "coverage", "opacity"]
    np.testing.assert_array_equal(back, data)


def test_exr_half_round_trip(tmp_path):
    data = rng_image(c=3) * 4 - 1
    writing.write_exr(tmp_path / "half.exr", data, half=True)
    back, _, _ = reading.read_exr(tmp_path / "half.exr")
    np.testing.assert_array_equal(back, data.astype(np.float16).astype(np.float32))


def test_exr_bytes_are_deterministic(tmp_path):
    data = rng_image(c=4)
    attrs = {"paint_relief:seed": 3, "paint_relief:params": "{}"}
    writing.write_exr(tmp_path / "a.exr", data, attributes=attrs)
    writing.write_exr(tmp_path / "b.exr", data, attributes=attrs)
    assert (tmp_path / "a.exr").read_bytes() == (tmp_path / "b.exr").read_bytes()
    assert b"DateTime" not in (tmp_path / "a.exr").read_bytes()


# --- PNG ---------------------------------------------------------------------


@pytest.mark.parametrize("bits", [8, 16])
def test_png_round_trip_exact(tmp_path, bits):
    maxval = 2 ** bits - 1
    k = np.random.default_rng(1).integers(0, maxval + 1, size=(9, 11, 3))
    data = k.astype(np.float32) / np.float32(maxval)
    writing.write_png(tmp_path / "p.png", data, bits=bits)
    back = reading.read_image(tmp_path / "p.png")
    assert back.dtype == np.float32 and back.shape == data.shape
    np.testing.assert_array_equal(back, data)


def test_png_rgba_stores_straight_alpha(tmp_path):
    data = np.array([[[0.8, 0.4, 0.2, 0.5], [1.0, 1.0, 1.0, 0.0]]], np.float32)
    writing.write_png(tmp_path / "s.png", data)
    config = oiio.ImageSpec()
    config.attribute("oiio:UnassociatedAlpha", 1)
    inp = oiio.ImageInput.open(str(tmp_path / "s.png"), config)
    raw = inp.read_image(0, 0, 0, 4, "uint8")
    inp.close()
    np.testing.assert_array_equal(raw, [[[204, 102, 51, 128], [255, 255, 255, 0]]])


def test_png_quantises_with_rounding_and_clipping(tmp_path):
    data = np.array([[0.0, 0.5 / 255, 0.49 / 255, 1.7 / 255, -0.3, 1.4]], dtype=np.float32)
    writing.write_png(tmp_path / "q.png", data)
    back = reading.read_gray(tmp_path / "q.png")
    np.testing.assert_array_equal(np.round(back * 255), [[0, 1, 0, 2, 0, 255]])


def test_png_bytes_are_deterministic(tmp_path):
    data = rng_image(c=4)
    for bits in (8, 16):
        writing.write_png(tmp_path / "a.png", data, bits=bits)
        writing.write_png(tmp_path / "b.png", data, bits=bits)
        assert (tmp_path / "a.png").read_bytes() == (tmp_path / "b.png").read_bytes()


# --- read_image --------------------------------------------------------------


def test_read_8bit_and_16bit(tmp_path):
    k8 = np.random.default_rng(2).integers(0, 256, size=(5, 7, 3)).astype(np.uint8)
    k16 = np.random.default_rng(3).integers(0, 65536, size=(5, 7, 3)).astype(np.uint16)
    a = reading.read_image(oiio_write(tmp_path / "a.png", k8))
    b = reading.read_image(oiio_write(tmp_path / "b.png", k16))
    np.testing.assert_array_equal(a, k8.astype(np.float32) / np.float32(255))
    np.testing.assert_array_equal(b, k16.astype(np.float32) / np.float32(65535))


def test_read_gray_is_replicated(tmp_path):
    k = np.arange(20, dtype=np.uint8).reshape(4, 5, 1) * 10
    img = reading.read_image(oiio_write(tmp_path / "g.png", k))
    assert img.shape == (4, 5, 3)
    for c in range(3):
        np.testing.assert_array_equal(img[:, :, c], k[:, :, 0] / np.float32(255))


def test_read_gray_alpha_composites_over_canvas(tmp_path):
    k = np.zeros((2, 2, 2), np.uint8)
    k[..., 0] = 200
    k[..., 1] = [[0, 255], [255, 0]]
    img = reading.read_image(oiio_write(tmp_path / "ga.png", k))
    np.testing.assert_allclose(img[0, 0], CANVAS, atol=1e-6)
    np.testing.assert_allclose(img[0, 1], [200 / 255] * 3, atol=1e-6)


def test_read_rgba_composites_over_canvas(tmp_path):
    k = np.zeros((1, 3, 4), np.uint8)
    k[0, :, :3] = [[10, 120, 250], [10, 120, 250], [200, 100, 0]]
    k[0, :, 3] = [0, 255, 128]
    img = reading.read_image(oiio_write(tmp_path / "rgba.png", k))
    np.testing.assert_allclose(img[0, 0], CANVAS, atol=1e-6)
    np.testing.assert_allclose(img[0, 1], np.array([10, 120, 250]) / 255, atol=1e-6)
    a = 128 / 255
    np.testing.assert_allclose(img[0, 2], np.array([200, 100, 0]) / 255 * a + np.array(CANVAS) * (1 - a), atol=1e-5)
    white = reading.read_image(tmp_path / "rgba.png", canvas_colour=(1, 1, 1))
    np.testing.assert_allclose(white[0, 0], [1, 1, 1], atol=1e-6)


def test_read_more_than_four_channels_takes_rgba(tmp_path):
    k = np.full((2, 2, 5), 0.5, np.float32)
    k[..., 3] = 1.0
    k[..., 4] = 0.0
    img = reading.read_image(oiio_write(tmp_path / "five.tif", k, "float"))
    np.testing.assert_allclose(img, 0.5, atol=1e-6)


def test_read_tiff_and_jpeg(tmp_path):
    k = np.random.default_rng(4).integers(0, 65536, size=(6, 8, 3)).astype(np.uint16)
    tif = reading.read_image(oiio_write(tmp_path / "t.tif", k))
    np.testing.assert_array_equal(tif, k.astype(np.float32) / np.float32(65535))
    smooth = np.zeros((32, 32, 3), np.uint8)
    smooth[..., 0] = 180
    smooth[..., 1] = 90
    smooth[..., 2] = 30
    jpg = reading.read_image(oiio_write(tmp_path / "j.jpg", smooth))
    np.testing.assert_allclose(jpg, smooth / 255.0, atol=3 / 255)


def test_read_linear_exr_gives_srgb(tmp_path):
    lin = np.full((3, 4, 3), 0.2140, np.float32)
    lin[0, 0] = [0.0, 1.0, 5.0]
    img = reading.read_image(oiio_write(tmp_path / "lin.exr", lin, "float"))
    np.testing.assert_allclose(img[1, 1], [0.5, 0.5, 0.5], atol=1e-3)
    np.testing.assert_allclose(img[0, 0], [0.0, 1.0, 1.0], atol=1e-6)


def test_read_premultiplied_exr_alpha(tmp_path):
    # EXR stores premultiplied colour: linear 0.2140 at alpha 0.5 is stored as 0.1070.
    px = np.array([[[0.1070, 0.1070, 0.1070, 0.5]]], np.float32)
    img = reading.read_image(oiio_write(tmp_path / "a.exr", px, "float"))
    np.testing.assert_allclose(img[0, 0], 0.5 * 0.5 + 0.5 * np.array(CANVAS), atol=1e-3)


def test_read_gray_luminance_and_alpha(tmp_path):
    k = np.zeros((1, 2, 4), np.uint8)
    k[0, :, :3] = [[255, 0, 0], [30, 160, 220]]
    k[0, :, 3] = [255, 0]
    g = reading.read_gray(oiio_write(tmp_path / "m.png", k))
    assert g.shape == (1, 2) and g.dtype == np.float32
    assert g[0, 0] == pytest.approx(0.2126, abs=1e-6)
    assert g[0, 1] == 0.0
    rgb = k[..., :3].astype(np.float32) / 255
    g2 = reading.read_gray(oiio_write(tmp_path / "m.jpg", np.repeat(np.repeat(k[..., :3], 8, 0), 8, 1)))
    assert g2.shape == (8, 16)
    assert g2[4, 12] == pytest.approx(float(luminance(rgb[0, 1])), abs=0.03)


def test_read_gray_of_gray_png(tmp_path):
    k = (np.arange(12, dtype=np.uint16).reshape(3, 4, 1) * 5000)
    g = reading.read_gray(oiio_write(tmp_path / "g16.png", k))
    np.testing.assert_array_equal(g, k[:, :, 0].astype(np.float32) / np.float32(65535))


# --- bad inputs --------------------------------------------------------------


def good_png(path, size=(40, 40)):
    data = np.random.default_rng(5).integers(0, 256, size=size + (3,)).astype(np.uint8)
    return oiio_write(path, data)


def good_jpeg(path):
    data = np.random.default_rng(6).integers(0, 256, size=(64, 64, 3)).astype(np.uint8)
    return oiio_write(path, data)


def truncate(path):
    raw = path.read_bytes()
    path.write_bytes(raw[: len(raw) // 2])
    return path


def bad_inputs(tmp_path):
    text = tmp_path / "notes.png"
    text.write_text("this is not an image\n")
    empty = tmp_path / "empty.png"
    empty.write_bytes(b"")
    folder = tmp_path / "folder.png"
    folder.mkdir()
    nan = np.ones((4, 4, 3), np.float32)
    nan[1, 2, 0] = np.nan
    inf = np.ones((4, 4, 3), np.float32)
    inf[3, 3, 2] = np.inf
    return {
        "missing": tmp_path / "missing.png",
        "folder": folder,
        "text": text,
        "empty": empty,
        "truncated png": truncate(good_png(tmp_path / "cut.png")),
        "truncated jpeg": truncate(good_jpeg(tmp_path / "cut.jpg")),
        "nan": oiio_write(tmp_path / "nan.exr", nan, "float"),
        "inf": oiio_write(tmp_path / "inf.exr", inf, "float"),
    }


@pytest.mark.parametrize("reader", [reading.read_image, reading.read_gray, reading.read_exr])
@pytest.mark.parametrize("case", ["missing", "folder", "text", "empty", "truncated png",
                                  "truncated jpeg", "nan", "inf"])
def test_bad_inputs_raise_input_error(tmp_path, reader, case):
    path = bad_inputs(tmp_path)[case]
    with pytest.raises(InputError) as exc_info:
        reader(path)
    assert_one_sentence(exc_info, path)


def test_missing_and_folder_messages(tmp_path):
    with pytest.raises(InputError, match="does not exist"):
        reading.read_image(tmp_path / "nope.png")
    with pytest.raises(InputError, match="folder"):
        reading.read_image(tmp_path)
    (tmp_path / "zero.exr").write_bytes(b"")
    with pytest.raises(InputError, match="empty"):
        reading.read_exr(tmp_path / "zero.exr")


def test_pixel_limit(tmp_path):
    path = good_png(tmp_path / "big.png", size=(20, 20))
    for reader in (reading.read_image, reading.read_gray):
        with pytest.raises(InputError) as exc_info:
            reader(path, max_megapixels=0.0001)
        assert_one_sentence(exc_info, path)
        assert "megapixels" in str(exc_info.value)
    assert reading.read_image(path, max_megapixels=0.0004).shape == (20, 20, 3)


# --- output folders and atomic writes -----------------------------------------


def test_ensure_output_dir_creates_parents(tmp_path):
    folder = writing.ensure_output_dir(tmp_path / "a" / "b")
    assert folder.is_dir() and list(folder.iterdir()) == []


def test_ensure_output_dir_under_a_file(tmp_path):
    blocker = tmp_path / "file.txt"
    blocker.write_text("x")
    with pytest.raises(OutputError) as exc_info:
        writing.ensure_output_dir(blocker / "out")
    assert_one_sentence(exc_info, blocker / "out")
    assert str(exc_info.value).startswith("Cannot write to output folder")


@pytest.mark.skipif(os.geteuid() == 0, reason="root ignores folder permissions")
def test_ensure_output_dir_read_only(tmp_path):
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o500)
    try:
        with pytest.raises(OutputError):
            writing.ensure_output_dir(folder)
    finally:
        folder.chmod(0o700)


def test_atomic_path_names_and_replace(tmp_path):
    target = tmp_path / "color.exr"
    with writing.atomic_path(target) as temp:
        assert temp.parent == tmp_path and temp.suffix == ".exr" and temp.name.startswith(".color.tmp-")
        temp.write_bytes(b"new")
        assert not target.exists()
    assert target.read_bytes() == b"new"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["color.exr"]


def test_atomic_path_failure_keeps_old_file(tmp_path):
    target = tmp_path / "old.txt"
    target.write_bytes(b"good")
    with pytest.raises(RuntimeError):
        with writing.atomic_path(target) as temp:
            temp.write_bytes(b"half")
            raise RuntimeError("boom")
    assert target.read_bytes() == b"good"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["old.txt"]


@pytest.mark.parametrize("kind", ["exr", "png", "json"])
def test_failed_write_keeps_previous_file(tmp_path, monkeypatch, kind):
    target = tmp_path / f"out.{kind}"
    data = rng_image(c=3)
    write = {"exr": lambda: writing.write_exr(target, data),
             "png": lambda: writing.write_png(target, data),
             "json": lambda: writing.write_json(target, {"a": 1})}[kind]
    write()
    before = target.read_bytes()

    def broken(*args, **kwargs):
        raise OSError("disk full")

    if kind == "json":
        monkeypatch.setattr(type(target), "write_text", broken)
    else:
        real_create = oiio.ImageOutput.create

        class HalfWriter:
            """Opens the file for real, then fails while writing pixels."""

            def __init__(self, name):
                self.out = real_create(name)

            def open(self, name, spec):
                return self.out.open(name, spec)

            def write_scanlines(self, ybegin, yend, z, pixels):
                return False

            def geterror(self):
                return "simulated failure midway"

            def close(self):
                return self.out.close()

        monkeypatch.setattr(writing.oiio.ImageOutput, "create", staticmethod(lambda name: HalfWriter(name)))
    with pytest.raises(OutputError) as exc_info:
        write()
    assert_one_sentence(exc_info, target)
    monkeypatch.undo()
    assert target.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == [target.name]


def test_write_into_missing_folder_raises_output_error(tmp_path):
    target = tmp_path / "nowhere" / "x.exr"
    with pytest.raises(OutputError) as exc_info:
        writing.write_exr(target, rng_image())
    assert_one_sentence(exc_info, target)


# --- JSON --------------------------------------------------------------------


def test_write_json_numpy_and_order(tmp_path):
    obj = {"b": np.float32(0.5), "a": np.arange(3), "n": np.int64(4), "nested": {"z": [np.bool_(True)]}}
    writing.write_json(tmp_path / "r.json", obj)
    text = (tmp_path / "r.json").read_text()
    assert text.endswith("}\n")
    assert list(json.loads(text)) == ["b", "a", "n", "nested"]
    assert json.loads(text) == {"b": 0.5, "a": [0, 1, 2], "n": 4, "nested": {"z": [True]}}
    assert text == json.dumps(json.loads(text), indent=2) + "\n"



def strict_json(text: str):
    """``text`` parsed as strict JSON: NaN, Infinity and -Infinity are refused."""
    def refuse(constant):
        raise ValueError(f"{constant} is not JSON")
    return json.loads(text, parse_constant=refuse)


@pytest.mark.parametrize("indent", [2, None])
def test_write_json_writes_null_for_a_figure_with_no_value(tmp_path, indent):
    """NaN and infinities, Python's or NumPy's, in dicts, lists, tuples and arrays, become null: the file is strict
    JSON; the finite values around them are written as they are."""
    obj = {"mean": float("nan"), "psnr": math.inf, "low": -math.inf, "f32": np.float32("nan"),
           "f64": np.float64("inf"), "pairs": [0.25, float("nan"), (1, np.nan)], "array": np.array([0.5, np.nan]),
           "nested": {"ratio": np.float32(0.5), "n": np.int64(3), "ok": True, "none": None, "text": "NaN"}}
    writing.write_json(tmp_path / "r.json", obj, indent=indent)
    read = strict_json((tmp_path / "r.json").read_text())
    assert read == {"mean": None, "psnr": None, "low": None, "f32": None, "f64": None,
                    "pairs": [0.25, None, [1, None]], "array": [0.5, None],
                    "nested": {"ratio": 0.5, "n": 3, "ok": True, "none": None, "text": "NaN"}}


def test_write_json_of_finite_values_is_as_before(tmp_path):
    """Finite data are written exactly as json.dumps writes them."""
    obj = {"x": [0.1, 1e300, -2.5e-7, 3], "y": {"z": 1.0}}
    writing.write_json(tmp_path / "r.json", obj)
    writing.write_json(tmp_path / "c.json", obj, indent=None)
    assert (tmp_path / "r.json").read_text() == json.dumps(obj, indent=2) + "\n"
    assert (tmp_path / "c.json").read_text() == json.dumps(obj, separators=(",", ":")) + "\n"


def test_exif_orientation_is_honoured(tmp_path):
    """A sideways JPEG (Orientation 6: shown turned 90 degrees clockwise) reads upright."""
    import OpenImageIO as oiio

    from core.files.reading import read_image, upright

    stored = np.zeros((20, 40, 3), np.uint8)
    stored[:, :20] = (255, 0, 0)   # left half red
    stored[:, 20:] = (0, 0, 255)   # right half blue
    path = tmp_path / "sideways.jpg"
    spec = oiio.ImageSpec(40, 20, 3, "uint8")
    spec.attribute("Orientation", 6)
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), spec) and out.write_image(stored) and out.close()
    image = read_image(path)
    assert image.shape == (40, 20, 3)                       # portrait, as the camera was held
    assert image[5, 10, 0] > 0.8 and image[5, 10, 2] < 0.2  # the stored left (red) is now the top
    assert image[35, 10, 2] > 0.8 and image[35, 10, 0] < 0.2
    grid = np.arange(6).reshape(2, 3, 1)
    assert upright(grid, 1) is grid or np.array_equal(upright(grid, 1), grid)
    assert np.array_equal(upright(grid, 8)[..., 0], [[2, 5], [1, 4], [0, 3]])
    assert np.array_equal(upright(grid, 7)[..., 0], [[5, 2], [4, 1], [3, 0]])
    assert np.array_equal(upright(grid, 3)[..., 0], [[5, 4, 3], [2, 1, 0]])


def test_library_messages_printed_in_a_thread_whose_capture_began_inside_anothers_reach_no_terminal(capfd,
                                                                                                     monkeypatch):
    """Descriptor 2 is the process's: a block that starts while another thread captures joins that capture and
    keeps it open until it ends itself, so what it prints after the first block ended is still captured."""
    import threading

    monkeypatch.setattr(quiet, "_enabled", True)
    first_inside, first_done = threading.Event(), threading.Event()
    texts = {}

    # the waits only guard against a hang: far beyond a thread's start on a loaded machine, and each is checked
    hang = 600

    def first():
        with quiet.captured() as printed:
            os.write(2, b"first\n")
            first_inside.set()
            texts["waited"] = first_done.wait(hang)
        texts["first"] = printed.text

    thread = threading.Thread(target=first)
    thread.start()
    assert first_inside.wait(hang)
    with quiet.captured() as printed:
        first_done.set()
        thread.join(hang)
        assert not thread.is_alive()
        os.write(2, b"second, after the first block ended\n")
    assert texts["waited"]
    assert texts["first"] == "first\n" and printed.text == "second, after the first block ended\n"
    os.write(2, b"after every block\n")
    assert capfd.readouterr().err == "after every block\n"
