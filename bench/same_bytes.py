"""SHA-256 of every file `core paint`, `core sequence` and `core object` write, over photographs, methods and
height modes.

A change that must not change a painting (a refactor, a speed-up) is
checked by running this before and after and comparing the two lists:
each line is `photo method height_mode file sha256` for a still,
`shot-photo huang11 height_mode file sha256` for a shot and
`texture-photo huang11 height_mode file sha256` for a texture. report.json
is left out (it holds seconds). Each painting runs `python -m core` as a
user would, at default settings and seed 0, with each height mode (over,
accumulate):

- a still of each photograph with each method (huang11, hertzmann98);
  --megapixels N resamples each photograph (bilinear) to N megapixels first;
- with --shot-frames K (default 5; 0: none), a shot of the first
  photograph: K frames of a 320 x 240 window panning 6 px a frame to the
  right over it (`core sequence`, the paper's method, which is the one a
  shot paints);
- with --texture-size N (default 512; 0: none), the demo box's texture
  (sample_scenes/object_scene.py) read through the first photograph,
  painted N x N (`core object`).

Each command's wall seconds go to stderr, and with --times FILE as lines
`kind photo method height_mode seconds` to FILE, so two runs can be timed
side by side.
Usage: python bench/same_bytes.py [--photos coffee,chelsea,astronaut,PATH...] [--megapixels MP]
       [--shot-frames K] [--texture-size N] [-o LIST] [--times FILE]
"""

from __future__ import annotations

import argparse
import hashlib
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from common import ROOT, photo
from core.files import reading, writing

sys.path.insert(0, str(ROOT / "sample_scenes"))

import object_scene  # noqa: E402

METHODS = ("huang11", "hertzmann98")
HEIGHT_MODES = ("over", "accumulate")
SHOT_WINDOW = (320, 240)
"""px (width, height) of a shot's frame, a window over the photograph."""
SHOT_PAN = 6
"""px the shot's window moves to the right each frame."""


def source_path(name: str) -> Path:
    """A bundled photograph by its stem (coffee, chelsea, astronaut, hubble) or any image path."""
    if Path(name).is_file():
        return Path(name)
    bundled = sorted((ROOT / "sample_scenes").glob(name + ".*"))
    if not bundled:
        raise SystemExit(f"same_bytes: no photograph {name} (neither a file nor a bundled sample)")
    return bundled[0]


def digests(folder: Path) -> dict:
    """{file name (relative to ``folder``): sha256 hex} of every file in ``folder`` and its subfolders but
    report.json."""
    return {path.relative_to(folder).as_posix(): hashlib.sha256(path.read_bytes()).hexdigest()
            for path in sorted(folder.rglob("*")) if path.is_file() and path.name != "report.json"}


def shot_frames(image: Path, frames: int, folder: Path) -> Path:
    """``folder`` holding ``frames`` PNG frames, frame_0001.png on: a SHOT_WINDOW window over ``image`` from its
    top left corner, SHOT_PAN px further right each frame (its width must hold them)."""
    picture = reading.read_image(image)
    width, height = SHOT_WINDOW
    folder.mkdir(parents=True)
    for frame in range(frames):
        left = frame * SHOT_PAN
        writing.write_png(folder / f"frame_{frame + 1:04d}.png", picture[:height, left:left + width])
    return folder


def painted(arguments: list, out: Path, times: list, label: str) -> dict:
    """Run ``python -m core`` with ``arguments`` into ``out``, quietly, as a user would; record its wall seconds
    in ``times`` as ``label seconds`` (and print it on stderr); return ``digests(out)``."""
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "core", *map(str, arguments), "-o", str(out), "-q"], cwd=ROOT, check=True)
    times.append(f"{label} {time.perf_counter() - start:.3f}")
    print(times[-1], file=sys.stderr, flush=True)
    return digests(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--photos", default="coffee,chelsea,astronaut")
    parser.add_argument("--megapixels", type=float, default=0.0, help="resample to this size first (0: as is)")
    parser.add_argument("--shot-frames", type=int, default=5, help="frames of the shot (0: no shot)")
    parser.add_argument("--texture-size", type=int, default=512, help="texels a side of the texture (0: none)")
    parser.add_argument("-o", "--output", type=Path, help="also write the list here")
    parser.add_argument("--times", type=Path, help="also write each command's wall seconds here")
    args = parser.parse_args()
    lines, times = [], []

    def listed(kind: str, method: str, mode: str, found: dict) -> None:
        for file, digest in found.items():
            lines.append(f"{kind} {method} {mode} {file} {digest}")
            print(lines[-1], flush=True)

    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        photos = []
        for name in args.photos.split(","):
            image = source_path(name)
            if args.megapixels:
                resized = tmp / f"{image.stem}.png"
                writing.write_png(resized, photo(args.megapixels, image))
                image = resized
            photos.append(image)
            for method in METHODS:
                for mode in HEIGHT_MODES:
                    listed(image.stem, method, mode,
                           painted(["paint", image, "--method", method, "--height-mode", mode],
                                   tmp / f"{image.stem}-{method}-{mode}", times, f"still {image.stem} {method} {mode}"))
        first = photos[0]
        if args.shot_frames:
            clip = shot_frames(first, args.shot_frames, tmp / "shot")
            for mode in HEIGHT_MODES:
                listed(f"shot-{first.stem}", "huang11", mode,
                       painted(["sequence", clip, "--height-mode", mode], tmp / f"shot-{mode}", times,
                               f"shot {first.stem} huang11 {mode}"))
        if args.texture_size:
            mesh = object_scene.box_obj(tmp / "box.obj")
            for mode in HEIGHT_MODES:
                listed(f"texture-{first.stem}", "huang11", mode,
                       painted(["object", first, "--mesh", mesh, "--texture-size", args.texture_size,
                                "--height-mode", mode], tmp / f"texture-{mode}", times,
                               f"texture {first.stem} huang11 {mode}"))
    if args.output:
        args.output.write_text("\n".join(lines) + "\n")
    if args.times:
        args.times.write_text("\n".join(times) + "\n")


if __name__ == "__main__":
    main()
