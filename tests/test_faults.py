"""The fault catalogue: bad inputs, bad numbers, failing disks, signals, kills and concurrent writers.

Every case runs the command line (in a subprocess where the process itself
matters: library messages, signals, resource limits, users) against an
output folder that already holds a complete painting (seed 1), and asserts
the exit status, that stderr is one sentence naming the problem, and that
the folder afterwards holds one complete painting (``check_painting``: every
file's size and SHA-256 as the report lists them, every EXR's header seed
equal to the report's) or exactly its previous contents.
"""

import contextlib
import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import held_run
import numpy as np
import OpenImageIO as oiio
import pytest
from addon_values import values
from oracles import one_sentence, same_bytes

from core.api import paint_file
from core.cli import main
from core.errors import InputError
from core.files import reading, writing
from core.files.maps import check_maps, check_painting
from core.files.staging import JOURNAL_NAME, STAGING_PREFIX, recover, settle
from core.params import Params

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO / "bench"))
from stress_kill import stress  # noqa: E402

# --- helpers ------------------------------------------------------------------------------------------------------

def snapshot(folder: Path) -> dict:
    """{relative path: bytes} of every file under ``folder`` (hidden ones included); None when it does not exist."""
    if not folder.exists():
        return None
    return {str(p.relative_to(folder)): (p.read_bytes() if p.is_file() else "<dir>")
            for p in sorted(folder.rglob("*"))}


def hidden_leftovers(folder: Path) -> list:
    return sorted(p.name for p in folder.iterdir() if p.name.startswith((STAGING_PREFIX, ".paint-relief")))


def run_cli(args, timeout=600, **kwargs):
    """Run ``python -m core ARGS`` in a subprocess; returns CompletedProcess with text output. ``timeout`` only
    guards against a hang: far beyond the seconds a command of these tests takes on a loaded machine."""
    env = dict(os.environ, PYTHONPATH=str(REPO), PYTHONDONTWRITEBYTECODE="1")
    return subprocess.run([sys.executable, "-m", "core"] + [str(a) for a in args], capture_output=True, text=True,
                          timeout=timeout, env=env, cwd=REPO, **kwargs)


def assert_one_sentence(err: str, *words):
    """stderr is exactly one line, a sentence (``oracles.one_sentence``) after the command's name, containing every
    word of ``words``."""
    text = one_sentence(err)
    assert text.startswith("paint-relief: "), text
    for word in words:
        assert str(word) in text, (word, text)


def assert_named_once(err: str, path):
    """The sentence names ``path`` exactly once (and no hidden staging or temporary name)."""
    assert err.count(str(path)) == 1, (str(path), err)
    assert STAGING_PREFIX not in err and ".tmp-" not in err, err


def assert_untouched_or_complete(folder: Path, before: dict):
    """The folder holds exactly ``before`` or one complete painting, and no staging, journal or lock."""
    after = snapshot(folder)
    if after == before:
        return
    assert after is not None, "the folder was removed"
    check_painting(folder)
    assert hidden_leftovers(folder) == []


def refuse_to_read_or_paint(monkeypatch, read: bool = True) -> None:
    """Make reading an image's pixels (when ``read``) and painting fail the test: a refusal must come before."""
    import core.methods.registry

    def started(*args, **kwargs):
        raise AssertionError("an image's pixels were read or painting started")
    monkeypatch.setattr(core.methods.registry, "paint", started)
    if read:
        monkeypatch.setattr(reading, "read_image", started)


