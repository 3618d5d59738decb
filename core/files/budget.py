"""Memory budgets decided before any work: what a run will need against what the machine has.

``estimate_bytes`` counts the full-image arrays a run holds at its peak, per
pixel, plus a fixed base for the libraries and the free heap kept for reuse; ``available_bytes`` reads what
the machine can give (``MemAvailable`` of /proc/meminfo, a cgroup limit,
RLIMIT_AS); ``check`` refuses with one sentence when the estimate is above
the limit. All of it reads only the image's header, so a refusal takes well
under a second whatever the image's size.
"""

from __future__ import annotations

import math
import os
import pathlib
import re
from typing import Optional

from ..errors import InputError, ParameterError
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
"""Sum of PER_PIXEL: 172 bytes; the measured peak resident memory is about 125 bytes per pixel at 16 megapixels.
Writing makes its images a block of rows at a time (``io.RowBlocks``): no full-size arrays of its own."""
MASK_BYTES_PER_PIXEL = 16
"""A user mask: the decoded file and its float32 copy, resized to the image."""
BASE_BYTES = 200 * 2**20
"""Python, NumPy, SciPy and OpenImageIO themselves, and the stroke list."""
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
    return BASE_BYTES + HEAP_BYTES + pixels * per_pixel + max(0, int(layers) - 16) * 2**20


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
    """ParameterError when a stroke size, scaled to this image, is wider than the image's longer side."""
    from ..params import scaled_sizes

    longest = max(int(height), int(width))
    widest = max(scaled_sizes(params, height, width))
    if widest > max(longest, 2):
        raise ParameterError(f"The largest stroke size {max(params.stroke_sizes)} px becomes {widest} px on this "
                             f"{width} x {height} image, wider than the image itself.")


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
