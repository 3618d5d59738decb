"""Benchmark of what painting across UV seams costs against painting the islands apart, and how the seams look
(ALGORITHM §10, strokes across seams).

Meshes built in NumPy (``tests/seam_meshes.py``), each with a colour that is a
smooth function of the 3-D position baked into its UV layout (a source that
runs on over the seams):

- a UV sphere of 16 x 8 (radius 0.5 m) at 1024 texels with strokes of
  750, 375, 188, 94 and 47 mm: its widest strokes are about 400 texels, wide
  against its one island, the case whose canvas across the seams grew up to
  twice as wide again before the apron's area was bounded
  (``apron.APRON_AREA``);
- the same sphere at 1024 texels with its default strokes;
- a cube of six islands at 512 texels, default strokes;
- a UV sphere of 48 x 24 at 512 texels, default strokes.

Each texture is painted (``surface_layout`` then ``paint_texture``, seed 0)
with its islands apart and across its seams, alternating, ``--runs`` times
each, every run in a child process of its own (forked), so each one's
processor seconds (user + system, all threads) and peak resident memory
(ru_maxrss, the child's, the parent's meshes and sources included) are its
own. Printed for each mesh: texture size, strokes, the median wall-clock and
processor seconds of both and the ratios across / apart, the largest peak
memory of each, and the seam / inner step ratios (``seams.texture_steps``)
of the source, the painting apart and the painting across, with the
painting's ratio over the source's.

Usage: python bench/seam_cost.py [--runs 3] [--only NAME]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time

from common import ROOT

sys.path.insert(0, str(ROOT / "tests"))

from seam_meshes import baked, cube, uv_sphere  # noqa: E402

from core.params import Params  # noqa: E402
from core.surface.seams import texture_steps  # noqa: E402
from core.surface.texture import paint_texture, surface_layout  # noqa: E402

WIDE_STROKES = (750.0, 375.0, 188.0, 94.0, 47.0)
"""mm: strokes about 400 texels wide at the widest on the 16 x 8 sphere at 1024 texels (1.9 mm a texel)."""

CASES = {
    "sphere16-wide": ("UV sphere 16 x 8, wide strokes", lambda: uv_sphere(16, 8), 1024, WIDE_STROKES),
    "sphere16": ("UV sphere 16 x 8", lambda: uv_sphere(16, 8), 1024, None),
    "cube": ("cube, 6 islands", cube, 512, None),
    "sphere48": ("UV sphere 48 x 24", lambda: uv_sphere(48, 24), 512, None),
}
"""name: (label, mesh maker, texture size in texels, stroke widths in mm or None for the default)."""


def in_child(work) -> tuple:
    """Run ``work()`` (returning a JSON-able value) in a forked child: (its value, wall seconds, processor seconds
    of the child (user + system), its peak resident MiB)."""
    read, write = os.pipe()
    start = time.perf_counter()
    pid = os.fork()
    if pid == 0:                                            # the child
        os.close(read)
        code = 0
        try:
            data = json.dumps(work()).encode()
        except BaseException as error:                     # noqa: BLE001 - reported by the parent
            data, code = json.dumps({"error": repr(error)}).encode(), 1
        with os.fdopen(write, "wb") as out:
            out.write(data)
        os._exit(code)
    os.close(write)
    with os.fdopen(read, "rb") as source:
        data = source.read()
    _, status, usage = os.wait4(pid, 0)
    seconds = time.perf_counter() - start
    value = json.loads(data)
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"a painting failed: {value.get('error')}")
    return value, seconds, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024.0


def ratio(steps: dict) -> float:
    """The seam step over the inner step."""
    return steps["seam"] / steps["inner"]


def measure(name: str, runs: int) -> dict:
    """Figures of case ``name`` of ``CASES`` (module docstring)."""
    label, make, size, stroke_mm = CASES[name]
    mesh = make()
    source = baked(mesh, size)

    def painting(across: bool):
        def work():
            layout = surface_layout(mesh, size, across)
            painted = paint_texture(source, layout, Params(seed=0), stroke_mm)
            steps = texture_steps(painted.colour, layout.edges)
            return {"strokes": painted.statistics["strokes"], "ratio": ratio(steps),
                    "source": ratio(texture_steps(source, layout.edges)),
                    "stroke_mm": painted.statistics["stroke_mm"]}
        return work

    found = {False: [], True: []}
    for _ in range(runs):
        for across in (False, True):
            found[across].append(in_child(painting(across)))
    out = {"label": label, "size": size}
    for across, key in ((False, "apart"), (True, "across")):
        values = found[across]
        out[key] = {"wall": statistics.median(v[1] for v in values), "cpu": statistics.median(v[2] for v in values),
                    "mib": max(v[3] for v in values), "strokes": values[0][0]["strokes"],
                    "ratio": values[0][0]["ratio"]}
        out["source"] = values[0][0]["source"]
        out["stroke_mm"] = values[0][0]["stroke_mm"]
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3, help="runs of each, apart and across alternating (medians)")
    parser.add_argument("--only", choices=sorted(CASES), action="append", help="measure only these cases")
    args = parser.parse_args()
    print(f"seed 0, {args.runs} runs each, apart and across alternating, each run in a child process; seconds are "
          f"medians, MiB the largest peak resident memory; seam / inner step ratios")
    print(f"{'mesh':<31}{'size':>5}{'strokes apart/across':>21}{'wall apart/across':>19}{'ratio':>6}"
          f"{'cpu apart/across':>18}{'ratio':>6}{'MiB apart/across':>17}{'source':>7}{'apart':>7}{'across':>7}"
          f"{'across/src':>11}")
    for name in args.only or list(CASES):
        f = measure(name, args.runs)
        apart, across = f["apart"], f["across"]
        print(f"{f['label']:<31}{f['size']:>5}{apart['strokes']:>11}/{across['strokes']:<9}"
              f"{apart['wall']:>10.2f}/{across['wall']:<8.2f}{across['wall'] / apart['wall']:>6.2f}"
              f"{apart['cpu']:>9.2f}/{across['cpu']:<8.2f}{across['cpu'] / apart['cpu']:>6.2f}"
              f"{apart['mib']:>8.0f}/{across['mib']:<8.0f}{f['source']:>7.3f}{apart['ratio']:>7.3f}"
              f"{across['ratio']:>7.3f}{across['ratio'] / f['source']:>11.2f}", flush=True)
    print("strokes of the default rows (mm): the still's widths at the median texel (texture.default_stroke_mm); "
          f"wide: {', '.join(f'{w:g}' for w in WIDE_STROKES)}")


if __name__ == "__main__":
    main()