# --- fixtures -----------------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def inputs(tmp_path_factory, half_textured):
    """Good and bad input files, by name."""
    d = tmp_path_factory.mktemp("inputs")
    image = half_textured()
    writing.write_png(d / "photo.png", image)
    writing.write_exr(d / "photo.exr", image)
    writing.write_png(d / "photo16.png", image, bits=16)
    writing.write_png(d / "gray.png", image[..., 0])
    writing.write_png(d / "rgba.png", np.concatenate([image, np.full((32, 40, 1), 0.5, np.float32)], axis=2))
    buf = oiio.ImageBuf(oiio.ImageSpec(40, 32, 2, "uint8"))
    buf.set_pixels(oiio.ROI(), (np.stack([image[..., 0], np.ones((32, 40))], axis=2) * 255).astype(np.uint8))
    buf.write(str(d / "gray_alpha.png"))
    buf = oiio.ImageBuf(oiio.ImageSpec(40, 32, 3, "uint8"))
    buf.set_pixels(oiio.ROI(), (image * 255).astype(np.uint8))
    buf.write(str(d / "photo.jpg"))
    for name in ("photo.png", "photo.exr", "photo.jpg"):
        data = (d / name).read_bytes()
        (d / f"truncated_{name}").write_bytes(data[: len(data) // 2])
    (d / "empty.png").write_bytes(b"")
    (d / "text.png").write_text("this is not a picture\n" * 20)
    nan = image.copy()
    nan[3, 4, 1] = np.nan
    writing.write_exr(d / "nan.exr", nan)
    inf = image.copy()
    inf[5, 6, 0] = np.inf
    writing.write_exr(d / "inf.exr", inf)
    (d / "a_folder.png").mkdir()
    writing.write_png(d / "square.png", np.full((100, 100, 3), 0.5, np.float32))
    _bomb_png(d / "bomb.png", 7000, 7000)
    other = d / "other"
    other.mkdir()
    writing.write_png(other / "photo.png", half_textured(seed=9))
    return d


def _bomb_png(path: Path, w: int, h: int):
    """A 1-bit gray PNG of w x h black pixels: a few kilobytes."""
    import struct
    import zlib

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    raw = (b"\x00" + b"\x00" * ((w + 7) // 8)) * h
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 1, 0, 0, 0, 0))
                     + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


@pytest.fixture(scope="module")
def painted(inputs, tmp_path_factory):
    """A folder holding a complete painting of photo.png with seed 1, and a user's own file."""
    out = tmp_path_factory.mktemp("painted") / "out"
    assert main(["paint", str(inputs / "photo.png"), "-o", str(out), "-q", "--seed", "1"]) == 0
    (out / "notes.txt").write_text("the user's own file\n")
    return out


@pytest.fixture
def folder(painted, tmp_path):
    """A fresh copy of the painted folder and its snapshot."""
    out = tmp_path / "out"
    shutil.copytree(painted, out)
    return out, snapshot(out)


# --- bad inputs: refused with one sentence, the folder untouched --------------------------------------------------

@pytest.mark.parametrize("name, words", [
    ("truncated_photo.png", ["truncated_photo.png"]),
    ("truncated_photo.jpg", ["truncated_photo.jpg"]),
    ("truncated_photo.exr", ["truncated_photo.exr"]),
    ("empty.png", ["empty.png", "empty"]),
    ("text.png", ["text.png"]),
    ("missing.png", ["missing.png", "does not exist"]),
    ("a_folder.png", ["a_folder.png", "folder"]),
    ("nan.exr", ["nan.exr", "NaN"]),
    ("inf.exr", ["inf.exr", "infinite"]),
    ("bomb.png", ["bomb.png", "decompression bomb"]),
])
def test_bad_input_is_one_sentence_and_changes_nothing(inputs, folder, name, words):
    out, before = folder
    run = run_cli(["paint", inputs / name, "-o", out, "-q", "--seed", "2"])
    assert run.returncode == 2
    assert_one_sentence(run.stderr, *words)
    assert_named_once(run.stderr, inputs / name)
    assert snapshot(out) == before


def test_bomb_is_refused_from_its_header(inputs, tmp_path, monkeypatch, capfd):
    """A 7000 x 7000 PNG of a few kilobytes is refused before any pixel of it is decoded."""
    refuse_to_read_or_paint(monkeypatch)
    assert main(["paint", str(inputs / "bomb.png"), "-o", str(tmp_path / "new"), "-q"]) == 2
    assert_one_sentence(capfd.readouterr().err, "bomb.png")
    assert not (tmp_path / "new").exists()


@pytest.mark.parametrize("options, words", [
    (["--max-megapixels", "0.001"], ["megapixels"]),
    (["--max-memory", "1M"], ["memory", "--max-memory"]),
    (["--max-memory", "1K"], ["--max-memory limit of 1 KB", "megapixels"]),
    (["--max-memory", "lots"], ["--max-memory"]),
    (["--mask", "TRUNCATED"], ["truncated_photo.png"]),
    (["--sizes", "100000"], ["1024"]),
    (["--sizes", "0"], ["positive"]),
    (["--seed", "-1"], ["seed"]),
    (["--seed", str(2**63)], ["seed", "2^63"]),
    (["--seed", "9" * 400], ["--seed", "400 digits"]),
    (["--seed", "1.5"], ["--seed"]),
    (["--detail", "nan"], ["--detail", "finite"]),
    (["--detail", "inf"], ["--detail", "finite"]),
    (["--mask-strength", "inf"], ["--mask-strength", "finite"]),
    (["--alpha", "nan"], ["--alpha", "finite"]),
    (["--max-megapixels", "inf"], ["--max-megapixels"]),
    (["--layers", "99"], ["Layers"]),
    (["--sizes", "64,8,8"], ["--sizes", "once", "8", "64,8,8"]),
])
def test_bad_numbers_are_one_sentence_and_change_nothing(inputs, folder, capfd, monkeypatch, options, words):
    out, before = folder
    options = [str(inputs / "truncated_photo.png") if o == "TRUNCATED" else o for o in options]
    refuse_to_read_or_paint(monkeypatch, read=False)
    try:
        status = main(["paint", str(inputs / "photo.png"), "-o", str(out), "-q", "--seed", "2"] + options)
    except SystemExit as exc:  # options the argument parser itself refuses
        status = exc.code
    assert status == 2
    assert_one_sentence(capfd.readouterr().err, *words)
    assert snapshot(out) == before


@pytest.mark.parametrize("command", ["paint", "analyze", "experiments"])
@pytest.mark.parametrize("output", ["", "  "])
def test_an_empty_output_folder_is_refused_and_nothing_is_written(inputs, tmp_path, command, output):
    """`-o "$UNSET"` must not paint into the current folder."""
    env = dict(os.environ, PYTHONPATH=str(REPO), PYTHONDONTWRITEBYTECODE="1")
    run = subprocess.run([sys.executable, "-m", "core", command, str(inputs / "photo.png"), "-o", output, "-q"],
                         capture_output=True, text=True, timeout=600, env=env, cwd=tmp_path)
    assert run.returncode == 2
    assert_one_sentence(run.stderr, "--output", "empty", "current folder")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("url", ["https://example.com/photos/cat.png", "file:///tmp/cat.png"])
def test_a_url_input_is_named_whole_and_refused(tmp_path, capfd, url):
    assert main(["paint", url, "-o", str(tmp_path / "out"), "-q"]) == 2
    assert_one_sentence(capfd.readouterr().err, url, "URL", "not supported")
    assert not (tmp_path / "out").exists()


def test_a_dangling_symlink_is_named_as_one(inputs, tmp_path, capfd):
    (tmp_path / "photo.png").symlink_to(tmp_path / "gone.png")
    assert main(["paint", str(tmp_path / "photo.png"), "-o", str(tmp_path / "out"), "-q"]) == 2
    assert_one_sentence(capfd.readouterr().err, "symbolic link", "gone.png", "does not exist")
    (tmp_path / "out").symlink_to(tmp_path / "missing-folder")
    assert main(["paint", str(inputs / "photo.png"), "-o", str(tmp_path / "out"), "-q"]) == 2
    err = capfd.readouterr().err
    assert_one_sentence(err, "symbolic link", "missing-folder", "does not exist")
    assert "in the way" not in err
    assert (tmp_path / "out").is_symlink() and not (tmp_path / "missing-folder").exists()


def test_experiments_refuse_an_image_given_twice(inputs, tmp_path, capfd):
    photo = inputs / "photo.png"
    same = tmp_path / ".." / tmp_path.name / "link.png"
    (tmp_path / "link.png").symlink_to(photo)
    assert main(["experiments", str(photo), str(same), "-o", str(tmp_path / "out"), "-q"]) == 2
    assert_one_sentence(capfd.readouterr().err, str(same), "twice")
    assert not (tmp_path / "out").exists()


def test_sizes_100000_refused_on_the_command_line(inputs, tmp_path):
    run = run_cli(["paint", inputs / "photo.png", "-o", tmp_path / "new", "--sizes", "100000"])
    assert run.returncode == 2 and not (tmp_path / "new").exists()
    assert_one_sentence(run.stderr, "1024")


def test_stroke_wider_than_the_image_is_refused(inputs, tmp_path, capfd):
    assert main(["paint", str(inputs / "square.png"), "-o", str(tmp_path / "o"), "-q", "--sizes", "1024"]) == 2
    assert_one_sentence(capfd.readouterr().err, "wider than the image")
    assert not (tmp_path / "o").exists()


def test_sizes_larger_than_the_image_are_refused_naming_the_option(folder, capfd, monkeypatch, half_textured):
    """--sizes are px at 1 megapixel: 900 becomes a 75 px brush on a 96 x 72 image, taller than the image."""
    out, before = folder
    small = out.parent / "small.png"
    writing.write_png(small, half_textured(72, 96))
    refuse_to_read_or_paint(monkeypatch)
    assert main(["paint", str(small), "-o", str(out), "-q", "--sizes", "900,64"]) == 2
    assert_one_sentence(capfd.readouterr().err, "stroke size 900", "--sizes", "75 px", "96 x 72", "72 px side",
                        "up to 872")
    assert snapshot(out) == before


def test_default_sizes_fit_every_image():
    """The defaults are never refused, on a 1 x 4000 strip either; a size scaled past a strip's width is."""
    from core.errors import ParameterError
    from core.files.budget import check_stroke_sizes

    for height, width in [(1, 4000), (4000, 1), (1, 1), (10, 4000), (72, 96), (3000, 4000)]:
        check_stroke_sizes(Params(), height, width)
    check_stroke_sizes(Params(stroke_sizes=(872, 4)), 72, 96)
    with pytest.raises(ParameterError, match="--sizes"):
        check_stroke_sizes(Params(stroke_sizes=(128,)), 1, 4000)


def test_panel_sizes_are_capped():
    with pytest.raises(ValueError, match="1024"):
        values.parse_sizes("64,100000")
    assert values.parse_sizes("1024,4") == (1024, 4)
    with pytest.raises(ValueError, match="8 is given twice"):
        values.parse_sizes("64, 8 8")


def test_memory_error_is_one_sentence(inputs, folder, monkeypatch, capfd):
    out, before = folder
    import core.methods.registry

    def boom(*args, **kwargs):
        raise MemoryError()
    monkeypatch.setattr(core.methods.registry, "paint", boom)
    assert main(["paint", str(inputs / "photo.png"), "-o", str(out), "-q"]) == 2
    assert_one_sentence(capfd.readouterr().err, "ran out of memory", "photo.png")
    assert snapshot(out) == before


# --- accepted inputs: one complete painting -----------------------------------------------------------------------

@pytest.mark.parametrize("name", ["photo16.png", "gray.png", "gray_alpha.png", "rgba.png", "photo.exr", "photo.jpg"])
def test_other_formats_paint_completely(inputs, folder, name):
    out, before = folder
    assert main(["paint", str(inputs / name), "-o", str(out), "-q", "--seed", "2"]) == 0
    assert check_painting(out) == "2"
    assert (out / "notes.txt").read_text() == "the user's own file\n"
    assert hidden_leftovers(out) == []


def _multi_image(path: Path, pages):
    """Write the (H, W, 3) float arrays ``pages`` as the subimages of one TIFF (8-bit) or EXR (half, one part each)."""
    out = oiio.ImageOutput.create(str(path))
    kind = "uint8" if path.suffix == ".tif" else "half"
    specs = [oiio.ImageSpec(p.shape[1], p.shape[0], 3, kind) for p in pages]
    for i, spec in enumerate(specs):
        spec.attribute("name", f"part{i}")
    assert out.open(str(path), specs)
    for i, page in enumerate(pages):
        assert i == 0 or out.open(str(path), specs[i], "AppendSubimage")
        data = np.round(page * 255).astype(np.uint8) if kind == "uint8" else page.astype(np.float32)
        assert out.write_image(data)
    out.close()


def _png_chunks(path: Path):
    """[(type, data)] of a PNG file."""
    import struct

    data, chunks, i = path.read_bytes(), [], 8
    while i < len(data):
        length, kind = struct.unpack(">I4s", data[i:i + 8])
        chunks.append((kind, data[i + 8:i + 8 + length]))
        i += 12 + length
    return chunks


def _apng(path: Path, frames):
    """An animated PNG of the PNG files ``frames`` (same size and format), built chunk by chunk (APNG 1.0)."""
    import struct
    import zlib

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)
    first = _png_chunks(frames[0])
    ihdr = dict(first)[b"IHDR"]
    width, height = struct.unpack(">II", ihdr[:8])
    out, seq = [b"\x89PNG\r\n\x1a\n", chunk(b"IHDR", ihdr), chunk(b"acTL", struct.pack(">II", len(frames), 0))], 0
    for n, frame in enumerate(frames):
        out.append(chunk(b"fcTL", struct.pack(">IIIIIHHBB", seq, width, height, 0, 0, 1, 10, 0, 0)))
        seq += 1
        for kind, body in _png_chunks(frame):
            if kind == b"IDAT" and n == 0:
                out.append(chunk(b"IDAT", body))
            elif kind == b"IDAT":
                out.append(chunk(b"fdAT", struct.pack(">I", seq) + body))
                seq += 1
    out.append(chunk(b"IEND", b""))
    path.write_bytes(b"".join(out))


@pytest.mark.parametrize("name, pages", [("photo.tif", 3), ("photo_parts.exr", 2), ("animated.png", 3)])
def test_an_input_of_several_images_paints_the_first_and_says_so(inputs, tmp_path, name, pages, half_textured):
    first = half_textured()
    others = [np.full_like(first, 0.1 * (i + 1)) for i in range(pages - 1)]
    source = tmp_path / name
    if name.endswith(".png"):
        frames = [tmp_path / f"frame{i}.png" for i in range(pages)]
        for frame, data in zip(frames, [first] + others, strict=True):
            writing.write_png(frame, data)
        _apng(source, frames)
    else:
        _multi_image(source, [first] + others)
    alone = tmp_path / ("alone" + Path(name).suffix)
    if name.endswith(".png"):
        writing.write_png(alone, first)
    else:
        _multi_image(alone, [first])
    run = run_cli(["paint", source, "-o", tmp_path / "out", "-q", "--seed", "4"])
    assert run.returncode == 0, run.stderr
    assert run.stderr == f"paint-relief: {source} holds {pages} images; painting the first.\n"
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    assert (report["input_page"], report["input_pages"]) == (0, pages)
    assert main(["paint", str(alone), "-o", str(tmp_path / "alone_out"), "-q", "--seed", "4"]) == 0
    assert json.loads((tmp_path / "alone_out" / "report.json").read_text())["input_pages"] == 1
    same_bytes(tmp_path / "out", tmp_path / "alone_out")


@pytest.mark.parametrize("seed", [2**31, 2**53 + 1, 2**63 - 1])
def test_large_seeds_are_stored_exactly(inputs, tmp_path, seed):
    out = tmp_path / "o"
    assert main(["paint", str(inputs / "photo.png"), "-o", str(out), "-q", "--seed", str(seed)]) == 0
    assert check_painting(out) == str(seed)
    report = json.loads((out / "report.json").read_text())
    assert report["seed"] == seed and report["params"]["seed"] == seed
    _, _, attributes = reading.read_exr(out / "height.exr")
    assert attributes["paint_relief:seed"] == str(seed)
    assert json.loads(attributes["paint_relief:params"])["seed"] == seed


# --- output faults ------------------------------------------------------------------------------------------------

def test_output_is_a_file(inputs, tmp_path, capfd):
    blocker = tmp_path / "blocker"
    blocker.write_text("x")
    assert main(["paint", str(inputs / "photo.png"), "-o", str(blocker), "-q"]) == 2
    assert_one_sentence(capfd.readouterr().err, "blocker")
    assert blocker.read_text() == "x"


def test_output_under_a_file(inputs, tmp_path, capfd):
    blocker = tmp_path / "blocker"
    blocker.write_text("x")
    assert main(["paint", str(inputs / "photo.png"), "-o", str(blocker / "a" / "b"), "-q"]) == 2
    assert_one_sentence(capfd.readouterr().err, "blocker")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["blocker"]


def test_failed_run_creates_no_folders(inputs, tmp_path):
    run = run_cli(["paint", inputs / "truncated_photo.png", "-o", tmp_path / "a" / "b" / "c", "-q"])
    assert run.returncode == 2 and list(tmp_path.iterdir()) == []


def test_failed_run_after_creating_the_folder_removes_it(inputs, tmp_path, monkeypatch, capfd):
    import core.methods.registry

    def broken(*args, **kwargs):
        raise InputError("The painter stopped on purpose.")
    monkeypatch.setattr(core.methods.registry, "paint", broken)
    assert main(["paint", str(inputs / "photo.png"), "-o", str(tmp_path / "a" / "b"), "-q"]) == 2
    assert_one_sentence(capfd.readouterr().err, "on purpose")
    assert list(tmp_path.iterdir()) == []


def test_a_folder_where_a_file_should_be(inputs, folder, capfd):
    out, _ = folder
    (out / "opacity.exr").unlink()
    (out / "opacity.exr").mkdir()
    (out / "opacity.exr" / "inside.txt").write_text("keep me")
    before = snapshot(out)
    assert main(["paint", str(inputs / "photo.png"), "-o", str(out), "-q", "--seed", "2"]) == 2
    assert_one_sentence(capfd.readouterr().err, "opacity.exr", "folder")
    assert snapshot(out) == before


def _without_root_override():
    """In the child: drop CAP_DAC_OVERRIDE and CAP_DAC_READ_SEARCH, so root meets folder permissions too."""
    import ctypes

    libc = ctypes.CDLL(None, use_errno=True)
    for capability in (1, 2):
        if libc.prctl(24, capability, 0, 0, 0) != 0:  # PR_CAPBSET_DROP
            raise OSError(ctypes.get_errno(), "prctl(PR_CAPBSET_DROP) failed")


def test_unwritable_folder(inputs, tmp_path):
    base = Path(tempfile.mkdtemp(prefix="paint-relief-ro-"))
    try:
        os.chmod(base, 0o755)
        shutil.copy(inputs / "photo.png", base / "photo.png")
        out = base / "out"
        out.mkdir()
        (out / "old.txt").write_text("old")
        os.chmod(out, 0o555)
        kwargs = {"preexec_fn": _without_root_override} if os.geteuid() == 0 else {}
        before = snapshot(out)
        run = run_cli(["paint", base / "photo.png", "-o", out, "-q"], **kwargs)
        assert run.returncode == 2
        assert_one_sentence(run.stderr, str(out))
        assert snapshot(out) == before
    finally:
        os.chmod(base / "out", 0o755)
        shutil.rmtree(base)


@pytest.mark.parametrize("limit_kb", [1, 6, 20, 60])
def test_full_disk(inputs, folder, limit_kb):
    """RLIMIT_FSIZE stands in for a full disk: writes beyond it fail (EFBIG) at different files."""
    import resource

    out, before = folder

    def limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit_kb * 1024, limit_kb * 1024))
    run = run_cli(["paint", inputs / "photo.png", "-o", out, "-q", "--seed", "2"], preexec_fn=limit)
    assert run.returncode == 2, run.stderr
    assert_one_sentence(run.stderr, str(out), "too large", "file size limit", "left as it was")
    assert_named_once(run.stderr, out)
    assert "Failed" not in run.stderr and "File output failed" not in run.stderr
    assert snapshot(out) == before


