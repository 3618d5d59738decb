"""The paper's comparisons as one rerunnable command.

Each image is painted by the paper's method, by Hertzmann 1998
(Impressionist) and by the two ablations of the paper's Fig. 8; the figures
go into table.md / table.csv and the pictures into one contact sheet per image.
"""

from __future__ import annotations

import csv
import io
import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, List, Optional, Sequence

import numpy as np

from ..errors import ParameterError
from ..figures.sheet import contact_sheet
from ..figures.visualize import partition_overlay
from ..files import reading, writing
from ..lighting import bump_lighting, paper_lighting
from ..measures.metrics import edge_fidelity, psnr, ssim
from ..methods.registry import paint
from ..params import Params
from ..progress import CancelFn, ProgressFn, Stage
from ..results import Painting

METHODS = {
    "ours": ("Huang et al. 2011", {}),
    "hertzmann98": ("Hertzmann 1998 (Impressionist)", {"method": "hertzmann98", "style": "impressionist"}),
    "layout_ablation": ("Ablation: Hertzmann layout", {"layout": "hertzmann98"}),
    "lines_ablation": ("Ablation: solid lines", {"renderer": "lines"}),
}
BUMP_LIGHT = (math.radians(225.0), math.radians(35.0))
"""Azimuth and elevation (radians) of the bump-lighting panel: light from the upper left."""


@dataclass
class Row:
    """Figures of one method on one image."""

    image: str
    width: int
    height: int
    method: str
    strokes: int
    seconds: float
    psnr_db: float
    ssim: float
    edge_fidelity: float


def measure(name: str, key: str, image: np.ndarray, painting: Painting, seconds: float) -> Row:
    """The figures of one painting of ``image``."""
    h, w = image.shape[:2]
    return Row(name, w, h, key, len(painting.strokes), seconds, psnr(painting.colour, image),
               ssim(painting.colour, image), edge_fidelity(painting.colour, image))


def run_image(path: Path, params: Params, stage: Stage) -> tuple:
    """Paint one image with every method; returns (rows, contact sheet)."""
    image = reading.read_image(path, params.max_megapixels, params.canvas_colour)
    rows: List[Row] = []
    paintings: Dict[str, Painting] = {}
    for i, (key, (_, changes)) in enumerate(METHODS.items()):
        stage.report(i / len(METHODS), f"{path.name}: {METHODS[key][0]}")
        t0 = time.perf_counter()
        paintings[key] = paint(image, params.replace(**changes))
        rows.append(measure(path.name, key, image, paintings[key], time.perf_counter() - t0))
    ours = paintings["ours"]
    analysis = ours.analysis
    panels = [("Input", image),
              ("Importance and partition",
               partition_overlay(np.repeat(analysis.importance[..., None], 3, axis=2), analysis.grids,
                                 analysis.grid_sizes, analysis.sizes))]
    panels += [(f"{label}: {len(paintings[key].strokes)} strokes", paintings[key].colour)
               for key, (label, _) in METHODS.items()]
    panels += [("Paper lighting (Eq. 6-7)", paper_lighting(ours.colour, ours.height, ours.orientation)),
               ("Bump lighting (Blinn-Phong)", bump_lighting(ours.colour, ours.height, *BUMP_LIGHT))]
    return rows, contact_sheet(panels, panel_height=min(320, image.shape[0]), columns=4)


def tables(rows: Sequence[Row]) -> tuple:
    """(markdown, csv) text: one line per image with every method's figures and the stroke ratio."""
    by_image: Dict[str, Dict[str, Row]] = {}
    for row in rows:
        by_image.setdefault(row.image, {})[row.method] = row
    header = ["image", "size"]
    for key in METHODS:
        header += [f"{key}_strokes", f"{key}_seconds", f"{key}_psnr_db", f"{key}_ssim", f"{key}_edge_fidelity"]
    header.append("stroke_ratio_ours_over_hertzmann98")
    lines = []
    for name, methods in by_image.items():
        first = next(iter(methods.values()))
        line = [name, f"{first.width}x{first.height}"]
        for key in METHODS:
            r = methods[key]
            line += [r.strokes, round(r.seconds, 2), round(r.psnr_db, 2), round(r.ssim, 3), round(r.edge_fidelity, 3)]
        line.append(round(methods["ours"].strokes / max(1, methods["hertzmann98"].strokes), 3))
        lines.append(line)
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(header)
    writer.writerows(lines)
    return markdown_table(by_image), out.getvalue()


def markdown_table(by_image: Dict[str, Dict[str, Row]]) -> str:
    """A readable table: per image and method, strokes, seconds, PSNR, SSIM, edge fidelity."""
    text = ["| image | size | method | strokes | seconds | PSNR dB | SSIM | edge fidelity |",
            "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: |"]
    for name, methods in by_image.items():
        for key, (label, _) in METHODS.items():
            r = methods[key]
            text.append(f"| {name} | {r.width}×{r.height} | {label} | {r.strokes} | {r.seconds:.1f} | "
                        f"{r.psnr_db:.2f} | {r.ssim:.3f} | {r.edge_fidelity:.3f} |")
    text.append("")
    text.append("| image | strokes ours / Hertzmann 1998 | PSNR ours − Hertzmann 1998 (dB) |")
    text.append("| --- | ---: | ---: |")
    for name, methods in by_image.items():
        ours, base = methods["ours"], methods["hertzmann98"]
        text.append(f"| {name} | {ours.strokes / max(1, base.strokes):.2f} | {ours.psnr_db - base.psnr_db:+.2f} |")
    return "\n".join(text) + "\n"


def check_names(paths: Sequence[Path]) -> None:
    """ParameterError when two images would share a table row name or a contact sheet file.

    Rows are named by the file name and sheets by the stem, so ``a/x.png``
    and ``b/x.png`` (or ``x.png`` and ``x.jpg``) cannot be told apart.
    """
    seen: Dict[str, Path] = {}
    for path in map(Path, paths):
        for key in {path.name.lower(), path.stem.lower()}:
            if key in seen and seen[key] != path:
                raise ParameterError(f"The images {seen[key]} and {path} have the same name {key!r}, so their "
                                     f"rows and contact sheets would clash; rename or copy one of them.")
            seen[key] = path


def run_experiments(paths: Sequence[Path], out_dir: Path, params: Params, progress: ProgressFn = None,
                    cancel: CancelFn = None, max_memory: Optional[int] = None) -> List[Row]:
    """Paint every image with every method; write table.md, table.csv and <image>_sheet.png into ``out_dir``.

    Every image is checked (names, headers, memory; see ``api.check_input``)
    before any work and before ``out_dir`` is created.
    """
    from ..api import check_input
    from ..files.staging import output_folder

    params.validate()
    paths = [Path(p) for p in paths]
    check_names(paths)
    for path in paths:
        check_input(path, params, max_memory=max_memory)
    with output_folder(out_dir) as folder:
        stage = Stage(progress, cancel)
        rows: List[Row] = []
        sheets = {}
        for i, path in enumerate(paths):
            image_rows, sheet = run_image(path, params, stage.sub(i / len(paths), (i + 1) / len(paths)))
            rows += image_rows
            sheets[path.stem] = sheet
        markdown, csv_text = tables(rows)
        with folder.staged() as staging:
            for stem, sheet in sheets.items():
                writing.write_png(staging / f"{stem}_sheet.png", sheet)
            writing.write_text(staging / "table.md", markdown)
            writing.write_text(staging / "table.csv", csv_text)
    stage.report(1.0, f"Compared {len(paths)} image(s)")
    return rows
