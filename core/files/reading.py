"""Reading images: photographs, masks and brush maps as sRGB values, EXR maps as stored, headers and image counts.

A Blender multilayer EXR (one part per pass, or one part whose channels are
named ``<ViewLayer>.<Pass>.<Channel>``) is one picture, its ``Combined``
pass; ``read_pass`` reads any other pass, such as ``Vector``, as stored.

Every reader raises ``InputError`` with one sentence naming the file and the
problem: missing, a folder, a URL, unreadable, truncated, empty, above the
pixel limit (checked from the header before any pixel is decoded) or holding
NaN or infinite values.
"""

from __future__ import annotations

import contextlib
import os
import pathlib
import re
import stat
import struct
from typing import Dict, Iterator, List, Optional, Sequence, Tuple

import numpy as np
import OpenImageIO as oiio

from ..colour import linear_to_srgb, luminance
from ..errors import InputError, plain_cause
from ..params import CANVAS_COLOUR
from . import quiet
from .image_files import CHANNEL_ORDER_ATTR, PathLike, oiio_error, reason

# File formats whose pixel values are scene-linear whatever their header says.
_LINEAR_FORMATS = {"openexr", "hdr"}
_LINEAR_EXTENSIONS = {".exr", ".hdr", ".sxr", ".mxr"}
# Colour-space names (lower case) that mean scene-linear data.
_LINEAR_SPACES = {"linear", "scene_linear", "acescg", "aces2065-1"}


def _noun(role: str) -> str:
    """What a file of ``role`` ('input', 'mask', 'brush map') is called in a sentence about its pixels."""
    return "image" if role == "input" else role


def check_input_path(path: pathlib.Path, role: str = "input") -> None:
    """Raise InputError when ``path`` is missing, a dangling symbolic link, a folder, empty or not readable.

    ``role`` names the file in the sentence: 'The input file ...', 'The mask file ...'.
    """
    what = f"The {role} file {path}"
    try:
        info = os.stat(path)
    except FileNotFoundError:
        if path.is_symlink():
            raise InputError(f"{what} is a symbolic link whose target {os.readlink(path)} does not exist.") from None
        raise InputError(f"{what} does not exist.") from None
    except NotADirectoryError:
        raise InputError(f"{what} does not exist: a part of its path is a file, not a folder.") from None
    except PermissionError:
        raise InputError(f"{what} cannot be reached: permission denied on a folder above it.") from None
    except OSError as exc:
        raise InputError(f"{what} cannot be read: {plain_cause(exc)}.") from None
    if stat.S_ISDIR(info.st_mode):
        raise InputError(f"The {role} {path} is a folder, not an image file.")
    if info.st_size == 0:
        raise InputError(f"{what} is empty (0 bytes).")
    try:
        with open(path, "rb"):
            pass
    except OSError as exc:
        raise InputError(f"{what} cannot be read: {plain_cause(exc)}.") from None


def _is_linear(path: pathlib.Path, format_name: str, spec) -> bool:
    """True when the file holds scene-linear values (EXR/HDR, or a linear colour space in its header)."""
    if format_name.lower() in _LINEAR_FORMATS or path.suffix.lower() in _LINEAR_EXTENSIONS:
        return True
    space = str(spec.get_string_attribute("oiio:ColorSpace", "")).lower()
    return space in _LINEAR_SPACES or space.startswith("lin_")


URL = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*://")
"""A URL's scheme (https://, file://, s3://): the painter reads local files only."""


def local_path(path: PathLike, role: str = "input") -> pathlib.Path:
    """``path`` as a Path; InputError when it is a URL (the text is kept whole in the sentence)."""
    text = os.fspath(path)
    if URL.match(text):
        raise InputError(f"The {role} {text} is a URL, which is not supported: download the {_noun(role)} "
                         f"and give its file.")
    return pathlib.Path(text)


@contextlib.contextmanager
def _opened(path: pathlib.Path, max_megapixels: float, config=None, role: str = "input") -> Iterator[tuple]:
    """The first image of ``path`` opened with the libraries' own messages captured: yields
    (ImageInput, its ImageSpec checked against ``max_megapixels``, the captured messages) and closes it.

    A missing, empty, unreadable or too large file raises InputError naming it as ``role`` ('input', 'mask').
    """
    check_input_path(path, role)
    oiio.geterror()  # drop any stale global error
    with quiet.captured() as printed:
        inp = oiio.ImageInput.open(str(path), config) if config is not None else oiio.ImageInput.open(str(path))
        if inp is None:
            why = reason(oiio_error() or printed.text, "not an image file OpenImageIO can read", path)
            raise InputError(f"Cannot read the {_noun(role)} {path}: {why}.")
        try:
            spec = inp.spec()
            _check_spec(path, spec, max_megapixels, role)
            yield inp, spec, printed
        finally:
            inp.close()