@contextlib.contextmanager
def small_disk(folder: Path, size: str):
    """A tmpfs of ``size`` (such as '2M') mounted at ``folder`` for the block; the test is skipped when mounting
    is not permitted (not root, or no CAP_SYS_ADMIN in a container)."""
    folder.mkdir(parents=True, exist_ok=True)
    mount = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(folder)],
                           capture_output=True, text=True)
    if mount.returncode != 0:
        pytest.skip(f"a small tmpfs cannot be mounted here: {mount.stderr.strip() or 'mount failed'}")
    try:
        yield folder
    finally:
        subprocess.run(["umount", "-l", str(folder)], capture_output=True)


@pytest.fixture(scope="module")
def photo_16mp(tmp_path_factory):
    """A 4000 x 4000 JPEG photograph (16 megapixels), its pixels never decoded by a refused run."""
    path = tmp_path_factory.mktemp("p16") / "photo16mp.jpg"
    rng = np.random.default_rng(16)
    y, x = np.mgrid[0:4000, 0:4000].astype(np.float32) / 4000
    pixels = np.stack([x, y, 0.5 * (x + y)], axis=2) * 200 + rng.integers(0, 40, (4000, 4000, 3))
    buf = oiio.ImageBuf(oiio.ImageSpec(4000, 4000, 3, "uint8"))
    buf.set_pixels(oiio.ROI(), pixels.astype(np.uint8))
    assert buf.write(str(path))
    return path


