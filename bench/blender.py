"""Benchmark of the Blender side: building the canvas and a Cycles preview render.

Paints a 1-megapixel photograph once (the painter is not what is timed), then
runs each case in its own subprocess (bpy can be imported once per process;
BLENDER_USER_RESOURCES points at a temporary folder) and prints the seconds
and each subprocess's own peak resident memory (ru_maxrss):
  build     paint_relief.build_canvas on the 1 MP maps, for each displacement method
  render    a 512 px Cycles render (CPU, 16 samples) of the canvas with its lights
            and camera, for each displacement method
  panel     what an artist waits for in the panel: Paint on a --panel-megapixels photograph
            (10 MP by default) and Build Canvas (MESH) on its maps, both operators as
            the panel calls them (headless, so the paint runs in the operator's call),
            median of --runs runs, each in a fresh process
Usage: python bench/blender.py [--megapixels 1] [--size 512] [--samples 16] [--panel-megapixels 10] [--runs 3]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
METHODS = ("MESH", "CYCLES_ADAPTIVE")

# Runs inside the subprocess: argv = painted folder, method, case, render size, samples, package dir.
CASE = r'''
import json, os, sys, time
painted, method, case, size, samples, package_dir = sys.argv[1:7]
sys.path.insert(0, package_dir)
import bpy
bpy.ops.wm.read_factory_settings(use_empty=True)
import paint_relief
paint_relief.register()
scene = bpy.context.scene
settings = scene.paint_relief
settings.painting_dir = painted
settings.displacement_method = method
if case == "panel":
    settings.image_path = painted
    settings.output_dir = os.path.join(os.path.dirname(painted), "panel_painted")
    t0 = time.perf_counter()
    assert bpy.ops.paint_relief.paint() == {"FINISHED"}
    paint_seconds = time.perf_counter() - t0
t0 = time.perf_counter()
assert bpy.ops.paint_relief.build_canvas() == {"FINISHED"}
bpy.context.evaluated_depsgraph_get()  # the modifiers' evaluation is part of building
measured = {"build": time.perf_counter() - t0}
if case == "panel":
    measured.update(paint=paint_seconds, panel=paint_seconds + measured["build"])
if case == "render":
    bpy.ops.paint_relief.add_lights()
    bpy.ops.paint_relief.add_camera()
    render = scene.render
    render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = int(samples)
    render.resolution_percentage = max(1, round(100 * int(size) / max(render.resolution_x, render.resolution_y)))
    render.filepath = os.path.join(os.path.dirname(painted), "preview_" + method.lower() + ".png")
    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    measured["render"] = time.perf_counter() - t0
    measured["render_size"] = [render.resolution_x * render.resolution_percentage // 100,
                              render.resolution_y * render.resolution_percentage // 100]
import resource
measured["peak_mib"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # KiB on Linux
print("MEASURED " + json.dumps(measured), flush=True)
'''


def run_case(work: Path, painted: Path, method: str, case: str, size: int, samples: int) -> dict:
    """One case in a fresh Python process; its figures, with the process's own peak memory (ru_maxrss) in MiB."""
    package_dir = work / "pkg"
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(work / "blender_user"))
    run = subprocess.run([sys.executable, "-c", CASE, str(painted), method, case, str(size), str(samples),
                          str(package_dir)], capture_output=True, text=True, env=env, cwd=work)
    lines = [line for line in run.stdout.splitlines() if line.startswith("MEASURED ")]
    if run.returncode != 0 or not lines:
        raise SystemExit("{} {} failed:\n{}\n{}".format(case, method, run.stdout[-3000:], run.stderr[-3000:]))
    return json.loads(lines[-1][len("MEASURED "):])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--megapixels", type=float, default=1.0)
    parser.add_argument("--size", type=int, default=512, help="longer side of the preview render in pixels")
    parser.add_argument("--samples", type=int, default=16)
    parser.add_argument("--panel-megapixels", type=float, default=10.0, help="photograph of the panel case (0: skip)")
    parser.add_argument("--runs", type=int, default=3, help="runs of the panel case")
    args = parser.parse_args()

    sys.path.insert(0, str(ROOT / "bench"))
    from common import photo  # noqa: E402
    from core import Params  # noqa: E402
    from core.api import paint_file  # noqa: E402
    from core.files import writing  # noqa: E402

    with tempfile.TemporaryDirectory(prefix="paint_relief_bench_") as tmp:
        work = Path(tmp)
        (work / "pkg").mkdir()
        os.symlink(ROOT, work / "pkg" / "paint_relief")
        image = photo(args.megapixels)
        writing.write_png(work / "photo.png", image)
        t0 = time.perf_counter()
        paint_file(work / "photo.png", work / "painted", Params())
        h, w = image.shape[:2]
        print(f"painted {w}x{h} ({h * w / 1e6:.2f} MP) in {time.perf_counter() - t0:.1f} s (not part of the measures)")
        print(f"{'case':<8} {'method':<16} {'seconds':>8} {'peak MiB':>9}  note")
        for case in ("build", "render"):
            for method in METHODS:
                measured = run_case(work, work / "painted", method, case, args.size, args.samples)
                seconds = measured[case]
                peak = f"{measured['peak_mib']:>9.0f}"
                note = ("target <= 3 s" if case == "build" else
                        "{}x{} px, {} samples, target <= 30 s (build {:.2f} s)".format(
                            *measured["render_size"], args.samples, measured["build"]))
                print(f"{case:<8} {method:<16} {seconds:>8.2f} {peak}  {note}", flush=True)
        if args.panel_megapixels > 0:
            panel_photo(work, args.panel_megapixels, args.runs, args.size, args.samples)


def panel_photo(work: Path, megapixels: float, runs: int, size: int, samples: int) -> None:
    """The panel case: Paint then Build Canvas on a ``megapixels`` photograph, median of ``runs`` fresh processes."""
    import statistics

    from common import photo  # noqa: E402
    from core.files import writing  # noqa: E402

    image = photo(megapixels)
    path = work / f"photo_{megapixels:g}mp.png"
    writing.write_png(path, image)
    h, w = image.shape[:2]
    del image
    results = [run_case(work, path, "MESH", "panel", size, samples) for _ in range(runs)]
    median = {key: statistics.median(r[key] for r in results) for key in ("paint", "build", "panel")}
    peak = max(r["peak_mib"] for r in results)
    print(f"{'panel':<8} {'MESH':<16} {median['panel']:>8.2f} {peak:>9.0f}  {w}x{h} ({h * w / 1e6:.1f} MP): "
          f"paint {median['paint']:.2f} s + build {median['build']:.2f} s, median of {runs}, target <= 15 s",
          flush=True)


if __name__ == "__main__":
    main()
