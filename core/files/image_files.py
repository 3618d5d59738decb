"""What reading (``reading``) and writing (``writing``) image files share.

The path type both take, the EXR header attribute that keeps the channel
order ``write_exr`` was given, and OpenImageIO's error text cut down to the
one reason their sentences give.
"""

from __future__ import annotations

import os
import re
from typing import Union

import OpenImageIO as oiio

PathLike = Union[str, os.PathLike]

CHANNEL_ORDER_ATTR = "paint_relief:channel_order"
"""Header attribute holding the channel order given to write_exr (OpenEXR stores channels sorted by name)."""


def reason(text: str, fallback: str, *paths) -> str:
    """The first sentence of a library's error text, without the file names ``paths`` and a trailing full stop.

    OpenImageIO and its libraries name the file in their messages ('... ("/a/b.jpg")', 'image file "/a/.b.tmp.exr".
    File output failed.'); our sentence names it already, so the names are dropped and only the first of their
    sentences is kept.
    """
    for line in (text or "").splitlines():
        for path in sorted({os.fspath(p) for p in paths}, key=len, reverse=True):
            for form in (f' ("{path}")', f' "{path}"', f'"{path}"', f" ({path})", f" {path}", path):
                line = line.replace(form, "")
        line = re.split(r"(?<=[a-z0-9)])\.\s", line.strip())[0]
        line = " ".join(line.split()).rstrip(":.").strip()
        if line:
            return line
    return fallback


def oiio_error(obj=None) -> str:
    """Pending OpenImageIO error text from ``obj`` (or the global one); clears it."""
    text = ""
    if obj is not None:
        text = obj.geterror()
    return text or oiio.geterror()
