"""Benchmark of painting a mesh's texture in its UV space against painting a still of the same picture.

The texture is the demo box's (``sample_scenes/object_scene.py``: six UV
islands whose texels differ 4x, read through coffee.png) at ``--size``
texels a side, painted by ``python -m core object`` as a user would. The
still is the same picture at the same size (2048 x 2048: 4.2 MP), painted by
``python -m core paint``. The two alternate, ``--runs`` times each, so both
see the same machine. Printed: the median and best wall-clock seconds, the
peak resident memory of the child (ru_maxrss), the strokes, and the ratio
of the medians (texture / still). How many texels the islands cover is
printed too: the texture painter paints only those, and pays an analysis
per island.

With ``--seams``, it measures instead what painting across the UV seams
costs (ALGORITHM §10, strokes across seams): on three meshes, the demo box
through coffee.png, a cube of six islands and a UV sphere (a meridian seam),
the last two with a colour that runs on over the surface baked into their UV
layouts (``tests/seam_meshes.py``), the texture is painted with its islands
apart and across its seams, alternating in this process, ``--runs`` times
each (the layout's making counted in). Printed for each mesh: the median
wall-clock seconds of both and their ratio, the median processor seconds
(all threads: what a busy machine does not blur) and their ratio, and the
seam / inner step ratio (``seams.texture_steps``) of the source and of both
paintings.

Usage: python bench/object.py [--size 2048] [--runs 3] [--seams]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from common import ROOT, SAMPLE

sys.path.insert(0, str(ROOT / "sample_scenes"))

import object_scene  # noqa: E402

from core.files import reading, writing  # noqa: E402
from core.surface.mesh import read_obj  # noqa: E402
from core.surface.texture import square_texture, surface_layout  # noqa: E402

sys.path.insert(0, str(ROOT / "tests"))


def seams_bench(size: int, runs: int) -> None:
    """Print, for the demo box, a cube and a UV sphere, painting with the islands apart against across the seams
    (module docstring)."""
    from seam_meshes import baked, cube, uv_sphere

    from core.params import Params
    from core.surface.seams import texture_steps
    from core.surface.texture import paint_texture

    with tempfile.TemporaryDirectory() as work:
        box = read_obj(object_scene.box_obj(Path(work) / "box.obj"))
    meshes = {"demo box": (box, square_texture(reading.read_image(SAMPLE), size))}
    for name, mesh in (("cube", cube()), ("UV sphere", uv_sphere(48, 24))):
        meshes[name] = (mesh, baked(mesh, size))
    print(f"{size} x {size} texels, seed 0, {runs} runs each, alternating; seam / inner steps")
    print(f"{'':<11}{'apart s':>9}{'across s':>9}{'ratio':>7}{'apart cpu':>10}{'across cpu':>11}{'ratio':>7}"
          f"{'source':>8}{'apart':>8}{'across':>8}")
    for name, (mesh, texture) in meshes.items():
        seconds, work, steps = {False: [], True: []}, {False: [], True: []}, {}
        for _ in range(runs):
            for across in (False, True):
                start, processor = time.perf_counter(), time.process_time()
                layout = surface_layout(mesh, size, across)
                painted = paint_texture(texture, layout, Params(seed=0))
                seconds[across].append(time.perf_counter() - start)
                work[across].append(time.process_time() - processor)
                steps[across] = texture_steps(painted.colour, layout.edges)
        source = texture_steps(texture, layout.edges)
        ratio = {key: value["seam"] / value["inner"] for key, value in
                 (("source", source), ("apart", steps[False]), ("across", steps[True]))}
        apart, across = statistics.median(seconds[False]), statistics.median(seconds[True])
        apart_cpu, across_cpu = statistics.median(work[False]), statistics.median(work[True])
        print(f"{name:<11}{apart:>9.2f}{across:>9.2f}{across / apart:>7.2f}{apart_cpu:>10.2f}{across_cpu:>11.2f}"
              f"{across_cpu / apart_cpu:>7.2f}{ratio['source']:>8.3f}{ratio['apart']:>8.3f}{ratio['across']:>8.3f}")


def timed_command(arguments: list, out: Path) -> tuple:
    """Run ``python -m core`` with ``arguments``: (wall seconds, peak resident MiB, report dict)."""
    start = time.perf_counter()
    child = subprocess.Popen([sys.executable, "-m", "core", *map(str, arguments), "-o", str(out), "-q"], cwd=ROOT)
    _, status, usage = os.wait4(child.pid, 0)
    seconds = time.perf_counter() - start
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"python -m core {arguments[0]} failed")
    return seconds, usage.ru_maxrss / 1024.0, json.loads((out / "report.json").read_text())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=2048, help="texels a side of the texture and the still")
    parser.add_argument("--runs", type=int, default=3, help="runs of each (median and best are printed)")
    parser.add_argument("--seams", action="store_true", help="painting across the seams against the islands apart")
    args = parser.parse_args()
    if args.seams:
        seams_bench(args.size, args.runs)
        return
    with tempfile.TemporaryDirectory() as work:
        work = Path(work)
        mesh = object_scene.box_obj(work / "box.obj")
        still = work / "still.png"
        writing.write_png(still, square_texture(reading.read_image(SAMPLE), args.size), bits=16)
        layout = surface_layout(read_obj(mesh), args.size)
        covered = float((layout.islands > 0).mean())
        found = {"texture": [], "still": []}
        for run in range(args.runs):
            found["texture"].append(timed_command(["object", SAMPLE, "--mesh", mesh, "--texture-size", args.size],
                                                  work / f"texture_{run}"))
            found["still"].append(timed_command(["paint", still], work / f"still_{run}"))
    print(f"{args.size} x {args.size} texels ({args.size ** 2 / 1e6:.1f} MP), the islands cover {covered:.0%} of "
          f"them; {args.runs} runs each, alternating")
    print(f"{'':<10}{'median s':>10}{'best s':>10}{'peak MiB':>10}{'strokes':>10}")
    medians = {}
    for name, runs in found.items():
        seconds = [s for s, _, _ in runs]
        medians[name] = statistics.median(seconds)
        print(f"{name:<10}{medians[name]:>10.2f}{min(seconds):>10.2f}{max(p for _, p, _ in runs):>10.0f}"
              f"{runs[0][2]['strokes']:>10}")
    print(f"texture / still: {medians['texture'] / medians['still']:.2f}")


if __name__ == "__main__":
    main()
