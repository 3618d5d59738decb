"""Writing files: EXR and PNG images (whole or a block of rows at a time), JSON and text.

Every writer raises ``OutputError`` with one sentence naming the file and
the problem. Writers go through ``atomic_path``: the data is written to a
temporary file in the same folder and renamed over the target, so a failed
write never leaves a half-written file over a good one. Writers produce the
same bytes for the same data (no timestamps).
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import pathlib
import re
import secrets
from dataclasses import dataclass
from typing import Callable, Dict, Iterator, Optional, Sequence, Tuple, Union

import numpy as np
import OpenImageIO as oiio

from .. import tuning
from ..errors import OutputError, plain_cause
from . import quiet
from .image_files import CHANNEL_ORDER_ATTR, PathLike, oiio_error, reason


@contextlib.contextmanager
def atomic_path(path: PathLike) -> Iterator[pathlib.Path]:
    """Yield a temporary path beside ``path`` (same folder, same extension last).

    The temporary name is ``.<stem>.tmp-<pid>-<random><suffix>``. On normal
    exit the temporary file replaces ``path`` (``os.replace``, atomic on one
    file system); on an exception it is deleted and the exception re-raised,
    leaving any previous ``path`` untouched. A failed rename raises
    OutputError.
    """
    path = pathlib.Path(path)
    temp = path.with_name(f".{path.stem}.tmp-{os.getpid()}-{secrets.token_hex(4)}{path.suffix}")
    try:
        yield temp
    except BaseException:
        _remove_quietly(temp)
        raise
    try:
        os.replace(temp, path)
    except OSError as exc:
        _remove_quietly(temp)
        cause = plain_cause(exc)
        raise OutputError(f"Cannot write {path}: {cause}.", path=path, cause=cause) from exc


TEMPORARY_NAME = re.compile(r"\.[^/]+\.tmp-[0-9]+-[0-9a-f]{8}(\.[^./]+)?")
"""The names ``atomic_path`` gives its temporary files: what a process killed while writing leaves."""


def is_temporary_name(name: str) -> bool:
    """Whether the file name ``name`` is one of ``atomic_path``'s temporary files (``TEMPORARY_NAME``)."""
    return TEMPORARY_NAME.fullmatch(name) is not None


def _remove_quietly(path: pathlib.Path) -> None:
    """Delete ``path`` if it exists; ignore failures."""
    try:
        path.unlink()
    except OSError:
        pass


def ensure_output_dir(path: PathLike) -> pathlib.Path:
    """Create the folder ``path`` (and its parents) and check a file can be written in it.

    Returns the folder as a ``pathlib.Path``. Raises OutputError ("Cannot
    write to output folder X: reason.") when it cannot be created or is not
    writable (checked by creating and deleting a temporary file).
    """
    folder = pathlib.Path(path)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe = folder / f".paint-relief-probe-{os.getpid()}-{secrets.token_hex(4)}"
        with open(probe, "wb"):
            pass
        probe.unlink()
    except OSError as exc:
        raise OutputError(f"Cannot write to output folder {folder}: {plain_cause(exc)}.") from exc
    return folder


def _default_channels(count: int) -> Tuple[str, ...]:
    """Standard EXR channel names for 1, 3 or 4 channels."""
    names = {1: ("Y",), 3: ("R", "G", "B"), 4: ("R", "G", "B", "A")}
    if count not in names:
        raise ValueError(f"Give channel names for {count} channels.")
    return names[count]


def _as_hwc(data: np.ndarray) -> np.ndarray:
    """(H, W) or (H, W, C) -> contiguous float32 (H, W, C)."""
    array = np.asarray(data, dtype=np.float32)
    if array.ndim == 2:
        array = array[:, :, None]
    if array.ndim != 3 or array.shape[0] == 0 or array.shape[1] == 0:
        raise ValueError(f"Image data must be (H, W) or (H, W, C) with H, W > 0, got shape {array.shape}.")
    return np.ascontiguousarray(array)


def _attribute_value(value):
    """str / int / float (NumPy scalars and bools included) for an OpenImageIO header attribute.

    Integers outside the 32-bit range become decimal text so they are stored exactly.
    """
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, bool):
        return int(value)
    if isinstance(value, int) and not -2**31 <= value < 2**31:
        return str(value)  # header integers hold 32 bits: larger ones are kept exactly as text
    if isinstance(value, (str, int, float)):
        return value
    raise ValueError(f"Header attribute values must be str, int or float, got {type(value).__name__}.")