def test_no_space_is_refused_before_any_pixel_is_read(photo_16mp, tmp_path, monkeypatch, capfd):
    """A 16 MP photograph into a nearly full 2 MB disk: refused from its header, before any pixel is read."""
    refuse_to_read_or_paint(monkeypatch)
    with small_disk(tmp_path / "disk", "2M") as disk:
        (disk / "big.bin").write_bytes(bytes(1_500_000))
        out = disk / "out"
        out.mkdir()
        (out / "notes.txt").write_text("the user's own file\n")
        before = snapshot(disk)
        status = main(["paint", str(photo_16mp), "-o", str(out), "-q", "--max-memory", "100G"])
        err = capfd.readouterr().err
        assert snapshot(disk) == before
    assert status == 2
    assert_one_sentence(err, "not enough space is left on the device", "KB free", "needs at least 46 MB",
                        "4000 x 4000")
    assert_named_once(err, out)


def test_no_space_is_refused_before_painting_on_any_machine(inputs, folder, monkeypatch, capfd):
    """The same refusal without mounting anything: the file system says it has 100 KB free."""
    import shutil as shutil_module

    import core.methods.registry

    out, before = folder
    monkeypatch.setattr(core.methods.registry, "paint", lambda *a, **k: pytest.fail("painting started"))
    monkeypatch.setattr(shutil_module, "disk_usage", lambda path: shutil_module._ntuple_diskusage(1 << 30, 1 << 30,
                                                                                                  100 * 1024))
    writing.write_png(out.parent / "wide.png", np.full((400, 500, 3), 0.5, np.float32))
    assert main(["paint", str(out.parent / "wide.png"), "-o", str(out), "-q"]) == 2
    err = capfd.readouterr().err
    assert_one_sentence(err, "not enough space", "100 KB free", "586 KB")
    assert_named_once(err, out)
    assert snapshot(out) == before


