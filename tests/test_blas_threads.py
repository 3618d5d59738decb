"""The number of BLAS threads changes no painted byte: an object's texture painted with one OpenBLAS thread and
with three is the same files (its source resampled to the texture's size by matrix products, whose sums BLAS
orders by its threads, is resampled on one)."""

import hashlib
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

PAINT = """
import sys
sys.path[:0] = [{root!r}, {tests!r}]
import core
from core.params import Params
from seam_meshes import uv_sphere
core.paint_object(texture_path={texture!r}, mesh=uv_sphere(), output_dir=sys.argv[1], params=Params(seed=1),
                  texture_size=256)
"""


def painted(folder: Path, threads: int) -> dict:
    code = PAINT.format(root=str(ROOT), tests=str(ROOT / "tests"), texture=str(ROOT / "sample_scenes" / "coffee.png"))
    environment = dict(os.environ, OPENBLAS_NUM_THREADS=str(threads), OMP_NUM_THREADS=str(threads))
    subprocess.run([sys.executable, "-c", code, str(folder)], check=True, env=environment, timeout=600)
    return {name: hashlib.sha256((folder / name).read_bytes()).hexdigest()
            for name in ("color.exr", "height.exr", "opacity.exr", "orientation.exr", "strokes.json")}


def test_an_object_painted_on_one_blas_thread_and_on_three_is_the_same_bytes(tmp_path):
    assert painted(tmp_path / "one", 1) == painted(tmp_path / "three", 3)
