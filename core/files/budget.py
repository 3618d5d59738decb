"""Memory and disk budgets decided before any work: what a run will need against what the machine has.

``estimate_bytes`` counts the full-image arrays a run holds at its peak, per
pixel, plus a fixed base for the libraries and the free heap kept for reuse; ``available_bytes`` reads what
the machine can give (``MemAvailable`` of /proc/meminfo, a cgroup limit,
RLIMIT_AS); ``check`` refuses with one sentence when the estimate is above
the limit. ``check_space`` does the same for the bytes a painting writes
against the free space of the output folder's file system. All of it reads
only the image's header, so a refusal takes well under a second whatever the
image's size.
"""

from __future__ import annotations

import math
import os
import pathlib
import re
import shutil
from typing import Optional

from ..errors import InputError, OutputError, ParameterError
from ..heap import TRIM_THRESHOLD

# Bytes per pixel of the arrays alive at a run's peak (float32 unless said).
PER_PIXEL = {
    "decoded file (native samples + float32 RGB(A))": 4 + 16,
    "input image (H, W, 3)": 12,
    "analysis: reference (H, W, 3), intensity, importance, orientation": 24,
    "analysis working arrays (bilateral grid, Sobel, structure tensor float64, summed-area table)": 56,
    "canvas: colour (H, W, 3), coverage, height, opacity": 24,
    "colour sources: the reference smoothed at each brush's scale (up to three levels at full size)": 36,
}
BYTES_PER_PIXEL = sum(PER_PIXEL.values())
"""Sum of PER_PIXEL: 172 bytes; the measured peak resident memory is 130-160 bytes per pixel at 16 megapixels.
Writing makes its images a block of rows at a time (``writing.RowBlocks``): no full-size arrays of its own."""
MASK_BYTES_PER_PIXEL = 16
"""A user mask: the decoded file and its float32 copy, resized to the image."""
BASE_BYTES = 200 * 2**20
"""Python, NumPy, SciPy and OpenImageIO themselves, and the stroke list."""
ROUND_BYTES = 320 * 2**20
"""A round of strokes at work, whatever the image size: its chunks of anchors, plans and footprints
(``core.strokes.rounds`` bounds each), measured at about 250 bytes a track sample of a laying chunk."""
HEAP_BYTES = TRIM_THRESHOLD
"""Freed memory the C heap keeps for reuse while painting (``core.heap``), at most this."""

BOMB_PIXELS_PER_BYTE = 500.0
"""An image stored in fewer than 1 byte per this many pixels is a decompression bomb (above BOMB_MIN_PIXELS)."""
BOMB_MIN_PIXELS = 16_000_000

_UNITS = {"": 2**20, "k": 2**10, "m": 2**20, "g": 2**30, "t": 2**40}


def estimate_bytes(width: int, height: int, layers: int = 4, mask: bool = False) -> int:
    """Peak memory (bytes) of painting a ``width`` x ``height`` image and writing its outputs.

    ``layers`` changes only the stroke list (a few hundred bytes a stroke,
    a few thousand strokes a layer), counted in BASE_BYTES up to 16 layers.
    """
    pixels = int(width) * int(height)
    per_pixel = BYTES_PER_PIXEL + (MASK_BYTES_PER_PIXEL if mask else 0)
    return BASE_BYTES + ROUND_BYTES + HEAP_BYTES + pixels * per_pixel + max(0, int(layers) - 16) * 2**20


def _meminfo_available() -> Optional[int]:
    try:
        with open("/proc/meminfo", encoding="ascii") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        return None
    return None


def _cgroup_available() -> Optional[int]:
    """memory.max - memory.current of this process's cgroup (v2), or None when unlimited or unknown."""
    try:
        with open("/proc/self/cgroup", encoding="ascii") as f:
            rel = next((line.strip().split(":", 2)[2] for line in f if line.startswith("0::")), None)
        if rel is None:
            return None
        base = pathlib.Path("/sys/fs/cgroup") / rel.lstrip("/")
        limit = (base / "memory.max").read_text().strip()
        if limit == "max":
            return None
        return max(0, int(limit) - int((base / "memory.current").read_text().strip()))
    except (OSError, ValueError, StopIteration):
        return None


