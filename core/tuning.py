"""How the painter cuts its work: every constant that bounds memory or decides when work is spread over threads.

None of these changes a painted byte. Each only decides where work is cut
into pieces, and the pieces' results are joined back in order (the tests
paint with small values of each and compare the bytes), so they can be
tuned to a machine's memory and cores. The method's own constants (brush
contact levels, thresholds, the paper's parameters) are in ``params.py``
and beside the rule they belong to, not here. Modules read these as
``tuning.NAME`` when they run, so a test can set one for a case.
"""

# Threads -----------------------------------------------------------------------------------------------------------

MAX_WORKERS = 4
"""Worker threads at most (``core.workers``): memory bandwidth, not cores, bounds the painter's work beyond a few."""

WRITERS = 2
"""Output files encoded and written at once (``files.export``): the EXR and PNG encoders run side by side."""

# Images, a block of rows at a time ---------------------------------------------------------------------------------

BLOCK_PIXELS = 1 << 20
"""Pixels (rows times width) in one block of rows: of per-pixel work on the worker threads (``workers.in_row_blocks``)
and of an image made and written at a time (``files.writing.RowBlocks``, in whole multiples of 16 rows). Bounds each
block's temporaries to a few MiB."""

BILATERAL_SPLAT_PIXELS = 1 << 20
"""Pixels of one channel splatted into the bilateral grid at a time (``analysis.importance``)."""

RBF_SOLVE_VALUES = 1 << 20
"""Matrix entries of the orientation field's local RBF systems solved at once (float64: 8 MiB)."""

RBF_EVAL_VALUES = 1 << 18
"""(query point, neighbour) distances of the local RBF interpolants evaluated at once."""

# Strokes -----------------------------------------------------------------------------------------------------------

ANCHOR_CHUNK_PIXELS = 1 << 18
"""Grid pixels whose anchors are chosen at once, in all worker threads together (``strokes.layout``)."""

ANCHOR_LEAST_PIXELS = 1 << 16
"""Grid pixels below which choosing anchors is not split between worker threads."""

PLAN_CHUNK_SAMPLES = 1 << 23
"""Curve samples (times bristles and channels, roughly) of a round planned at once, in all worker threads
together: bounds the memory of planning (``strokes.rounds``)."""

WORKER_LEAST_STROKES = 64
"""Strokes below which a round's planning is not split between worker threads."""

LAY_CHUNK_SAMPLES = 1 << 20
"""Track samples (times brush columns) of a round made into footprints at once: bounds the memory of a round's
footprints (about 100 bytes each), whatever the brush size (``strokes.rounds``)."""

WORKER_LEAST_SAMPLES = 1 << 15
"""Track samples (times brush columns) below which making footprints is not split between worker threads."""

SPLAT_CHUNK_PIXELS = 1 << 18
"""Box pixels of strokes splatted at once (``strokes.compositing``): a chunk's sums (6 float32 values each,
6 MiB) stay in the processor's cache while the splat scatters into them, and bound the scratch memory."""

LAY_LEAST_ENTRIES = 1 << 16
"""Footprint entries below which a run of strokes is laid in one band rather than in bands of rows on the
worker threads (``strokes.canvas``)."""

RELAY_TILE = 32
"""px: the side of the square tiles in which a frame of a shot is laid again where its strokes changed
(``strokes.relay``): smaller tiles lay fewer pixels again, at more bookkeeping."""

RELAY_MOST_MARKED = 0.75
"""The share of a frame's tiles above which it is laid anew rather than again where its strokes changed
(``strokes.relay``): laying again on most of the canvas lays nearly every stroke, and picking the entries of the
marked pixels then costs more than it saves (at 1920x1080, 2.6 s anew against 2.8 s again at 0.87 of the tiles,
2.3 s again against 2.6 s anew at 0.65)."""

BAND_SAMPLE = 8
"""Bands of rows are balanced on the rows of every BAND_SAMPLE-th entry (``strokes.canvas.row_bands``)."""

RING_CHUNK_VALUES = 1 << 21
"""Ring pixels gathered at once by the detail pass (candidates times ring size): bounds the memory of the ring
test, whose ring grows with the square of the smallest brush (800 pixels at 16 MP) (``strokes.details``)."""
