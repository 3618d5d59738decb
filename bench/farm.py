"""Benchmark of painting a sequence on a Dask cluster (``core.farm``): the pieces' times, their sequential share,
a projection to many machines, and the measured speed-up of `core sequence --workers 2` over `--workers 1`.

1. The pieces (``core.sequence.pieces``) of every frame of ``--clip`` (default
   /work/footage/bbb1080, ``--frames`` 1-5), made one after another in this
   process with the arguments the cluster driver (``core.farm.sequence``)
   gives them (``core.farm.frame_file.cluster_arguments``): "prepare"
   (reading, analysis), "motion", the strokes' life in its three steps
   ("carry"; "judge", the judging canvas laid in bands of rows, as the driver
   cuts it for 1, 2 and 8 worker threads, each band timed; "birth"), "shown"
   (laying the frame shown), "write" (the maps into a staging folder, with
   the measures), then ``shot.Run.commit`` itself (the lives appended, the
   state, report.json and the staging folder committed), which the driver
   runs on the client. The painter runs on one
   thread, as on a Dask worker (``core.farm.plugin.PainterWorker``:
   ``tuning.MAX_WORKERS`` and ``tuning.WRITERS`` 1, the C heap reused). The
   table gives each piece's median seconds over the frames after the first,
   the first frame's pieces apart (its life, in "carry", is the still), and each
   result's size pickled (``pickle`` protocol 5: what travels between
   workers). Peak memory is this process's ru_maxrss (the pieces of two
   frames alive, as the driver keeps them, and their pickles).
2. The sequential share: (carry + birth + commit) over all the work of a
   frame after the first. Frame t's life needs frame t-1's, and the client
   commits frames one at a time, so these run in frame order whatever the
   cluster's size; the judging canvas's bands run side by side between them.
3. A projection of a 250-frame shot (``--projected-frames``) onto 1, 8 and 32
   machines of 2 single-threaded workers each (and of 1, 4 and 16 such shots
   painted at once by `core batch`), from the measured piece
   times: max(chain, commits, work / threads) + fill + drain, where chain =
   the first frame's life + 249 x (carry + judging + birth), the life chain,
   judging on T threads being the longest of the min(T, 8) bands the driver
   cuts (``core.farm.scheduling.MAX_BANDS``; min(T / S, 8) for S shots at
   once); commits = 250 x commit, which
   the client makes in frame order beside the life chain (it sends the next
   life's pieces out before each commit); work = every piece of every
   frame on the workers, fill = the first frame's reading (before the chain
   can start), drain = laying and writing the last frame. Then the same with
   every piece's inputs (and the strokes and the maps' report the client
   gathers) sent over a 1 GB/s network (``--network-gbps``) and no transfer overlapping work: an
   assumption, the worst case, since the driver places a piece on the worker
   holding most of its inputs.
4. `python -m core sequence CLIP -o DIR --seed 5 --workers N` for N = 1 and
   2 on ``--small-clip`` (default /work/footage/bbb01, 6 frames of 424x240),
   as a user runs it, and without --workers (one process, no Dask) beside
   them: the median wall time over ``--runs`` runs each (taken in turn), the
   ratio of --workers 2 to --workers 1, the peak resident memory of the
   largest process (the command or one of its workers: ru_maxrss from
   os.wait4), and whether every run wrote the same bytes (every .png, .exr
   and strokes.lives file). These commands run before the pieces are timed,
   since a child started by vfork counts this process's peak as its own.
5. Many shots at once: `python -m core batch SHOT SHOT ... -o ROOT --seed 5
   --workers N` for N = 1 and 2 on ``--shots`` (default --small-clip twice:
   two shots painted into ROOT/<name>_001 and _002), the median wall time
   over ``--runs`` runs each, the ratio of --workers 2 to --workers 1, and
   whether each shot's folder holds the bytes of `core sequence SHOT` in one
   process (part 4's run, or one run of its own for a shot not painted there).

Usage: python bench/farm.py [--clip DIR] [--frames A-B] [--small-clip DIR] [--shots DIR DIR ...] [--runs 3]
         [--seed 5] [--skip-pieces] [--skip-speedup] [--skip-shots]
"""

