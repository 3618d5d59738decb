"""The one-stroke-at-a-time painter: the reference the engine's rounds are held to, byte for byte.

``paint_round`` here takes the engine's arguments and follows the same rule,
but plans each stroke of a round alone against the canvas as the round
began (``plan_round`` of one anchor), judges each alone on that canvas
(``improves``) and lays the kept ones one after another, each alone on the
whole box around its pixels (``lay_one``). ``paint`` is ``huang11.paint``
with every round painted so.

It is made of the engine's own pieces (planning, ``strokes_footprints``,
``improves``, Eq. 4's ``composite``), so agreeing with it proves that what
the engine adds, planning and judging a round's strokes together, cutting a
round into runs, chunks and bands, and laying it pass by pass, changes no
byte. It does not prove those pieces right: the stamp-by-stamp oracle
(``stamp_oracle``) and the by-hand tests do that.
"""

import numpy as np
import pytest

from core.methods import huang11
from core.strokes.canvas import Canvas, composite, inverse_full
from core.strokes.compositing import Footprints
from core.strokes.rounds import RoundPlan, improves, lay_round, plan_round, records, strokes_footprints


def paint(image: np.ndarray, params):
    """``huang11.paint(image, params)`` with every round painted by this module's ``paint_round``."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(huang11, "paint_round", paint_round)
        return huang11.paint(image, params)


def paint_round(canvas: Canvas, sources, orientation: np.ndarray, anchors: np.ndarray, size: int, layer: int, tip,
                draws: np.ndarray, params, ratios: np.ndarray = None, record=None) -> list:
    """``core.strokes.rounds.paint_round``, one stroke at a time: every stroke planned and judged alone on the
    canvas as the round found it, then the kept ones laid alone in order; returns their records (and hands
    ``record`` their plan, joined)."""
    anchors = np.asarray(anchors, np.int64).reshape(-1, 2)
    plans = [plan_round(canvas, sources, orientation, anchors[i:i + 1], size, tip, draws[i:i + 1], params)
             for i in range(len(anchors))]
    if ratios is not None and params.renderer != "lines":
        shape = canvas.height.shape
        plans = [plan for plan, ratio in zip(plans, np.asarray(ratios, np.float64).tolist(), strict=True)
                 if not ratio or improves(canvas.colour, strokes_footprints(plan, size, tip, params, shape),
                                          sources.reference, ratio)[0]]
    for plan in plans:
        if params.renderer == "lines":
            lay_round(canvas, plan, size, tip, params)        # a solid line is laid whole, one stroke at a time
        else:
            lay_one(canvas, strokes_footprints(plan, size, tip, params, canvas.height.shape), 0,
                    params.height_mode, params.height_build)
    if record is not None and plans:
        record(RoundPlan.joined(plans))
    return [stroke for plan in plans for stroke in records(plan, size, layer)]


def lay_one(canvas: Canvas, footprints: Footprints, stroke: int, height_mode: str, build: float) -> None:
    """Lay stroke ``stroke`` of ``footprints`` alone on ``canvas``, on the whole box around the pixels it touches.

    ``composite`` over the box, where the pixels the stroke does not touch take
    transmittance 1 and no paint, deposit or height (which leaves them as they
    are).
    """
    entries = slice(int(footprints.starts[stroke]), int(footprints.starts[stroke + 1]))
    pixel = footprints.pixel[entries]
    if pixel.size == 0:
        return
    rows, columns = np.divmod(pixel, canvas.height.shape[1])
    top, left = int(rows.min()), int(columns.min())
    shape = (int(rows.max()) - top + 1, int(columns.max()) - left + 1)
    local = (rows - top, columns - left)
    transmittance, paint = np.ones(shape, np.float32), np.zeros(shape + (3,), np.float32)
    deposit, height = np.zeros(shape, np.float32), np.zeros(shape, np.float32)
    transmittance[local] = footprints.transmittance[entries]
    paint[local] = footprints.paint[entries]
    deposit[local] = footprints.deposit[entries]
    height[local] = footprints.height[entries]
    box = (slice(top, top + shape[0]), slice(left, left + shape[1]))
    inverse = np.full(shape, inverse_full(footprints.full[stroke:stroke + 1])[0], np.float32)
    (canvas.colour[box], canvas.coverage[box], canvas.height[box], canvas.opacity[box]) = composite(
        canvas.colour[box], canvas.coverage[box], canvas.height[box], canvas.opacity[box], transmittance, paint,
        deposit, height, inverse, height_mode, build)
