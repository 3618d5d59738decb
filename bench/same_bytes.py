"""SHA-256 of every file `core paint` writes, for photographs times methods times height modes.

A change that must not change a painting (a refactor, a speed-up) is
checked by running this before and after and comparing the two lists:
each line is `photo method height_mode file sha256`. report.json is left
out (it holds seconds). Each painting runs `python -m core paint` as a
user would, at default settings and seed 0, with one of the methods
(huang11, hertzmann98) and height modes (over, accumulate); --sizes N
resamples each photograph (bilinear) to N megapixels first.
Usage: python bench/same_bytes.py [--photos coffee,chelsea,astronaut,PATH...] [--sizes MP] [-o LIST]
"""

from __future__ import annotations

import argparse
import hashlib
import subprocess
import sys
import tempfile
from pathlib import Path

from common import ROOT, photo
from core.files import writing

METHODS = ("huang11", "hertzmann98")
HEIGHT_MODES = ("over", "accumulate")


def source_path(name: str) -> Path:
    """A bundled photograph by its stem (coffee, chelsea, astronaut, hubble) or any image path."""
    if Path(name).is_file():
        return Path(name)
    bundled = sorted((ROOT / "sample_scenes").glob(name + ".*"))
    if not bundled:
        raise SystemExit(f"same_bytes: no photograph {name} (neither a file nor a bundled sample)")
    return bundled[0]


def digests(folder: Path) -> dict:
    """{file name: sha256 hex} of every file in ``folder`` but report.json."""
    return {path.name: hashlib.sha256(path.read_bytes()).hexdigest()
            for path in sorted(folder.iterdir()) if path.name != "report.json"}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--photos", default="coffee,chelsea,astronaut")
    parser.add_argument("--megapixels", type=float, default=0.0, help="resample to this size first (0: as is)")
    parser.add_argument("-o", "--output", type=Path, help="also write the list here")
    args = parser.parse_args()
    lines = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.photos.split(","):
            image = source_path(name)
            if args.megapixels:
                resized = Path(tmp) / f"{image.stem}.png"
                writing.write_png(resized, photo(args.megapixels, image))
                image = resized
            for method in METHODS:
                for mode in HEIGHT_MODES:
                    out = Path(tmp) / f"{image.stem}-{method}-{mode}"
                    subprocess.run([sys.executable, "-m", "core", "paint", str(image), "-o", str(out), "-q",
                                    "--method", method, "--height-mode", mode], cwd=ROOT, check=True)
                    for file, digest in digests(out).items():
                        lines.append(f"{image.stem} {method} {mode} {file} {digest}")
                        print(lines[-1], flush=True)
    if args.output:
        args.output.write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