from __future__ import annotations

import argparse
import contextlib
import os
import pickle
import resource
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Dict, Mapping, Sequence

from common import file_digests, run_child
from core import tuning
from core.cli import build_parser, params_from_args
from core.farm.frame_file import READ, STROKES, cluster_arguments, input_source
from core.farm.scheduling import MAX_BANDS
from core.farm.sequence import lived_strokes
from core.files.frames import find_frames
from core.files.staging import output_folder
from core.heap import reused_heap
from core.params import SequenceSettings
from core.sequence.pieces import PieceKey, PieceKind, judging_bands, piece_needs
from core.sequence.shot import Run, shot_settings

FOOTAGE = Path("/work/footage")
CLIP = FOOTAGE / "bbb1080"
CLIP_FRAMES = "1-5"
SMALL_CLIP = FOOTAGE / "bbb01"
PIECES = tuple(kind.value for kind in PieceKind) + ("commit",)
WORKER_PIECES = PIECES[:-1]
CHAIN_PIECES = ("carry", "birth", "commit")     # in frame order; "judge" runs in bands side by side between them
LIFE_PIECES = ("carry", "birth")                # the life chain: a frame's carry needs the births of the one before
MACHINES = (1, 8, 32)
SHOTS = (1, 4, 16)
THREADS_PER_MACHINE = 2
PROJECTED_FRAMES = 250
COMPARED_SUFFIXES = (".png", ".exr", ".lives")
SPEEDUP_WORKERS = (1, 2, 0)     # --workers 1, --workers 2, and 0: no --workers (one process, no Dask)

CLIENT_RECEIVES = ("carry", "lived", "write")    # the driver cuts the bands, gathers the strokes, commits the maps
CHAIN_KINDS = (PieceKind.CARRY, PieceKind.JUDGE, PieceKind.BIRTH)


def piece_inputs(kinds=tuple(PieceKind)) -> tuple:
    """(piece, result it is sent) for each input of the pieces of ``kinds`` of a frame t > 0 with one judging band,
    the shot measured, from the pieces' declaration (``pieces.piece_needs``) and where the farm takes each input
    (``frame_file.input_source``): a frame read again is not sent; frame t-1's strokes ("lived": its BIRTH result
    without the canvas its births were laid on) come from the client."""
    pairs = []
    for kind in kinds:
        key = PieceKey(kind, 1)
        for need in piece_needs(key, 1, measures=True):
            source = input_source(key, need)
            if source != READ:
                pairs.append((kind.value, "lived" if source == STROKES else need.kind.value))
    return tuple(pairs)


# The inputs each piece of frame t > 0 is sent and the results sent to the client: the volume per frame when every
# one crosses the network; CHAIN_SENT, those of the life chain.
SENT = piece_inputs() + tuple(("client", result) for result in CLIENT_RECEIVES)
CHAIN_SENT = piece_inputs(CHAIN_KINDS) + (("client", "carry"), ("client", "lived"))


@contextlib.contextmanager
def worker_painter():
    """The painter set up as on a Dask worker (``core.farm.plugin.PainterWorker``) for the body, restored after."""
    saved = tuning.MAX_WORKERS, tuning.WRITERS
    tuning.MAX_WORKERS, tuning.WRITERS = 1, 1
    try:
        with reused_heap():
            yield
    finally:
        tuning.MAX_WORKERS, tuning.WRITERS = saved


def pickled(value) -> tuple:
    """(bytes of ``value`` pickled (protocol 5, the arrays' buffers in band), seconds to pickle and unpickle it)."""
    clock = time.perf_counter()
    data = pickle.dumps(value, protocol=5)
    pickle.loads(data)
    return len(data), time.perf_counter() - clock


def prepared_parts(made) -> Dict[str, int]:
    """Pickled bytes of a later frame's PREPARE result by part: the picture read, the analysis, the colour
    sources at every stroke width (``frame_step.FrameAnalysis``)."""
    return {"picture": pickled(made.frame.image)[0], "analysis": pickled(made.analysed.analysis)[0],
            "colour sources": pickled(made.analysed.sources)[0]}