def _read_pixels(path: PathLike, max_megapixels: float, role: str = "input") -> Tuple[np.ndarray, bool, bool]:
    """Read the picture of any file OpenImageIO reads: subimage 0, or the Combined pass of a Blender multilayer
    EXR, at mip level 0.

    Returns ``(data, has_alpha, linear)``: ``data`` float32 (H, W, C) with
    C = channels of the file (integer data divided by its type's maximum,
    float data as stored); alpha, if any, is the last channel of the first
    two (gray + alpha) or four (RGBA) and the colour is straight (not
    premultiplied). ``linear`` says the colour values are scene-linear.
    Sentences call the file by ``role`` ('input', 'mask').
    """
    path = local_path(path, role)
    config = oiio.ImageSpec()
    config.attribute("oiio:UnassociatedAlpha", 1)
    with _opened(path, max_megapixels, config, role) as (inp, spec, _):
        subimage, spec, channels = _picture(path, inp, spec, max_megapixels, role)
        data = _read_subimage(path, inp, spec, subimage, role)
        if channels is not None:
            data = np.ascontiguousarray(data[:, :, channels])
        data = upright(data, spec.get_int_attribute("Orientation", 1))
        linear = _is_linear(path, inp.format_name(), spec)
        associated = spec.get_int_attribute("oiio:UnassociatedAlpha", 0) == 0
    if not np.all(np.isfinite(data)):
        raise InputError(f"The {_noun(role)} {path} holds NaN or infinite values.")
    data, has_alpha = _select_channels(data)
    if has_alpha and associated:
        data = _unpremultiply(data)
    return data, has_alpha, linear


COMBINED = ("Combined", "RGBA")
"""The pass of a Blender multilayer EXR that holds the rendered picture, and its channels."""


def _picture(path: pathlib.Path, inp, spec, max_megapixels: float,
             role: str) -> Tuple[int, oiio.ImageSpec, Optional[List[int]]]:
    """Where the picture of the open file ``inp`` is: (subimage, its ImageSpec, channel indices or None for all).

    A Blender multilayer EXR's picture is its first Combined pass (R, G, B, A),
    found by name in any part; any other file's is subimage 0 (``spec``).
    The Combined part's header is checked like subimage 0's.
    """
    found = _find_pass(inp, *COMBINED)
    if found is None:
        return 0, spec, None
    _check_spec(path, found[1], max_megapixels, role)
    return found


def pass_channels(names: Sequence[str], pass_name: str, letters: str) -> Optional[List[int]]:
    """Indices into ``names`` of the channels ``<layer>.<pass_name>.<letter>`` (or ``<pass_name>.<letter>``) for
    each of ``letters`` in order, for the first layer (in channel order) that has them all; None when none has.

    Blender names a multilayer EXR's channels ``ViewLayer.Vector.X``.
    """
    index = {name: i for i, name in enumerate(names)}
    heads = dict.fromkeys(name.rpartition(".")[0] for name in names)
    for head in heads:
        if head == pass_name or head.endswith("." + pass_name):
            wanted = [f"{head}.{letter}" for letter in letters]
            if all(name in index for name in wanted):
                return [index[name] for name in wanted]
    return None


def _find_pass(inp, pass_name: str, letters: str) -> Optional[Tuple[int, oiio.ImageSpec, List[int]]]:
    """(subimage, ImageSpec, channel indices) of the first part of the open EXR ``inp`` holding Blender's pass
    ``pass_name`` with channels ``letters`` (``pass_channels``); None when no part holds it or the file is not
    an EXR. Reads headers only; leaves ``inp`` at any of its subimages."""
    if inp.format_name() != "openexr":
        return None
    for subimage, spec in _parts(inp):
        channels = pass_channels(spec.channelnames, pass_name, letters)
        if channels is not None:
            return subimage, spec, channels
    return None


def _parts(inp) -> Iterator[tuple]:
    """(subimage, ImageSpec) of each image of the open file ``inp``, first to last, at most MAX_COUNTED."""
    subimage = 0
    while subimage < MAX_COUNTED and inp.seek_subimage(subimage, 0):
        yield subimage, inp.spec()
        subimage += 1
    inp.geterror()  # the failed seek past the last image leaves an error message


