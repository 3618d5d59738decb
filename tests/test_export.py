"""Writing a painting: images made a block of rows at a time, the normal map only when asked."""

from __future__ import annotations

import json

import numpy as np
import pytest

from core import tuning
from core.cli import main
from core.files import reading, writing
from core.files.export import (
    HEIGHT_DIGEST_ATTR,
    NORMAL_FILE,
    ensure_normal_map,
    file_digest,
    painting_attributes,
    rows_with_halo,
)
from core.lighting import DEFAULT_RELIEF, encode_normals, normal_map, paper_lighting


@pytest.fixture(scope="module")
def painted(tmp_path_factory):
    rng = np.random.default_rng(8)
    image = np.clip(np.linspace(0.2, 0.8, 80)[None, :, None] + rng.normal(0, 0.05, (60, 80, 3)), 0, 1)
    photo = tmp_path_factory.mktemp("input") / "photo.png"
    writing.write_png(photo, image.astype(np.float32))
    plain, with_normals = tmp_path_factory.mktemp("plain"), tmp_path_factory.mktemp("normals")
    assert main(["paint", str(photo), "-o", str(plain), "-q", "--seed", "4"]) == 0
    assert main(["paint", str(photo), "-o", str(with_normals), "-q", "--seed", "4", "--normal-map"]) == 0
    return plain, with_normals


def test_row_blocks_write_the_same_file_as_the_whole_array(tmp_path, monkeypatch):
    rng = np.random.default_rng(1)
    data = rng.random((70, 33, 3), dtype=np.float32)
    writing.write_exr(tmp_path / "whole.exr", data, half=True)
    writing.write_png(tmp_path / "whole.png", data)
    monkeypatch.setattr(tuning, "BLOCK_PIXELS", 16 * 33)          # 16 rows a block: five blocks, the last short
    blocks = writing.RowBlocks(data.shape, lambda y0, y1: data[y0:y1])
    writing.write_exr(tmp_path / "blocks.exr", blocks, half=True)
    writing.write_png(tmp_path / "blocks.png", blocks)
    for ext in ("exr", "png"):
        assert (tmp_path / f"whole.{ext}").read_bytes() == (tmp_path / f"blocks.{ext}").read_bytes()


def test_rows_that_need_their_neighbours_come_out_as_computed_whole(monkeypatch):
    rng = np.random.default_rng(2)
    colour = rng.random((50, 40, 3), dtype=np.float32)
    height = rng.random((50, 40), dtype=np.float32)
    orientation = rng.uniform(0, np.pi, (50, 40)).astype(np.float32)
    monkeypatch.setattr(tuning, "BLOCK_PIXELS", 16 * 40)
    for compute, whole, halo in (
            (lambda a, b: paper_lighting(colour[a:b], height[a:b], orientation[a:b]),
             paper_lighting(colour, height, orientation), 2),
            (lambda a, b: normal_map(height[a:b], DEFAULT_RELIEF), normal_map(height, DEFAULT_RELIEF), 1)):
        image = rows_with_halo(whole.shape, compute, halo)
        blocks = np.concatenate([block for _, _, block in image.blocks()])
        np.testing.assert_allclose(blocks, whole, atol=1e-5)


def test_the_normal_map_is_written_only_when_asked(painted):
    plain, with_normals = painted
    assert not (plain / NORMAL_FILE).exists()
    assert NORMAL_FILE not in json.loads((plain / "report.json").read_text())["files"]
    report = json.loads((with_normals / "report.json").read_text())
    assert report["files"][NORMAL_FILE] == file_digest(with_normals / NORMAL_FILE)
    normals, channels, attributes = reading.read_exr(with_normals / NORMAL_FILE)
    assert channels == ["R", "G", "B"]
    assert attributes[HEIGHT_DIGEST_ATTR] == report["files"]["height.exr"]["sha256"]
    height = reading.read_exr(with_normals / "height.exr")[0][:, :, 0]
    np.testing.assert_allclose(normals, encode_normals(normal_map(height, DEFAULT_RELIEF)), atol=2e-3)  # half floats


def test_a_normal_map_is_made_for_the_height_map_it_belongs_to(painted, tmp_path):
    plain, with_normals = painted
    folder = tmp_path / "copy"
    folder.mkdir()
    for path in plain.iterdir():
        (folder / path.name).write_bytes(path.read_bytes())
    made = ensure_normal_map(folder)
    assert made == folder / NORMAL_FILE
    assert made.read_bytes() == (with_normals / NORMAL_FILE).read_bytes()   # as the painter writes it
    stamp = made.stat().st_mtime_ns
    assert ensure_normal_map(folder).stat().st_mtime_ns == stamp            # the same height map: kept
    height, _, attributes = reading.read_exr(folder / "height.exr")
    kept = painting_attributes(attributes)
    writing.write_exr(folder / "height.exr", height[::-1].copy(), channels=("Y",), half=True, attributes=kept)
    remade = reading.read_exr(ensure_normal_map(folder))[0]                       # painted again: made again
    np.testing.assert_allclose(remade, encode_normals(normal_map(height[::-1, :, 0], DEFAULT_RELIEF)), atol=2e-3)


def test_a_normal_map_needs_a_height_map(tmp_path):
    from core.errors import InputError

    with pytest.raises(InputError, match="height.exr"):
        ensure_normal_map(tmp_path)
    assert not (tmp_path / NORMAL_FILE).exists()