def timed(fn, *args):
    """(fn(*args), wall seconds)."""
    clock = time.perf_counter()
    result = fn(*args)
    return result, time.perf_counter() - clock


def cli_params(clip: str, seed: int):
    """The Params and SequenceSettings `python -m core sequence CLIP -o OUT --seed SEED` paints with."""
    args = build_parser().parse_args(["sequence", clip, "-o", "unused", "--seed", str(seed)])
    return params_from_args(args), SequenceSettings(args.fade_frames, args.normal_map).validate()


BAND_COUNTS = (1, THREADS_PER_MACHINE, 4, MAX_BANDS)
"""The bands the judging canvas is cut into on one thread, one machine, a shot's share of 16 threads painting 4
shots, and eight threads or more."""


def measure_pieces(clip: str, frame_range: str, seed: int, work: Path) -> dict:
    """Every frame's pieces of ``clip`` (``core.sequence.pieces``) made in order with the arguments the cluster
    driver gives them (``core.farm.frame_file.cluster_arguments``), committed into ``work``.

    Returns {"frames": Frames, "seconds": [{piece: s} per frame], "bytes": [{piece: pickled bytes} per frame],
    "pickling": [{piece: s to pickle and unpickle its result} per frame], "life_stages": [{stage: s} per frame]
    (the life's own "seconds", its analysis left out), "strokes": [alive per frame], "prepared_parts": [{part:
    pickled bytes} per frame after the first], "bands": [{bands: (s of all, s of the longest)} per frame after
    the first, for each of BAND_COUNTS]}; the first frame has no "motion", and its "carry" is the still painted
    (no "judge"). "judge" is the seconds of the THREADS_PER_MACHINE bands together, the cut the driver makes on
    one machine like this one.
    """
    params, settings = cli_params(clip, seed)
    frames = find_frames([clip], frame_range, params.max_megapixels)
    run = Run(frames, shot_settings(frames, params, settings))
    seconds, sizes, pickling, stages, strokes, parts, banded = [], [], [], [], [], [], []
    with worker_painter(), output_folder(work) as folder:
        report = run.new_report()
        pieces = run.pieces(folder.folder, analyse_ahead=True)
        made, lived = {}, {}
        for index, number in enumerate(frames.numbers):
            took = {}
            for key in pieces.life_start_keys(index):
                took[key.kind.value] = made_piece(pieces.piece(key), made, lived, run)
            step = made[PieceKey(PieceKind.CARRY, index)]
            bands = judging_bands(step, run.shot.shape[0], THREADS_PER_MACHINE)
            if bands:
                banded.append(band_seconds(pieces, index, made, lived, run))
            for key in pieces.life_end_keys(index, bands):
                took[key.kind.value] = took.get(key.kind.value, 0.0) + made_piece(pieces.piece(key, bands), made,
                                                                                    lived, run)
            painted = lived[index] = made[PieceKey(PieceKind.BIRTH, index)]
            _, took["commit"] = timed(run.commit, folder, index, painted, made[PieceKey(PieceKind.WRITE, index)],
                                      report)
            seconds.append(took)
            travelled = {name: pickled(value) for name, value in frame_results(made, index).items()}
            sizes.append({name: size for name, (size, _) in travelled.items()})
            pickling.append({name: spent for name, (_, spent) in travelled.items()})
            if index:
                parts.append(prepared_parts(made[PieceKey(PieceKind.PREPARE, index)]))
            stages.append({k: v for k, v in painted.seconds.items() if k != "analysis"})
            strokes.append(len(painted.living))
            for key in [key for key in made if key.index < index]:
                del made[key]
            print(f"frame {number}: " + ", ".join(f"{k} {v:.2f} s" for k, v in took.items()), file=sys.stderr)
    return {"frames": frames, "seconds": seconds, "bytes": sizes, "pickling": pickling, "life_stages": stages,
            "strokes": strokes, "prepared_parts": parts, "bands": banded}