@pytest.mark.parametrize("size", ["16k", "40k", "100k"])
def test_a_disk_found_full_while_writing_is_named_as_one(inputs, tmp_path, size):
    """Enough space for the estimate, too little for the painting: one sentence with the cause and the user's
    folder, without the libraries' own messages or the staging names, and the folder as it was."""
    with small_disk(tmp_path / "disk", size) as disk:
        out = disk / "out"
        out.mkdir()
        (out / "notes.txt").write_text("the user's own file\n")
        before = snapshot(disk)
        run = run_cli(["paint", inputs / "photo.png", "-o", out, "-q"])
        after = snapshot(disk)
    assert run.returncode == 2, run.stderr
    assert re.fullmatch(rf"paint-relief: error: Cannot write [a-z_]+\.(exr|png|json) into the output folder "
                        rf"{re.escape(str(out))}: no space is left on the device; the folder was left as it was\.\n",
                        run.stderr), run.stderr
    assert after == before


@pytest.mark.parametrize("name, command", [("painting.png", "paint"), ("color.exr", "paint"),
                                           ("normal.exr", "paint --normal-map"), ("importance.exr", "analyze")])
def test_something_in_the_way_is_refused_before_painting(inputs, folder, monkeypatch, capfd, name, command):
    import core.cli
    import core.methods.registry

    out, _ = folder
    if (out / name).exists():
        (out / name).unlink()
    (out / name).mkdir()
    (out / name / "inside.txt").write_text("keep me")
    before = snapshot(out)
    monkeypatch.setattr(core.methods.registry, "paint", lambda *a, **k: pytest.fail("painting started"))
    monkeypatch.setattr(core.cli, "analyze", lambda *a, **k: pytest.fail("analysis started"))
    words = command.split()
    assert main([words[0], str(inputs / "photo.png"), "-o", str(out), "-q"] + words[1:]) == 2
    err = capfd.readouterr().err
    assert_one_sentence(err, "folder of that name is in the way")
    assert_named_once(err, out / name)
    assert snapshot(out) == before


