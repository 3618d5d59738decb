"""``python -m core experiments``: tables and contact sheets of the comparison."""

import csv

import numpy as np

from core.cli import main
from core.files import reading, writing


def test_experiments_writes_tables_and_sheets(tmp_path):
    rng = np.random.default_rng(4)
    paths = []
    for name in ("one", "two"):
        image = np.zeros((48, 64, 3), np.float32)
        image[..., 2] = np.linspace(0.2, 0.8, 64)[None, :]
        image[12:36, 16:48] = rng.random((24, 32, 3))
        path = tmp_path / f"{name}.png"
        writing.write_png(path, image)
        paths.append(str(path))
    out = tmp_path / "out"
    assert main(["experiments", *paths, "-o", str(out), "-q"]) == 0
    assert {p.name for p in out.iterdir()} == {"table.md", "table.csv", "one_sheet.png", "two_sheet.png"}
    rows = list(csv.DictReader((out / "table.csv").open()))
    assert [r["image"] for r in rows] == ["one.png", "two.png"]
    for r in rows:
        assert r["size"] == "64x48"
        ratio = int(r["ours_strokes"]) / int(r["hertzmann98_strokes"])
        assert float(r["stroke_ratio_ours_over_hertzmann98"]) == round(ratio, 3)
        for key in ("ours", "hertzmann98", "layout_ablation", "lines_ablation"):
            assert int(r[f"{key}_strokes"]) > 0
            assert 5.0 < float(r[f"{key}_psnr_db"]) < 60.0
            assert -1.0 <= float(r[f"{key}_ssim"]) <= 1.0
    table = (out / "table.md").read_text()
    assert table.count("one.png") == 5 and "Hertzmann 1998 (Impressionist)" in table
    sheet = reading.read_image(out / "one_sheet.png")
    assert sheet.shape[0] > 2 * 48 and sheet.shape[1] > 4 * 64  # two rows of four panels


def test_experiments_bad_image(tmp_path, capsys):
    assert main(["experiments", str(tmp_path / "nothing.png"), "-o", str(tmp_path / "out"), "-q"]) != 0
    assert "nothing.png" in capsys.readouterr().err