def made_piece(piece, made: dict, lived: dict, run: Run) -> float:
    """Make ``piece`` with the arguments the cluster driver gives it, keep its result in ``made``; its seconds."""
    arguments = cluster_arguments(piece, made, lived, run.shot, run.frames.paths)
    made[piece.key], spent = timed(piece.make, *arguments)
    return spent


def band_seconds(pieces, index: int, made: dict, lived: dict, run: Run) -> dict:
    """{bands: (s of all, s of the longest)} of frame ``index``'s judging canvas cut for each of BAND_COUNTS."""
    step = made[PieceKey(PieceKind.CARRY, index)]
    cuts = {}
    for count in BAND_COUNTS:
        bands = judging_bands(step, run.shot.shape[0], count)
        spent = [made_piece(pieces.piece(PieceKey(PieceKind.JUDGE, index, band), bands), {**made}, lived, run)
                 for band in range(len(bands))]
        cuts[count] = (sum(spent), max(spent))
    return cuts


def frame_results(made: dict, index: int) -> Dict[str, object]:
    """{piece kind: its result (a list of them for the JUDGE bands)} of frame ``index``'s pieces in ``made``, and
    "lived": what of its BIRTH result comes back to the client (``farm.sequence.lived_strokes``)."""
    results: Dict[str, object] = {}
    for key, value in made.items():
        if key.index == index and key.kind is PieceKind.JUDGE:
            results.setdefault(key.kind.value, []).append(value)
        elif key.index == index:
            results[key.kind.value] = value
    results["lived"] = lived_strokes(results["birth"])
    return results


def medians(rows: Sequence[Mapping[str, float]]) -> Dict[str, float]:
    """{name: median over ``rows`` of the rows' values of that name} for every name any row has."""
    names = [k for row in rows for k in row]
    return {name: statistics.median(row[name] for row in rows if name in row) for name in dict.fromkeys(names)}


def sequential_share(later: Mapping[str, float]) -> float:
    """(carry + birth + commit) / (every piece, commit included) of a frame after the first (seconds per
    piece)."""
    return sum(later[p] for p in CHAIN_PIECES) / sum(later[p] for p in PIECES)


def band_count(threads: int, measured) -> int:
    """The bands the driver cuts the judging canvas into on ``threads`` worker threads (min(threads, 8)), or the
    largest of the ``measured`` counts below that."""
    return max(count for count in measured if count <= min(threads, MAX_BANDS))


def settling(later: Mapping, threads: int) -> float:
    """Seconds the judging canvas takes on the chain with ``threads`` worker threads: its longest band
    (``later["bands"]``: {bands: (s of all, s of the longest)})."""
    return later["bands"][band_count(threads, later["bands"])][1]


def judge_work(later: Mapping, threads: int) -> float:
    """Seconds of all the judging canvas's bands on ``threads`` worker threads."""
    return later["bands"][band_count(threads, later["bands"])][0]


def sent_bytes(sizes: Mapping[str, float], sent=SENT) -> float:
    """Bytes that cross the network per frame after the first when every transfer in ``sent`` does
    ((receiver, piece whose result it receives) pairs), from the pieces' pickled ``sizes``."""
    return float(sum(sizes[piece] for _, piece in sent))