@pytest.mark.parametrize("kind, words", [("missing", ["does not exist"]), ("empty", ["is empty"]),
                                         ("folder", ["is a folder"])])
def test_a_missing_or_empty_mask_is_called_a_mask(inputs, folder, capfd, kind, words):
    out, before = folder
    mask = out.parent / "mask.png"
    if kind == "empty":
        mask.write_bytes(b"")
    elif kind == "folder":
        mask.mkdir()
    assert main(["paint", str(inputs / "photo.png"), "-o", str(out), "-q", "--mask", str(mask)]) == 2
    err = capfd.readouterr().err
    assert_one_sentence(err, "The mask", *words)
    assert "input file" not in err
    assert_named_once(err, mask)
    assert snapshot(out) == before


@pytest.mark.parametrize("locked", ["file", "folder above"])
def test_an_unreadable_input_says_permission_is_denied(inputs, tmp_path, locked):
    """Mode 000 on the file (or its folder) as a user the permissions apply to (root without its override)."""
    if os.geteuid() != 0:
        pytest.skip("needs root to drop its permission override in the child")
    private = tmp_path / "private"
    private.mkdir()
    photo = private / "photo.png"
    shutil.copy(inputs / "photo.png", photo)
    out = tmp_path / "out"
    os.chmod(photo if locked == "file" else private, 0)
    try:
        run = run_cli(["paint", photo, "-o", out, "-q"], preexec_fn=_without_root_override)
    finally:
        os.chmod(photo if locked == "file" else private, 0o755)
    assert run.returncode == 2
    assert_one_sentence(run.stderr, "The input file", "permission denied")
    assert_named_once(run.stderr, photo)
    assert "Could not open" not in run.stderr and not out.exists()


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="no /proc on this system")
def test_an_existing_folder_where_no_file_can_be_created(inputs, capfd):
    assert main(["paint", str(inputs / "photo.png"), "-o", "/proc/self", "-q"]) == 2
    err = capfd.readouterr().err
    assert_one_sentence(err, "no file can be created")
    assert_named_once(err, "/proc/self")
    assert "no such file" not in err.lower()


