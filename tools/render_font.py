# SPDX-License-Identifier: GPL-3.0-or-later
"""Render the bitmap font core/figures/text.py draws with: printable ASCII of Droid Sans at 32 px, as coverage.

Needs OpenImageIO built with FreeType (the PyPI package is; Blender's bundled
module is not, which is why the painter ships this bitmap instead of
rendering text at run time)::

    .venv/bin/python tools/render_font.py            # writes core/figures/font.npz

Droid Sans (Apache License 2.0) is the font OpenImageIO's PyPI package ships.
Each glyph is rendered on its own, anti-aliased, into a cell as wide as its
advance (measured between two capital I's, so spacing is the font's) and as
tall as the tallest ascent plus the deepest descent; the cells sit side by
side in one uint8 coverage atlas. The output is the same bytes on every run.
"""

import io
import sys
from pathlib import Path

import numpy as np
import OpenImageIO as oiio

FONT = "DroidSans"
EM_PX = 32
FIRST, LAST = 32, 126
OUT = Path(__file__).resolve().parent.parent / "core" / "figures" / "font.npz"


def advance(char):
    """Pen advance of ``char`` in pixels at EM_PX."""
    with_char = oiio.ImageBufAlgo.text_size("I" + char + "I", EM_PX, FONT)
    without = oiio.ImageBufAlgo.text_size("II", EM_PX, FONT)
    return with_char.xend - without.xend


def main():
    chars = [chr(code) for code in range(FIRST, LAST + 1)]
    boxes = [oiio.ImageBufAlgo.text_size(c, EM_PX, FONT) for c in chars]
    if not all(box.defined for box in boxes[1:]):
        sys.exit("OpenImageIO cannot render text here (no FreeType or no {} font).".format(FONT))
    ascent = max(-box.ybegin for box in boxes if box.defined)
    descent = max(box.yend for box in boxes if box.defined)
    height = ascent + descent
    widths = [max(1, advance(c)) for c in chars]
    cells = []
    for char, width in zip(chars, widths, strict=True):
        buf = oiio.ImageBuf(oiio.ImageSpec(width, height, 1, oiio.FLOAT))
        if char != " " and not oiio.ImageBufAlgo.render_text(buf, 0, ascent, char, EM_PX, FONT, (1.0,)):
            sys.exit("OpenImageIO could not render {!r}: {}".format(char, buf.geterror()))
        cells.append(np.asarray(buf.get_pixels(oiio.FLOAT)).reshape(height, width))
    atlas = np.concatenate(cells, axis=1)
    coverage = np.round(np.clip(atlas, 0.0, 1.0) * 255.0).astype(np.uint8)
    offsets = np.concatenate([[0], np.cumsum(widths)[:-1]]).astype(np.int32)
    buffer = io.BytesIO()
    # np.savez writes zip entries with a fixed date, so the same arrays give the same bytes.
    np.savez_compressed(buffer, coverage=coverage, offsets=offsets, widths=np.asarray(widths, np.int32),
                        first=np.int32(FIRST), ascent=np.int32(ascent), em=np.int32(EM_PX))
    OUT.write_bytes(buffer.getvalue())
    print("{}: {} glyphs, {} x {} px atlas, {} bytes".format(OUT, len(chars), *coverage.shape, OUT.stat().st_size))


if __name__ == "__main__":
    main()