def projection(first: Mapping[str, float], later: Mapping[str, float], frames: int, threads: int,
               transfer: float = 0.0, chain_transfer: float = 0.0, shots: int = 1) -> dict:
    """Seconds to paint ``frames`` frames of one shot on ``threads`` single-threaded workers, from pieces' seconds,
    the threads shared by ``shots`` shots painted at once (each cuts its judging canvas for its share, the threads
    over the shots: ``scheduling.band_count``).

    first: the first frame's seconds per piece (no "motion"; "carry" is the still); later: a later frame's, with
    "bands" (``settling``).
    transfer: seconds per later frame its pieces spend receiving their inputs; chain_transfer: of those, the
    seconds on the life chain (the strokes to and from the client, the life's inputs).
    Returns {"chain", "commits", "work", "fill", "drain", "total"}: chain = the first frame's life + (frames - 1) x
    (carry + settling + birth + chain_transfer), the life chain (a frame's carry needs the births of the frame
    before); commits = frames x commit, the client's commits in frame order, beside the life chain (the driver
    sends the next life's pieces out before it commits); work = every worker piece of every frame (+ transfers) /
    threads; fill = the first frame's reading and analysis, before the chain starts; drain = laying and writing
    the last frame; total = max(chain, commits, work) + fill + drain.
    """
    share = max(1, threads // shots)
    later_work = sum(later[p] for p in WORKER_PIECES if p != "judge") + judge_work(later, share) + transfer
    chain = first["carry"] + (frames - 1) * (sum(later[p] for p in LIFE_PIECES) + settling(later, share)
                                             + chain_transfer)
    commits = first["commit"] + (frames - 1) * later["commit"]
    work = (sum(first.get(p, 0.0) for p in WORKER_PIECES) + (frames - 1) * later_work) / threads
    fill = first["prepare"]
    drain = later["shown"] + later["write"]
    return {"chain": chain, "commits": commits, "work": work, "fill": fill, "drain": drain,
            "total": max(chain, commits, work) + fill + drain}


def output_digests(folder: Path) -> Dict[str, str]:
    """{file name: SHA-256} of the painted files in ``folder``: every .png, .exr and strokes.lives."""
    return file_digests(folder, COMPARED_SUFFIXES)


def measure_speedup(clip: str, seed: int, runs: int, work: Path) -> dict:
    """`core sequence` on ``clip`` with --workers 1, --workers 2 and in one process (no --workers), ``runs`` times
    each in turn, each into a new folder.

    Returns {"runs": {workers (0: one process): {"walls": [s], "peaks": [MiB]}}, "same": whether every run's
    painted files are the bytes of the first run's, "files": how many files each run painted}.
    """
    results = {n: {"walls": [], "peaks": []} for n in SPEEDUP_WORKERS}
    reference, same = None, True
    for r in range(runs):
        for n in SPEEDUP_WORKERS:
            out = work / f"workers{n}_run{r}"
            farm = ["--workers", n] if n else []
            command = [sys.executable, "-m", "core", "sequence", clip, "-o", out, "--seed", seed, "-q", *farm]
            wall, peak = run_child(command, f"core sequence {' '.join(map(str, farm))}", quiet=True)
            results[n]["walls"].append(wall)
            results[n]["peaks"].append(peak)
            digests = output_digests(out)
            reference = reference or digests
            same = same and bool(digests) and digests == reference
            print(f"{workers_name(n)} run {r + 1}: {wall:.2f} s", file=sys.stderr)
    return {"runs": results, "same": same, "files": len(reference or {})}


def measure_shots(shots: Sequence[str], seed: int, runs: int, work: Path) -> dict:
    """`core batch SHOTS` with --workers 1 and 2, ``runs`` times each in turn, each into a new root, and each shot
    painted alone by `core sequence` once.

    Returns {"walls": {workers: [s]}, "same": whether every shot's folder of every run holds the bytes of that
    shot painted alone, "files": files compared per run}.
    """
    alone = {}
    for k, shot in enumerate(dict.fromkeys(shots)):
        out = work / f"alone{k}"
        run_child([sys.executable, "-m", "core", "sequence", shot, "-o", out, "--seed", seed, "-q"],
                  "core sequence (a shot alone)", quiet=True)
        alone[shot] = output_digests(out)
    walls, same, files = {1: [], 2: []}, True, 0
    for r in range(runs):
        for n in (1, 2):
            root = work / f"batch_workers{n}_run{r}"
            wall, _ = run_child([sys.executable, "-m", "core", "batch", *shots, "-o", root, "--seed", seed, "-q",
                                 "--workers", n], f"core batch --workers {n}", quiet=True)
            walls[n].append(wall)
            folders = sorted(p for p in root.iterdir() if p.is_dir())
            painted = [output_digests(folder) for folder in folders]
            files = sum(len(d) for d in painted)
            same = same and len(folders) == len(shots) and all(
                digests == alone[shot] for digests, shot in zip(painted, sorted_shots(shots, folders), strict=True))
            print(f"core batch --workers {n} run {r + 1}: {wall:.2f} s", file=sys.stderr)
    return {"walls": walls, "same": same, "files": files}


def sorted_shots(shots: Sequence[str], folders: Sequence[Path]) -> list:
    """The shot painted into each of ``folders`` (sorted by name): batch names a shot's folder
    <shot name>_<counter>, in the inputs' order among shots of one name."""
    from core.files.shot_files import shot_name

    names = {}
    for shot in shots:
        names.setdefault(shot_name(shot), []).append(shot)
    return [names[folder.name.rsplit("_", 1)[0]][int(folder.name.rsplit("_", 1)[1]) - 1] for folder in folders]


def print_shots(measured: dict, shots: Sequence[str], runs: int) -> None:
    """The many-shots table: --workers 1 and 2, the ratio and whether the bytes are those of each shot alone."""
    print(f"`core batch {' '.join(shots)} --seed 5 --workers N` ({len(shots)} shots at once), wall time of the whole "
          f"command, median of {runs}")
    medians = {n: statistics.median(walls) for n, walls in measured["walls"].items()}
    for n, walls in measured["walls"].items():
        print(f"{workers_name(n):<36} {medians[n]:>9.2f} {min(walls):>6.2f}-{max(walls):.2f}")
    print(f"--workers 2 / --workers 1: {medians[2] / medians[1]:.2f} (the issue asks <= 0.6)")
    print(f"same bytes as each shot painted alone: {'yes' if measured['same'] else 'no'} ({measured['files']} files "
          f"a run)")


def workers_name(n: int) -> str:
    """"--workers 2", or "one process" for 0 (no --workers)."""
    return f"--workers {n}" if n else "one process"


def megabytes(value: float) -> str:
    """Bytes as MB (10^6), 3 significant figures."""
    return f"{value / 1e6:.3g}"


def print_pieces(measured: dict) -> tuple:
    """The per-piece table; returns (the first frame's seconds, the later frames' medians, their pickled bytes)."""
    frames, seconds, sizes = measured["frames"], measured["seconds"], measured["bytes"]
    first, later = seconds[0], medians(seconds[1:])
    later_bytes, later_pickling = medians(sizes[1:]), medians(measured["pickling"][1:])
    spread = {p: (min(s[p] for s in seconds[1:]), max(s[p] for s in seconds[1:])) for p in PIECES}
    bands = {count: tuple(statistics.median(cuts[count][k] for cuts in measured["bands"]) for k in (0, 1))
             for count in BAND_COUNTS}
    n = len(frames.paths)
    print(f"clip {frames.paths[0].parent}: frames {frames.numbers[0]}-{frames.numbers[-1]} ({n}), "
          f"{frames.width}x{frames.height} ({frames.width * frames.height / 1e6:.2f} MP); painter on one thread "
          f"as on a Dask worker; strokes alive: first {measured['strokes'][0]}, later median "
          f"{statistics.median(measured['strokes'][1:]):.0f}")
    print(f"{'piece':<10} {'first frame s':>14} {'later frames s (median)':>24} {'min-max':>13} "
          f"{'result pickled MB':>18} {'pickle+unpickle s':>18}")
    for piece in PIECES:
        low, high = spread[piece]
        size, spent = ("-", "-") if piece == "commit" else (megabytes(later_bytes[piece]),
                                                             f"{later_pickling[piece]:.2f}")
        print(f"{piece:<10} {first.get(piece, float('nan')):>14.2f} {later[piece]:>24.2f} "
              f"{f'{low:.2f}-{high:.2f}':>13} {size:>18} {spent:>18}")
    print(f"{'all':<10} {sum(first.values()):>14.2f} {sum(later[p] for p in PIECES):>24.2f}")
    print("judge, the judging canvas in bands of rows (median s, all bands / the longest): "
          + ", ".join(f"{count} band{'s' if count > 1 else ''} {all_:.2f} / {longest:.2f}"
                      for count, (all_, longest) in bands.items()))
    print("prepare's result pickled, MB by part (median): "
          + ", ".join(f"{k} {megabytes(v)}" for k, v in medians(measured["prepared_parts"]).items()))
    stages = medians(measured["life_stages"][1:])
    print("life of a later frame, its own stages (median s): "
          + ", ".join(f"{k} {v:.2f}" for k, v in stages.items()))
    print(f"peak resident memory of this process: {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} "
          f"MiB")
    return first, dict(later, bands=bands), later_bytes


def print_projection(first, later, later_bytes, frames: int, gbps: float) -> None:
    """The projection table for 1, 8 and 32 machines, without and with the network."""
    volume, chain_volume = sent_bytes(later_bytes), sent_bytes(later_bytes, CHAIN_SENT)
    rate = gbps * 1e9
    print(f"transfer per later frame if every piece's inputs (and the results the client gathers) crossed the "
          f"network: {megabytes(volume)} MB ({megabytes(chain_volume)} MB of it on the life chain); at {gbps:g} GB/s "
          f"{volume / rate:.2f} s of transfer per frame, {chain_volume / rate:.2f} s of it on the chain")
    print(f"PROJECTION from the measured task times (not a run on a cluster): {frames} frames of this clip's "
          f"size; each machine {THREADS_PER_MACHINE} single-threaded workers (like this one); "
          f"total = max(chain, commits, work / threads) + fill + drain; commits {projection(first, later, frames, 1)['commits']:.0f} s")
    print(f"{'machines':>8} {'threads':>7} {'chain s':>9} {'work/threads s':>15} {'fill s':>7} {'drain s':>8} "
          f"{'total s':>9} {'s/frame':>8} {'x 1 machine':>11} {'x 1 thread':>10} {'total s at ' + f'{gbps:g} GB/s':>18}")
    alone = projection(first, later, frames, 1)["work"]
    one = None
    for machines in MACHINES:
        threads = machines * THREADS_PER_MACHINE
        p = projection(first, later, frames, threads)
        net = projection(first, later, frames, threads, volume / rate, chain_volume / rate)
        one = one or p["total"]
        print(f"{machines:>8} {threads:>7} {p['chain']:>9.0f} {p['work']:>15.0f} {p['fill']:>7.1f} "
              f"{p['drain']:>8.1f} {p['total']:>9.0f} {p['total'] / frames:>8.2f} {one / p['total']:>11.1f} "
              f"{alone / p['total']:>10.1f} "
              f"{net['total']:>18.0f}")
    print(f"one thread (every piece in turn, no commit): {alone:.0f} s; the chain allows at most "
          f"{alone / projection(first, later, frames, 10**6)['total']:.1f} times that speed on any cluster")
    print(f"many shots at once (`core batch`): each shot's chain is its own, so S shots of {frames} frames take "
          f"max(chain, commits, S x work / threads) + fill + drain (each shot commits in a thread of its own and cuts its "
          f"judging canvas for its share of the threads); frames a second as a multiple of one shot on one machine")
    print(f"{'machines':>8} " + " ".join(f"{f'{shots} shot' + ('s' if shots > 1 else ''):>9}" for shots in SHOTS))
    for machines in MACHINES:
        at_once = [projection(first, later, frames, machines * THREADS_PER_MACHINE, shots=shots) for shots in SHOTS]
        rates = [shots * frames / (max(p["chain"], p["commits"], shots * p["work"]) + p["fill"] + p["drain"])
                 for shots, p in zip(SHOTS, at_once, strict=True)]
        print(f"{machines:>8} " + " ".join(f"{rate * one / frames:>9.1f}" for rate in rates))


def print_speedup(measured: dict, clip: str, runs: int) -> None:
    """The --workers 1 and 2 table, the ratio and whether the bytes are the same."""
    frames = find_frames([clip])
    print(f"`core sequence {clip} --seed 5 --workers N`, {len(frames.paths)} frames {frames.width}x{frames.height} "
          f"({frames.width * frames.height / 1e6:.2f} MP), wall time of the whole command, median of {runs}")
    print(f"{'run':<36} {'median s':>9} {'min-max s':>13} {'peak MiB (largest process)':>27}")
    walls = {}
    for n, m in measured["runs"].items():
        walls[n] = statistics.median(m["walls"])
        spread = f"{min(m['walls']):.2f}-{max(m['walls']):.2f}"
        name = workers_name(n) + ("" if n else " (no --workers, no Dask)")
        print(f"{name:<36} {walls[n]:>9.2f} {spread:>13} {max(m['peaks']):>27.0f}")
    print(f"--workers 2 / --workers 1: {walls[2] / walls[1]:.2f} (target <= 0.75)")
    print(f"same bytes: {'yes' if measured['same'] else 'no'} ({measured['files']} files of every run compared)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clip", default=str(CLIP), help=f"frames whose pieces are timed (default {CLIP})")
    parser.add_argument("--frames", default=None, metavar="A-B",
                        help=f"frames of --clip (default {CLIP_FRAMES} for the default clip, else all)")
    parser.add_argument("--small-clip", default=str(SMALL_CLIP),
                        help=f"clip painted with --workers 1 and 2 (default {SMALL_CLIP})")
    parser.add_argument("--shots", nargs="+", default=None, metavar="SHOT",
                        help="shots painted at once by core batch (default --small-clip twice)")
    parser.add_argument("--runs", type=int, default=3, help="runs of each --workers N (default 3)")
    parser.add_argument("--seed", type=int, default=5)
    parser.add_argument("--projected-frames", type=int, default=PROJECTED_FRAMES, help="frames of the projection")
    parser.add_argument("--network-gbps", type=float, default=1.0, help="GB/s of the projection's network")
    parser.add_argument("--skip-pieces", action="store_true", help="measure the speed-up only")
    parser.add_argument("--skip-speedup", action="store_true", help="skip `core sequence --workers N`")
    parser.add_argument("--skip-shots", action="store_true", help="skip `core batch` of many shots")
    args = parser.parse_args()
    if args.runs < 1 or args.projected_frames < 2:
        parser.error("--runs must be at least 1 and --projected-frames at least 2")
    for clip, option, skipped in ((args.clip, "--clip", args.skip_pieces),
                                  (args.small_clip, "--small-clip", args.skip_speedup and (args.skip_shots or
                                                                                           args.shots)),
                                  *((shot, "--shots", args.skip_shots) for shot in args.shots or ())):
        if not skipped and not Path(clip).exists():
            parser.error(f"{option} {clip} does not exist: give footage, or render a clip with "
                         f"`python sample_scenes/sequence_scene.py -o DIR --frames 6 --size 424x240 --png`")
    frame_range = args.frames or (CLIP_FRAMES if Path(args.clip) == CLIP else None)
    print(f"{os.cpu_count()} cores", file=sys.stderr)
    with tempfile.TemporaryDirectory() as tmp:
        # The commands run first: a child started by vfork keeps this process's peak as its own ru_maxrss.
        speedup = None if args.skip_speedup else measure_speedup(args.small_clip, args.seed, args.runs,
                                                                  Path(tmp) / "speedup")
        shots = args.shots or [args.small_clip, args.small_clip]
        at_once = None if args.skip_shots else measure_shots(shots, args.seed, args.runs, Path(tmp) / "shots")
        if not args.skip_pieces:
            measured = measure_pieces(args.clip, frame_range, args.seed, Path(tmp) / "pieces")
            if len(measured["seconds"]) < 2:
                parser.error("the pieces need at least 2 frames")
            first, later, later_bytes = print_pieces(measured)
            print(f"sequential share of a later frame: (carry + birth + commit) / all = "
                  f"({' + '.join(f'{later[p]:.2f}' for p in CHAIN_PIECES)}) / "
                  f"{sum(later[p] for p in PIECES):.2f} = {sequential_share(later):.2f} (the design asks <= 0.25)")
            print_projection(first, later, later_bytes, args.projected_frames, args.network_gbps)
        if speedup is not None:
            print_speedup(speedup, args.small_clip, args.runs)
        if at_once is not None:
            print_shots(at_once, shots, args.runs)


if __name__ == "__main__":
    main()