@dataclass(frozen=True)
class RowBlocks:
    """An (H, W, C) float32 image made a block of rows at a time, so a large image is written in little memory.

    shape: (H, W, C); rows(y0, y1) returns float32 (y1 - y0, W, C), the image's rows y0 .. y1 - 1.
    """

    shape: Tuple[int, int, int]
    rows: Callable[[int, int], np.ndarray]

    @classmethod
    def of(cls, data: Union[np.ndarray, "RowBlocks"]) -> "RowBlocks":
        """``data`` itself when it is RowBlocks, else the (H, W) or (H, W, C) array cut into blocks."""
        if isinstance(data, RowBlocks):
            return data
        pixels = _as_hwc(data)
        return cls(pixels.shape, lambda y0, y1: pixels[y0:y1])

    def blocks(self) -> Iterator[Tuple[int, int, np.ndarray]]:
        """(y0, y1, rows) for consecutive blocks of about ``tuning.BLOCK_PIXELS`` pixels (whole multiples of 16 rows)."""
        height, width, channels = self.shape
        step = max(16, tuning.BLOCK_PIXELS // width // 16 * 16)
        for y0 in range(0, height, step):
            y1 = min(height, y0 + step)
            block = self.rows(y0, y1)
            if block.shape != (y1 - y0, width, channels):
                raise ValueError(f"Rows {y0}..{y1} came back with shape {block.shape}.")
            yield y0, y1, block


def _write_with_oiio(path: pathlib.Path, spec, image: RowBlocks,
                     convert: Callable[[np.ndarray], np.ndarray] = None) -> None:
    """Write ``image`` with ``spec`` to ``path`` through a temporary file, a block of rows at a time
    (each passed through ``convert`` first when given); OutputError on any failure."""
    with atomic_path(path) as temp, quiet.captured() as printed:
        oiio.geterror()
        out = oiio.ImageOutput.create(str(temp))
        if out is None:
            raise OutputError(f"Cannot write {path}: {reason(oiio.geterror(), 'no writer for this file type', temp)}.")
        try:
            ok = out.open(str(temp), spec)
            for y0, y1, block in image.blocks() if ok else ():
                pixels = np.ascontiguousarray(convert(block) if convert is not None else block)
                ok = out.write_scanlines(y0, y1, 0, pixels)
                if not ok:
                    break
            error = "" if ok else oiio_error(out)
        finally:
            closed = out.close()
        if not ok or not closed:
            cause = write_failure_cause(temp) or reason(error or oiio_error(out) or printed.text,
                                                        "the image could not be written", temp, path)
            raise OutputError(f"Cannot write {path}: {cause}.", path=path, cause=cause)


PROBE_BYTES = 1 << 20
"""Bytes appended to a file a library failed to write, to learn the operating system's reason."""


def write_failure_cause(temp: pathlib.Path) -> Optional[str]:
    """Why writing the temporary file ``temp`` failed, in plain words ('no space is left on the device'), or None.

    OpenEXR, libpng and libjpeg report only that writing failed ('Failed to write pixel data ... File output
    failed'). The file is about to be deleted anyway, so PROBE_BYTES more are appended to it and flushed: the
    error the operating system gives (no space, a quota, the file size limit, a device error) is the cause.
    None when that write goes through (the library failed for a reason of its own).
    """
    try:
        with open(temp, "ab") as f:
            f.write(bytes(PROBE_BYTES))
            f.flush()
            os.fsync(f.fileno())
    except OSError as exc:
        return plain_cause(exc)
    return None


def write_exr(path: PathLike, data: Union[np.ndarray, RowBlocks], channels: Optional[Sequence[str]] = None,
              half: bool = False, attributes: Optional[Dict[str, object]] = None,
              compression: str = "zip") -> None:
    """Write float32 (H, W) or (H, W, C) ``data`` (or RowBlocks) as an OpenEXR file, zip-compressed unless
    ``compression`` names another lossless OpenEXR compression ("rle", "zips", "piz", "none").

    ``channels`` names the C channels (default Y / R,G,B / R,G,B,A for 1 / 3 / 4
    channels); ``half=True`` stores 16-bit half floats, otherwise 32-bit
    floats. Values are written as given (scene-linear for colour).
    ``attributes`` maps header names to str / int / float values (for example
    "paint_relief:params", "paint_relief:seed"). The channel order is also
    stored (``paint_relief:channel_order``) so ``read_exr`` returns it. No
    time stamp is written: the same arguments give the same bytes. The file
    is written atomically; any failure raises OutputError naming it.
    """
    path = pathlib.Path(path)
    image = RowBlocks.of(data)
    height, width, count = image.shape
    names = tuple(channels) if channels is not None else _default_channels(count)
    if len(names) != count:
        raise ValueError(f"{len(names)} channel names given for {count} channels.")
    spec = oiio.ImageSpec(width, height, count, "half" if half else "float")
    spec.channelnames = names
    spec.alpha_channel = names.index("A") if "A" in names else -1
    spec.attribute("compression", compression)
    spec.attribute("DateTime", "")  # an empty DateTime stops OpenImageIO from stamping the current time
    spec.attribute(CHANNEL_ORDER_ATTR, ",".join(names))
    for name, value in (attributes or {}).items():
        spec.attribute(str(name), _attribute_value(value))
    _write_with_oiio(path, spec, image)


PNG_COMPRESSION = 3
"""zlib level of the PNGs: level 3 is several times faster than the highest and the files about 10 % larger."""


PNG_UNFILTERED = 8
"""libpng's PNG_FILTER_NONE: rows compressed as they are, about twice as fast to write as libpng's adaptive
filtering for a fifth more bytes."""


def write_png(path: PathLike, data: Union[np.ndarray, RowBlocks], bits: int = 8,
              level: int = PNG_COMPRESSION, filters: Optional[int] = None) -> None:
    """Write float32 (H, W) or (H, W, 3|4) sRGB-encoded ``data`` (or RowBlocks) in [0, 1] as an 8- or 16-bit PNG,
    zlib ``level`` (0 to 9) compressed, with libpng's row ``filters`` (a PNG_FILTER_* mask such as
    ``PNG_UNFILTERED``; None: libpng's choice).

    Values are quantised as ``floor(v * maxval + 0.5)`` clipped to
    [0, maxval] (maxval 255 or 65535; NaN becomes 0); RowBlocks whose rows are
    uint8 (8 bits) or uint16 (16 bits) are written as they are. Four channels are RGB
    plus straight (not premultiplied) alpha. Same data gives same bytes; the
    file is written atomically; failures raise OutputError naming it.
    """
    if bits not in (8, 16):
        raise ValueError(f"PNG bits must be 8 or 16, got {bits}.")
    image = RowBlocks.of(data)
    height, width, count = image.shape
    if count not in (1, 3, 4):
        raise ValueError(f"PNG data needs 1, 3 or 4 channels, got {count}.")
    dtype, fmt = (np.uint8, "uint8") if bits == 8 else (np.uint16, "uint16")
    maxval = float(np.iinfo(dtype).max)

    def quantise(block: np.ndarray) -> np.ndarray:
        if block.dtype == dtype:                     # quantised already (``RowBlocks`` of ``dtype`` rows)
            return block
        values = np.nan_to_num(block.astype(np.float32), nan=0.0, copy=False)   # a float32 copy, then in place
        values *= np.float32(maxval)
        values += np.float32(0.5)
        np.floor(values, out=values)
        np.clip(values, 0.0, maxval, out=values)
        return values.astype(dtype)

    spec = oiio.ImageSpec(width, height, count, fmt)
    if count == 4:
        spec.attribute("oiio:UnassociatedAlpha", 1)
    spec.attribute("DateTime", "")
    spec.attribute("png:compressionLevel", int(level))
    if filters is not None:
        spec.attribute("png:filter", int(filters))
    _write_with_oiio(pathlib.Path(path), spec, image, quantise)


def _json_default(value):
    """JSON form of NumPy scalars and arrays and of paths."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    raise TypeError(f"Object of type {type(value).__name__} is not JSON serialisable")


def write_json(path: PathLike, obj, indent: Optional[int] = 2) -> None:
    """Write ``obj`` as strict JSON (``indent`` spaces, None for compact; keys in given order; final newline),
    atomically.

    NumPy scalars and arrays and paths are converted to plain JSON values; a
    float that is NaN or infinite (a figure with no value) is written as
    null, so strict parsers read the file. Failures to write raise
    OutputError naming the file.
    """
    separators = None if indent is not None else (",", ":")
    options = dict(indent=indent, separators=separators, sort_keys=False, default=_json_default, allow_nan=False)
    try:
        text = json.dumps(obj, **options)
    except ValueError:
        text = json.dumps(finite_or_null(obj), **options)
    write_text(path, text + "\n")


def finite_or_null(value):
    """``value`` (dicts, lists and tuples of JSON values, NumPy scalars and arrays) with every NaN or infinite
    float replaced by None, recursively; containers become dicts and lists, other values are kept."""
    if isinstance(value, dict):
        return {key: finite_or_null(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite_or_null(item) for item in value]
    if isinstance(value, np.ndarray):
        return finite_or_null(value.tolist())
    if isinstance(value, np.generic):
        return finite_or_null(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def write_text(path: PathLike, text: str) -> None:
    """Write UTF-8 ``text`` atomically; failures raise OutputError naming the file."""
    path = pathlib.Path(path)
    with atomic_path(path) as temp:
        try:
            temp.write_text(text, encoding="utf-8")
        except OSError as exc:
            cause = plain_cause(exc)
            raise OutputError(f"Cannot write {path}: {cause}.", path=path, cause=cause) from exc