def upright(data: np.ndarray, orientation: int) -> np.ndarray:
    """(H, W, C) pixels as stored -> as meant to be seen, by the EXIF/TIFF ``Orientation`` tag (1-8).

    1 is upright; 2 mirrored left-right; 3 turned 180 degrees; 4 mirrored
    top-bottom; 5 transposed; 6 shown turned 90 degrees clockwise; 7
    transverse; 8 shown turned 90 degrees counter-clockwise. Other values
    are taken as 1. Cameras store sideways photographs with 6 or 8.
    """
    ops = {
        2: lambda a: a[:, ::-1],
        3: lambda a: a[::-1, ::-1],
        4: lambda a: a[::-1, :],
        5: lambda a: a.transpose(1, 0, 2),
        6: lambda a: np.rot90(a, -1),
        7: lambda a: a[::-1, ::-1].transpose(1, 0, 2),
        8: lambda a: np.rot90(a, 1),
    }
    if orientation not in ops:
        return data
    return np.ascontiguousarray(ops[orientation](data))


def _check_spec(path: pathlib.Path, spec, max_megapixels: float, role: str = "input") -> None:
    """Refuse empty images and images above the pixel limit, before reading any pixel."""
    if spec.width <= 0 or spec.height <= 0 or spec.nchannels <= 0:
        raise InputError(f"The {_noun(role)} {path} is empty ({spec.width} x {spec.height} pixels).")
    megapixels = spec.width * spec.height / 1e6
    if megapixels > max_megapixels:
        raise InputError(
            f"The {_noun(role)} {path} has {megapixels:g} megapixels ({spec.width} x {spec.height}), "
            f"more than the limit of {max_megapixels:g} megapixels.")


def _read_subimage(path: pathlib.Path, inp, spec, subimage: int = 0, role: str = "input") -> np.ndarray:
    """Pixels of ``subimage`` (whose ImageSpec is ``spec``), mip 0, as float32 (H, W, C); integer data divided
    by its type's maximum. InputError when reading fails or is partial."""
    native = {"uint8": np.uint8, "uint16": np.uint16}.get(str(spec.format))
    fmt = str(spec.format) if native is not None else "float"
    pixels = inp.read_image(subimage, 0, 0, spec.nchannels, fmt)
    error = inp.geterror() if inp.has_error else ""
    if pixels is None or error:
        why = reason(error or oiio.geterror(), "the pixel data could not be read", path)
        raise InputError(f"Cannot read the {_noun(role)} {path}: {why}.")
    pixels = np.asarray(pixels)
    if pixels.ndim == 2 and spec.nchannels == 1:
        pixels = pixels[:, :, None]
    if pixels.shape != (spec.height, spec.width, spec.nchannels):
        raise InputError(f"Cannot read the {_noun(role)} {path}: the pixel data has the wrong size {pixels.shape}.")
    if native is not None:
        return np.divide(pixels, np.float32(np.iinfo(native).max), dtype=np.float32)
    return pixels.astype(np.float32, copy=False)


def _select_channels(data: np.ndarray) -> Tuple[np.ndarray, bool]:
    """(H, W, C) -> (H, W, 1|2|3|4) and whether the last channel is alpha: 1 gray, 2 gray+alpha, 3 RGB, >=4 RGBA."""
    n = data.shape[2]
    if n >= 4:
        return data[:, :, :4], True
    return data, n in (2, 4)


def _unpremultiply(data: np.ndarray) -> np.ndarray:
    """Straight colour from premultiplied (H, W, C) data whose last channel is alpha; alpha 0 gives colour 0."""
    alpha = data[:, :, -1:]
    safe = np.where(alpha > 0, alpha, np.float32(1))
    colour = np.where(alpha > 0, data[:, :, :-1] / safe, np.float32(0))
    return np.concatenate([colour, alpha], axis=2).astype(np.float32)


def _to_srgb(colour: np.ndarray, linear: bool) -> np.ndarray:
    """Colour values -> sRGB-encoded [0, 1]: linear data goes through the sRGB curve, other data is clipped
    (float32 ``colour``, which the caller owns, in place)."""
    if linear:
        return linear_to_srgb(colour)
    if colour.dtype != np.float32:
        return np.clip(colour, 0.0, 1.0).astype(np.float32)
    return np.clip(colour, 0.0, 1.0, out=colour)


def probe(path: PathLike, max_megapixels: float = float("inf"), role: str = "input") -> Tuple[int, int, int]:
    """(width, height, channels) of the picture in ``path`` (as ``read_image`` chooses it: subimage 0, or a
    Blender multilayer EXR's Combined pass), from its headers alone (no pixel is decoded).

    Same InputError rules as ``read_image`` for missing, empty, unreadable
    and too large files; sentences call the file by ``role`` ('input', 'mask').
    """
    path = local_path(path, role)
    with _opened(path, max_megapixels, role=role) as (inp, spec, _):
        _, spec, channels = _picture(path, inp, spec, max_megapixels, role)
        return int(spec.width), int(spec.height), int(spec.nchannels if channels is None else len(channels))