def _rlimit_available() -> Optional[int]:
    """RLIMIT_AS minus this process's address space, or None when unlimited."""
    try:
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_AS)
        if soft == resource.RLIM_INFINITY:
            return None
        with open("/proc/self/statm", encoding="ascii") as f:
            size = int(f.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
        return max(0, soft - size)
    except (ImportError, OSError, ValueError, AttributeError):
        return None


def available_bytes() -> Optional[int]:
    """Memory this process can still use (bytes): the smallest of the known limits, None when none is known."""
    known = [v for v in (_meminfo_available(), _cgroup_available(), _rlimit_available()) if v is not None]
    return min(known) if known else None


def parse_size(text: str, option: str = "--max-memory") -> int:
    """'512M', '2G', '1.5g', '800' (MiB) -> bytes; ParameterError (one sentence) for anything else."""
    match = re.fullmatch(r"\s*([0-9]*\.?[0-9]+(?:[eE][+-]?[0-9]+)?)\s*([kKmMgGtT]?)(?:i?[bB])?\s*", str(text))
    value = float(match.group(1)) * _UNITS[match.group(2).lower()] if match else math.nan
    if not math.isfinite(value) or value <= 0:
        raise ParameterError(f"The option {option} must be a positive size such as 512M or 4G, got {text!r}.")
    return int(value)


def format_bytes(n: float) -> str:
    """Bytes as '1.2 GB' / '350 MB' / '12 KB' / '512 bytes' (powers of 1024); never shown as zero of a unit."""
    if n >= 2**30:
        return f"{n / 2**30:.1f} GB"
    if n >= 2**20:
        return f"{round(n / 2**20)} MB"
    if n >= 2**10:
        return f"{round(n / 2**10)} KB"
    return f"{int(n)} bytes"


def format_megapixels(pixels: int) -> str:
    """A pixel count as '12.0 megapixels', with two significant digits below 0.1 ('0.0069 megapixels')."""
    mp = pixels / 1e6
    return f"{mp:.1f} megapixels" if mp >= 0.1 else f"{mp:.2g} megapixels"


def check_stroke_sizes(params, height: int, width: int) -> None:
    """ParameterError when a stroke size, scaled to this image, is larger than the image: refused, never dropped.

    A size is larger than the image when its brush, scaled to the image
    (``params.scaled_sizes``), is wider than the image's longer side, or
    wider than its shorter side and wider than the largest default brush
    scaled alike: so ``--sizes 900`` on a 96 x 72 image (a 75 px brush) is
    refused, while the defaults paint any image, a 1 x 4000 strip included.
    The sentence names the option (--sizes, the panel's Stroke Sizes).
    """
    from ..params import Params, scaled_sizes

    longest, shortest = max(int(height), int(width)), min(int(height), int(width))
    default_widest = max(scaled_sizes(Params(), height, width))
    limit = max(shortest, default_widest)
    for size in sorted(params.stroke_sizes, reverse=True):
        scaled = scaled_sizes(params.replace(stroke_sizes=(size,)), height, width)[0]
        if scaled <= limit:
            continue
        what = (f"The stroke size {size} in --sizes (the panel's Stroke Sizes) becomes {scaled} px "
                f"on this {width} x {height} image")
        if scaled > max(longest, 2):
            raise ParameterError(f"{what}, wider than the image itself.")
        raise ParameterError(f"{what}, larger than the image's {shortest} px side; sizes are px at 1 megapixel, "
                             f"so give sizes up to {_largest_fitting(params, height, width, limit)}.")


def _largest_fitting(params, height: int, width: int, side: int) -> int:
    """The largest stroke size (px at 1 megapixel) whose brush, scaled to a ``width`` x ``height`` image, is at
    most ``side`` px wide."""
    scale = math.sqrt(int(height) * int(width) / (params.size_reference_megapixels * 1e6))
    size = max(1, int((side + 0.5) / scale))
    while size > 1 and round(size * scale) > side:
        size -= 1
    return size


def check_bomb(path, width: int, height: int) -> None:
    """InputError when a large image is stored in far fewer bytes than its pixels could ever compress to."""
    pixels = int(width) * int(height)
    try:
        size = max(1, os.path.getsize(path))
    except OSError:
        return
    if pixels >= BOMB_MIN_PIXELS and pixels / size > BOMB_PIXELS_PER_BYTE:
        raise InputError(f"The image {path} holds {width} x {height} pixels in only {size} bytes "
                         f"({pixels / size:.0f} pixels per byte), a decompression bomb; its pixels were not decoded.")


def check(path, width: int, height: int, layers: int = 4, mask: bool = False,
          max_memory: Optional[int] = None) -> int:
    """Refuse (InputError, one sentence) a run whose estimate exceeds ``max_memory`` or the available memory.

    Returns the estimate in bytes. When neither a limit is given nor any is
    known, nothing is refused.
    """
    need = estimate_bytes(width, height, layers, mask)
    if max_memory is not None:
        limit, what = int(max_memory), f"the --max-memory limit of {format_bytes(max_memory)}"
    else:
        limit = available_bytes()
        what = f"the {format_bytes(limit)} of memory available" if limit is not None else ""
    if limit is not None and need > limit:
        raise InputError(f"Painting {path} ({width} x {height} pixels, {format_megapixels(width * height)}) "
                         f"needs about {format_bytes(need)} of memory, more than {what}.")
    return need


OUTPUT_BYTES_PER_PIXEL = 3.0
"""Bytes a painting's folder takes per image pixel, at the least (normal.exr not counted).

Measured on painted folders (maps, PNGs, strokes.json, report): a flat gray
400 x 300 image 8.6 bytes per pixel, the 451 x 300 cat photograph 24, a
200 x 150 image of noise 62; larger images hold fewer strokes per pixel and
smoother maps. The figure is a floor, so a refusal for lack of space is
certain; a disk that fills up anyway is reported when writing, and the
folder is left as it was (``staging``)."""
NORMAL_BYTES_PER_PIXEL = 1.0
"""normal.exr's floor in bytes per pixel (1.9 for the flat image above, 3.8 for the cat)."""


def estimate_output_bytes(width: int, height: int, normal_map: bool = False, timelapse_bytes: int = 0) -> int:
    """The fewest bytes painting a ``width`` x ``height`` image writes (every output file together), with
    ``timelapse_bytes`` per pixel more for a time-lapse."""
    per_pixel = OUTPUT_BYTES_PER_PIXEL + (NORMAL_BYTES_PER_PIXEL if normal_map else 0.0) + timelapse_bytes
    return int(math.ceil(int(width) * int(height) * per_pixel))


def free_bytes(folder) -> Optional[int]:
    """Bytes this process may still write on the file system of ``folder`` (or of its nearest existing parent,
    when it does not exist yet); None when that cannot be told, as on system file systems such as /proc, which
    have no size at all."""
    path = pathlib.Path(os.path.abspath(folder))
    while not path.exists() and path.parent != path:
        path = path.parent
    try:
        usage = shutil.disk_usage(path)
    except OSError:
        return None
    return usage.free if usage.total > 0 else None


def check_space(folder, source, width: int, height: int, normal_map: bool = False, timelapse_bytes: int = 0) -> int:
    """Refuse (OutputError, one sentence naming ``folder``) painting ``source`` into ``folder`` when its file
    system has less free space than the painting will take (``timelapse_bytes`` per pixel more for a
    time-lapse); returns the estimate in bytes.

    The whole new painting is written before the files it replaces go, so
    the files already in ``folder`` do not count as free.
    """
    need = estimate_output_bytes(width, height, normal_map, timelapse_bytes)
    free = free_bytes(folder)
    if free is not None and need > free:
        raise OutputError(f"Cannot paint {source} into the output folder {folder}: not enough space is left on "
                          f"the device, {format_bytes(free)} free where painting its {width} x {height} pixels "
                          f"needs at least {format_bytes(need)}.")
    return need