# --- signals, kills, stale remains, concurrent writers ------------------------------------------------------------

@pytest.fixture(scope="module")
def big_photo(tmp_path_factory):
    """A 0.25-megapixel photograph: about a second of painting."""
    from common import photo

    path = tmp_path_factory.mktemp("big") / "big.png"
    writing.write_png(path, photo(0.25))
    return path


def _start(args):
    env = dict(os.environ, PYTHONPATH=str(REPO), PYTHONDONTWRITEBYTECODE="1")
    return subprocess.Popen([sys.executable, "-m", "core"] + [str(a) for a in args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env, cwd=REPO)


PAINTED = "core.methods.registry:paint"
"""Where a held `paint` waits (held_run): painted, holding its folder's lock, nothing of it written yet."""


@pytest.mark.parametrize("signum, status, name", [(signal.SIGTERM, 143, "SIGTERM"), (signal.SIGINT, 130, "SIGINT")])
def test_signal_ends_cleanly(big_photo, folder, signum, status, name):
    """A signal once the painting is made, its folder locked and nothing of it written: the folder as it was, no
    leftovers."""
    out, before = folder
    proc = held_run.start(["paint", big_photo, "-o", out, "-q", "--seed", "2"], PAINTED)
    held_run.held(proc)
    proc.send_signal(signum)
    _, err = proc.communicate(timeout=600)
    assert proc.returncode == status
    assert_one_sentence(err, name, "left as it was")
    assert snapshot(out) == before
    assert hidden_leftovers(out) == []


def test_signal_into_a_new_folder_leaves_no_folder(big_photo, tmp_path):
    proc = held_run.start(["paint", big_photo, "-o", tmp_path / "new" / "deeper", "-q"], PAINTED)
    held_run.held(proc)
    assert (tmp_path / "new" / "deeper").is_dir()   # made for the run, and locked
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=600)
    assert proc.returncode == 143 and "left as it was" in err
    assert list(tmp_path.iterdir()) == []


def test_kills_during_writing(tmp_path):
    """bench/stress_kill.py with a handful of kills: each leaves one complete painting."""
    counts = stress(4, 0.05, seed=3, work=tmp_path, verbose=False)
    assert counts["complete"] == counts["kills"] == 4
    assert counts["rerun_ok"] == 4


@pytest.mark.parametrize("delay", [0.3, 0.7])
def test_kill_at_random_points_of_a_run(big_photo, folder, delay):
    out, before = folder
    proc = _start(["paint", big_photo, "-o", out, "-q", "--seed", "2"])
    time.sleep(delay + random.Random(int(delay * 10)).uniform(0, 0.3))
    proc.kill()
    proc.wait()
    settle(out)  # what the next run does first, under the folder's lock
    assert_untouched_or_complete(out, before)


def test_stale_staging_is_removed_by_the_next_run(inputs, folder):
    out, _ = folder
    stale = out / f"{STAGING_PREFIX}99999-dead"
    stale.mkdir()
    (stale / "color.exr").write_bytes(b"half a file")
    (out / ".paint-relief.lock").write_text("99999")  # left by a killed process: nobody holds it
    assert main(["paint", str(inputs / "photo.png"), "-o", str(out), "-q", "--seed", "2"]) == 0
    assert check_painting(out) == "2" and hidden_leftovers(out) == []


def test_a_temporary_file_a_killed_writer_left_is_removed_by_the_next_run(inputs, folder):
    """The lives file of a shot is written in the folder itself, through a temporary file: a run killed while
    writing it leaves that file, which the next run into the folder removes; a file of the user's that only looks
    alike stays."""
    out, _ = folder
    (out / ".strokes.tmp-31275-8fe4e4e0.lives").write_bytes(b"half a record")
    (out / ".notes.tmp-old.txt").write_text("the user's")
    assert main(["paint", str(inputs / "photo.png"), "-o", str(out), "-q", "--seed", "2"]) == 0
    assert not (out / ".strokes.tmp-31275-8fe4e4e0.lives").exists()
    assert (out / ".notes.tmp-old.txt").read_text() == "the user's"


def test_interrupted_commit_is_completed_by_the_next_run(inputs, folder, tmp_path):
    """A journal left mid-commit (SIGKILL after the commit point) is rolled forward before anything else."""
    out, _ = folder
    new = tmp_path / "new"
    assert main(["paint", str(inputs / "other" / "photo.png"), "-o", str(new), "-q", "--seed", "7"]) == 0
    staging = out / f"{STAGING_PREFIX}12345-abcd"
    staging.mkdir()
    names = sorted(p.name for p in new.iterdir())
    for i, name in enumerate(names):  # the first three were already moved when the process died
        shutil.copy(new / name, (out if i < 3 else staging) / name)
    (out / JOURNAL_NAME).write_text(json.dumps({"staging": staging.name, "files": names}))
    with pytest.raises(InputError):
        check_painting(out)  # mixed on disk until a run or a reader settles it
    check_maps(out)  # a reader (Build Canvas) settles the folder first
    assert check_painting(out) == "7" and hidden_leftovers(out) == []
    assert (out / "notes.txt").exists()


