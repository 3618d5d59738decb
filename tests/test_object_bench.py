"""bench/object.py runs on a small texture and prints its table, and the demo box's OBJ has its six islands."""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "sample_scenes"))


def test_the_demo_box_as_an_obj_has_six_islands_whose_texels_differ_four_times(tmp_path):
    import object_scene

    from core.surface.mesh import read_obj
    from core.surface.texture import surface_layout, texel_mm

    layout = surface_layout(read_obj(object_scene.box_obj(tmp_path / "box.obj")), 512)
    spans = texel_mm(layout)
    assert len(spans) == 6 and spans.max() / spans.min() == pytest.approx(4.0, rel=1e-3)
    assert spans.min() == pytest.approx(1000 * 0.4 / 0.46 / 512, rel=1e-3)    # 0.4 m over a 0.46 UV square


def test_the_object_bench_prints_both_paintings_and_their_ratio():
    run = subprocess.run([sys.executable, "bench/object.py", "--size", "256", "--runs", "1"], cwd=ROOT,
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    assert lines[0].startswith("256 x 256 texels (0.1 MP), the islands cover ")
    assert lines[2].split()[0] == "texture" and lines[3].split()[0] == "still"
    assert lines[-1].startswith("texture / still: ") and float(lines[-1].split()[-1]) > 0
