"""The one function callers outside the painter use: paint a file into a folder."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

from . import io
from .params import Params
from .progress import CancelFn, ProgressFn
from .staging import staged_outputs


def paint_file(input_path, output_dir, params: Params, progress: ProgressFn = None, cancel: CancelFn = None,
               mask_path: Optional[str] = None) -> dict:
    """Read ``input_path``, paint it and write every output into ``output_dir``; return the report.

    Outputs appear only when all of them were written (see staging); a
    failure raises a PaintReliefError whose message is one sentence naming
    the file and the problem, and leaves ``output_dir`` as it was.
    """
    from .export import write_painting
    from .painting import paint

    params.validate()
    out = io.ensure_output_dir(output_dir)
    image = io.read_image(input_path, params.max_megapixels, params.canvas_colour)
    mask = io.read_gray(mask_path, params.max_megapixels) if mask_path else None
    painting = paint(image, params, progress=progress, cancel=cancel, mask=mask)
    with staged_outputs(out) as staging:
        report = write_painting(staging, painting, str(input_path))
    report["output_dir"] = str(Path(out).resolve())
    return report