def test_torn_journal_is_discarded(inputs, folder):
    out, before = folder
    (out / JOURNAL_NAME).write_text('{"staging": ".staging-1-x", "fil')
    recover(out)
    assert snapshot(out) == {k: v for k, v in before.items()}


def test_two_concurrent_writers(big_photo, folder):
    out, _ = folder
    first = held_run.start(["paint", big_photo, "-o", out, "-q", "--seed", "2"], PAINTED)
    held_run.held(first)                         # the first holds the folder's lock until the second has ended
    second = _start(["paint", big_photo, "-o", out, "-q", "--seed", "3"])
    _, err2 = second.communicate(timeout=600)
    _, err1 = held_run.release(first)
    assert first.returncode == 0, err1
    assert second.returncode == 2
    assert_one_sentence(err2, str(out), "being written by process", str(first.pid))
    assert check_painting(out) == "2" and hidden_leftovers(out) == []


def test_analyze_and_paint_share_the_lock(big_photo, folder):
    out, _ = folder
    first = held_run.start(["paint", big_photo, "-o", out, "-q", "--seed", "2"], PAINTED)
    held_run.held(first)
    second = run_cli(["analyze", big_photo, "-o", out, "-q"])
    _, err1 = held_run.release(first)
    assert first.returncode == 0, err1
    assert second.returncode == 2 and "being written" in second.stderr
    assert check_painting(out) == "2"


# --- experiments --------------------------------------------------------------------------------------------------

def test_experiments_with_two_images_of_the_same_name(inputs, tmp_path, capfd):
    out = tmp_path / "exp"
    assert main(["experiments", str(inputs / "photo.png"), str(inputs / "other" / "photo.png"), "-o", str(out),
                 "-q"]) == 2
    assert_one_sentence(capfd.readouterr().err, "photo.png", "same name")
    assert not out.exists()


def test_experiments_refuse_a_bad_image_before_any_work(inputs, tmp_path, capfd):
    out = tmp_path / "exp"
    assert main(["experiments", str(inputs / "photo.png"), str(inputs / "truncated_photo.exr"), "-o", str(out),
                 "-q"]) == 2
    assert_one_sentence(capfd.readouterr().err, "truncated_photo.exr")
    assert not out.exists()


# --- maps before Blender ------------------------------------------------------------------------------------------

def _break(folder: Path, kind: str):
    height, channels, attributes = reading.read_exr(folder / "height.exr")
    keep = {k: v for k, v in attributes.items() if k.startswith("paint_relief:") and k != "paint_relief:channel_order"}
    if kind == "truncated":
        data = (folder / "height.exr").read_bytes()
        (folder / "height.exr").write_bytes(data[: len(data) // 2])
    elif kind == "zero":
        (folder / "height.exr").write_bytes(b"")
    elif kind == "nan":
        height[2, 3, 0] = np.nan
        writing.write_exr(folder / "height.exr", height, channels=("Y",), attributes=keep)
    elif kind == "inf":
        height[2, 3, 0] = np.inf
        writing.write_exr(folder / "height.exr", height, channels=("Y",), attributes=keep)
    elif kind == "channels":
        writing.write_exr(folder / "height.exr", np.repeat(height, 3, axis=2), attributes=keep)
    elif kind == "size":
        writing.write_exr(folder / "height.exr", height[:-1], channels=("Y",), attributes=keep)
    elif kind == "other_painting":
        keep["paint_relief:seed"] = "99"
        writing.write_exr(folder / "height.exr", height, channels=("Y",), attributes=keep)
    elif kind == "missing":
        (folder / "height.exr").unlink()
    elif kind == "text":
        (folder / "height.exr").write_text("not an EXR file\n" * 50)


@pytest.mark.parametrize("kind, words", [
    ("truncated", ["height.exr"]), ("zero", ["height.exr", "empty"]), ("nan", ["height.exr", "NaN"]),
    ("inf", ["height.exr", "infinite"]), ("channels", ["height.exr", "channels"]),
    ("size", ["height.exr", "pixels"]), ("other_painting", ["height.exr", "another painting"]),
    ("missing", ["height.exr", "does not exist"]), ("text", ["height.exr"]),
])
def test_bad_maps_are_refused_before_blender(folder, kind, words):
    out, _ = folder
    assert check_maps(out) == (40, 32)
    _break(out, kind)
    with pytest.raises(InputError) as caught:
        check_maps(out)
    message = str(caught.value)
    assert message.endswith(".") and "\n" not in message
    for word in words:
        assert word in message, message


def test_light_refuses_a_nan_map(folder, capfd):
    out, _ = folder
    _break(out, "nan")
    assert main(["light", str(out), "--model", "bump", "-q"]) == 2
    assert_one_sentence(capfd.readouterr().err, "height.exr", "NaN")


def test_paint_file_refuses_before_creating_anything(inputs, tmp_path):
    with pytest.raises(InputError, match="memory"):
        paint_file(inputs / "photo.png", tmp_path / "x", Params(), max_memory=1)
    assert list(tmp_path.iterdir()) == []