def image_count(path: PathLike) -> int:
    """How many images ``path`` holds, from its headers: the pages of a TIFF, the parts of an EXR, the frames of
    a GIF or of an animated PNG; 1 for a plain picture. The painter paints the first of them (subimage 0).

    The parts of a Blender multilayer EXR are the passes of its pictures:
    its images are its parts holding a Combined pass (one per view layer),
    and the painter paints the first of those. Counting stops at
    MAX_COUNTED. Same InputError rules as ``probe``.
    """
    path = local_path(path)
    frames = _apng_frames(path)
    with _opened(path, float("inf")) as (inp, spec, _):
        count = spec.get_int_attribute("oiio:subimages", 0)
        if count <= 0:
            count = sum(1 for _ in _parts(inp))
        if inp.format_name() == "openexr":
            pictures = sum(1 for _, part in _parts(inp) if pass_channels(part.channelnames, *COMBINED) is not None)
            count = pictures or count
    return max(count, frames)


MAX_COUNTED = 10_000
"""``image_count`` counts at most this many images."""

_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _apng_frames(path: pathlib.Path) -> int:
    """The images of an animated PNG (OpenImageIO reads only its default image): the frame count of its acTL
    chunk, plus the default image when that is not a frame (no fcTL before the first IDAT); 0 for other files."""
    frames, framed = 0, False
    try:
        with open(path, "rb") as f:
            if f.read(8) != _PNG_SIGNATURE:
                return 0
            while True:
                head = f.read(8)
                if len(head) < 8:
                    return 0
                length, kind = struct.unpack(">I4s", head)
                if kind == b"IDAT":
                    return frames + (0 if framed else 1) if frames else 0
                if kind == b"acTL":
                    frames = struct.unpack(">I", f.read(4))[0]
                    length -= 4
                framed = framed or kind == b"fcTL"
                f.seek(length + 4, os.SEEK_CUR)  # the chunk's data and its CRC
    except (OSError, struct.error):
        return 0


def read_image(path: PathLike, max_megapixels: float = 50.0,
               canvas_colour: Sequence[float] = CANVAS_COLOUR) -> np.ndarray:
    """Read a picture as float32 (H, W, 3) sRGB-encoded values in [0, 1].

    Any format OpenImageIO reads (PNG, JPEG, TIFF, EXR, ...; uint8, uint16,
    half, float); only the first subimage and its full-resolution level.
    Integer data is divided by its type's maximum (255, 65535). Scene-linear
    files (EXR, HDR, or a linear ``oiio:ColorSpace`` such as lin_rec709) are
    converted with the sRGB curve and clipped to [0, 1]; other float data is
    clipped. One channel is gray (copied to R, G, B); two are gray + alpha;
    three RGB; four or more: the first four are RGBA.

    Alpha is composited over ``canvas_colour`` (sRGB, three values in [0, 1])
    in sRGB space: ``rgb * a + canvas * (1 - a)``, with straight (not
    premultiplied) ``rgb``, so a transparent pixel shows the bare canvas.

    Raises InputError (one sentence naming the file) when the file is
    missing, a folder, not a readable image, truncated, empty, above
    ``max_megapixels`` (checked from the header before any pixel is read),
    or holds NaN or infinite values.
    """
    data, has_alpha, linear = _read_pixels(path, max_megapixels)
    colour_channels = data.shape[2] - (1 if has_alpha else 0)
    colour = data[:, :, :colour_channels]
    if colour_channels == 1:
        colour = np.repeat(colour, 3, axis=2)
    rgb = _to_srgb(colour, linear)
    if has_alpha:
        alpha = np.clip(data[:, :, -1:], 0.0, 1.0)
        canvas = np.asarray(canvas_colour, dtype=np.float32).reshape(1, 1, 3)
        rgb = rgb * alpha + canvas * (np.float32(1) - alpha)
    return np.ascontiguousarray(rgb, dtype=np.float32)


