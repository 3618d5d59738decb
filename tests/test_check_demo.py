"""tools/check_demo.py, the check `make demo` ends with (and CI runs through it): it passes a demo folder holding
every promised output whole, and names each missing, empty, unreadable, too small or flat picture and each broken
JSON file."""

import importlib.util
from pathlib import Path

import numpy as np

from core.files.writing import write_exr, write_png

_PATH = Path(__file__).resolve().parent.parent / "tools" / "check_demo.py"
_spec = importlib.util.spec_from_file_location("check_demo", _PATH)
check_demo = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(check_demo)

VIEWS = 3


def _gif(path, width, height):
    path.write_bytes(b"GIF89a" + width.to_bytes(2, "little") + height.to_bytes(2, "little") + b"\x00" * 8 + b";")


def _demo(folder):
    """A demo folder holding every output `make demo` promises, each small but whole."""
    y, x = np.mgrid[0:20, 0:24]
    picture = np.stack([x / 24, y / 20, np.full(x.shape, 0.5)], -1).astype(np.float32)
    for name in check_demo.expected(VIEWS):
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if path.suffix == ".png":
            write_png(path, picture)
        elif path.suffix == ".exr":
            write_exr(path, picture)
        elif path.suffix == ".gif":
            _gif(path, 24, 20)
        elif path.suffix == ".json":
            path.write_text('{"ok": true}\n')
        else:
            path.write_bytes(b"BLENDER-v503 and more")
    return folder


def test_a_whole_demo_passes(tmp_path, capsys):
    out = _demo(tmp_path / "out")
    assert check_demo.main([str(out), "--views", str(VIEWS)]) == 0
    assert "all {} outputs".format(len(check_demo.expected(VIEWS))) in capsys.readouterr().out


def test_the_expected_outputs_are_the_ones_the_readme_names():
    names = check_demo.expected(8)
    for name in ("painting/painting.png", "compare/comparison.png", "compare/light_sweep.gif",
                 "object/turntable/relit/0008.png", "object/turntable/side_by_side/0001.png", "object/object.json"):
        assert name in names, name
    assert "object/turntable/paper/0009.png" not in names


def test_each_missing_or_broken_output_is_named(tmp_path, capsys):
    out = _demo(tmp_path / "out")
    (out / "object" / "turntable" / "relit" / "0002.png").unlink()
    (out / "painting" / "painting.png").write_bytes(b"")
    (out / "compare" / "comparison.png").write_bytes(b"not a picture")
    write_png(out / "object" / "turntable" / "paper" / "0001.png", np.zeros((20, 24, 3), np.float32))
    write_png(out / "analysis" / "partition.png", np.random.default_rng(0).random((8, 40, 3)).astype(np.float32))
    _gif(out / "compare" / "light_sweep.gif", 0, 0)
    (out / "object" / "object.json").write_text("{")
    assert check_demo.main([str(out), "--views", str(VIEWS)]) == 1
    printed = capsys.readouterr().out
    for name, why in (("relit/0002.png", "is missing"), ("painting/painting.png", "is empty"),
                      ("compare/comparison.png", "cannot be read"), ("paper/0001.png", "one flat colour"),
                      ("analysis/partition.png", "is 40 x 8 px"), ("light_sweep.gif", "is 0 x 0 px"),
                      ("object.json", "is not JSON")):
        assert any(name in line and why in line for line in printed.splitlines()), (name, why, printed)
    assert "7 of the demo's" in printed


def test_more_views_ask_for_more_frames(tmp_path, capsys):
    out = _demo(tmp_path / "out")
    assert check_demo.main([str(out), "--views", str(VIEWS + 1)]) == 1
    assert "{:04d}.png is missing".format(VIEWS + 1) in capsys.readouterr().out