def read_gray(path: PathLike, max_megapixels: float = 50.0, role: str = "input") -> np.ndarray:
    """Read a mask or brush map as float32 (H, W) values in [0, 1].

    Gray files give their value; colour files the Rec.709 luminance of their
    sRGB-encoded values. Values are converted exactly as in ``read_image``
    (integer data / maximum; scene-linear files such as EXR go through the
    sRGB curve, including one-channel ones). Alpha, if present, multiplies
    the value, so transparent pixels read as 0. Same InputError rules as
    ``read_image``; sentences call the file by ``role`` ('mask', 'brush map').
    """
    data, has_alpha, linear = _read_pixels(path, max_megapixels, role)
    colour_channels = data.shape[2] - (1 if has_alpha else 0)
    values = _to_srgb(data[:, :, :colour_channels], linear)
    gray = values[:, :, 0] if colour_channels == 1 else luminance(values)
    if has_alpha:
        gray = gray * np.clip(data[:, :, -1], 0.0, 1.0)
    return np.ascontiguousarray(np.clip(gray, 0.0, 1.0), dtype=np.float32)


def read_exr(path: PathLike) -> Tuple[np.ndarray, List[str], Dict[str, object]]:
    """Read an EXR (or any float image) as stored, without colour conversion.

    Returns ``(data, channels, attributes)``: ``data`` float32 (H, W, C),
    always three-dimensional; ``channels`` the C channel names in the order
    ``write_exr`` was given them (OpenEXR itself stores them sorted by name);
    ``attributes`` every header attribute as name -> Python value (str, int,
    float or tuple). Raises InputError when the file is missing, a folder,
    unreadable, truncated, empty, or holds NaN or infinite values.
    """
    path = pathlib.Path(path)
    with _opened(path, float("inf")) as (inp, spec, printed):
        pixels = inp.read_image(0, 0, 0, spec.nchannels, "float")
        error = inp.geterror() if inp.has_error else ""
        names = list(spec.channelnames)
        attributes = {a.name: a.value for a in spec.extra_attribs}
    if pixels is None or error:
        why = reason(error or oiio.geterror() or printed.text, "the pixel data could not be read", path)
        raise InputError(f"Cannot read the image {path}: {why}.")
    data = np.asarray(pixels, dtype=np.float32).reshape(spec.height, spec.width, spec.nchannels)
    if not np.all(np.isfinite(data)):
        raise InputError(f"The image {path} holds NaN or infinite values.")
    data, names = _restore_channel_order(data, names, attributes.get(CHANNEL_ORDER_ATTR))
    return data, names, attributes


def read_pass(path: PathLike, pass_name: str, letters: str, role: str = "input") -> Optional[np.ndarray]:
    """The channels ``letters`` of Blender's pass ``pass_name`` in a multilayer EXR, as stored (no conversion).

    E.g. ``read_pass(path, "Vector", "XYZW")``: float32 (H, W, len(letters)),
    channel k is ``<ViewLayer>.<pass_name>.<letters[k]>`` of the first part
    holding them all, found by name (``pass_channels``); rows top first, as
    OpenImageIO reads them. None when the file holds no such pass (or is
    not an EXR). InputError as ``read_exr``; sentences call the file by
    ``role`` ('input', 'frame').
    """
    path = local_path(path, role)
    with _opened(path, float("inf"), role=role) as (inp, _, _printed):
        found = _find_pass(inp, pass_name, letters)
        if found is None:
            return None
        subimage, spec, channels = found
        _check_spec(path, spec, float("inf"), role)
        data = np.ascontiguousarray(_read_subimage(path, inp, spec, subimage, role)[:, :, channels])
    if not np.all(np.isfinite(data)):
        raise InputError(f"The {_noun(role)} {path} holds NaN or infinite values in its {pass_name} pass.")
    return data


def holds_pass(path: PathLike, pass_name: str, letters: str, role: str = "input") -> bool:
    """Whether ``path`` holds Blender's pass ``pass_name`` with channels ``letters`` (``read_pass``), from its
    headers alone; InputError as ``read_exr``."""
    path = local_path(path, role)
    with _opened(path, float("inf"), role=role) as (inp, _, _printed):
        return _find_pass(inp, pass_name, letters) is not None


def read_attributes(path: PathLike) -> Dict[str, object]:
    """The header attributes of an image (name -> Python value), without reading its pixels; InputError as read_exr."""
    with _opened(pathlib.Path(path), float("inf")) as (_, spec, _printed):
        return {a.name: a.value for a in spec.extra_attribs}


def _restore_channel_order(data: np.ndarray, names: List[str], order) -> Tuple[np.ndarray, List[str]]:
    """Reorder (H, W, C) ``data`` and ``names`` to the comma-separated ``order`` when it names the same channels."""
    if not isinstance(order, str):
        return data, names
    wanted = order.split(",")
    if sorted(wanted) != sorted(names) or len(set(wanted)) != len(wanted):
        return data, names
    index = [names.index(n) for n in wanted]
    return np.ascontiguousarray(data[:, :, index]), wanted
