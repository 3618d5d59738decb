"""A shot's frames painted on a Dask cluster, committed in order by this process (ALGORITHM §9).

Each piece of a frame's work (``core.sequence.pieces``) is a Dask task: a
frame's PREPARE piece (reading, analysis) and its motion from the frame
before run ahead on any worker, as far as ``scheduling.frames_ahead``
frames beyond the last committed. The strokes' life starts as soon as the
frame before has lived, in three steps: the carry (one short task), the
judging canvas they make in bands of rows side by side (one JUDGE task
each), and the births on it (one task). Laying the frame shown and writing
its maps into a staging folder of their own follow on any worker. This
process commits each frame (the lives record, the state, the report and
the staging folder, ``shot.Run.commit``) in frame order, so the output
folder only ever holds complete frames, exactly as one process writes them.

Which piece runs next and where is ``scheduling``'s choice: no more pieces
running than the cluster has threads, the most urgent first, each on the
free worker that holds most of its inputs. Several shots painted at once
(``core batch``) share the threads (``shared_threads``).

A frame's strokes come back to this process (without the canvas its births
were laid on, which only its SHOWN piece needs: ``lived_strokes``) and
travel with the next frame's life tasks (``frame_file.cluster_arguments``),
so the life never depends on data held by one worker alone: a lost
worker's tasks run again elsewhere from their own arguments, and the bytes
are those of one process. A task that runs twice writes two staging
folders; one is committed and the other removed at the end.
"""

from __future__ import annotations

import concurrent.futures
import contextlib
import secrets
import time
from typing import Dict, List, Set

from ..errors import Cancelled
from ..files import signals
from ..files.staging import recover
from ..progress import CancelFn, ProgressFn
from ..sequence.frame_step import PaintedFrame
from ..sequence.pieces import PieceKey, PieceKind, Rows, judging_bands
from ..sequence.shot import Run
from .cluster import FarmError, address, check_new_workers, describe, import_distributed, large_arguments, raise_error
from .frame_file import cluster_arguments
from .scheduling import Board, band_count, frames_ahead, place, urgent
from .shared_threads import SharedThreads

WAIT_SECONDS = 0.25
"""Seconds between looks at the cancel callback while tasks run."""

STOP_SECONDS = 30.0
"""The longest a stopped run waits for the maps it was writing (``ClusterRun.stop``)."""


def lived_strokes(painted: PaintedFrame) -> PaintedFrame:
    """What of a frame's BIRTH piece comes back to this process: all but the canvas its births were laid on."""
    return painted._replace(laid_on=None)


class ClusterFrames:
    """``shot.paint_sequence``'s way of painting frames, on the cluster of ``client``; ``shared``: the threads
    shared with the other shots painted at once (None: the shot has the cluster to itself)."""

    def __init__(self, client, shared: SharedThreads = None):
        self.client, self.shared = client, shared

    def __call__(self, run: Run, start: int, report: dict, folder, progress: ProgressFn, cancel: CancelFn) -> None:
        """Paint ``run``'s frames ``start`` .. the last on the cluster, committing each in order."""
        distributed = import_distributed()
        try:
            with large_arguments(), self.client.as_current():
                ClusterRun(self.client, run, start, folder, self.shared).paint(report, progress, cancel)
        except (concurrent.futures.CancelledError, distributed.comm.CommClosedError, OSError):
            raise FarmError(f"Lost the Dask scheduler at {address(self.client)}; the complete frames in "
                            f"{folder.folder} stay, and the same command goes on after them.") from None
        except distributed.scheduler.KilledWorker as exc:
            raise FarmError(f"Dask workers died again and again on {exc.task}; the complete frames in "
                            f"{folder.folder} stay, and the same command goes on after them.") from None
        recover(folder.folder)


class ClusterRun:
    """One run's pieces on the cluster: their futures, the worker each running one was sent to, the strokes
    gathered in this process and each living frame's judging bands; ``shared``: the threads it shares with other
    runs (None: its own)."""

    def __init__(self, client, run: Run, start: int, folder, shared: SharedThreads = None):
        self.client, self.run, self.start, self.folder = client, run, start, folder
        self.shared = SharedThreads() if shared is None else shared
        self.pieces = run.pieces(folder.folder, analyse_ahead=True)
        self.count = len(run.frames.paths)
        self.token = secrets.token_hex(4)
        self.futures: Dict[PieceKey, object] = {}
        self.running: Dict[object, str] = {}      # future: the worker it was sent to
        self.strokes: Dict[int, object] = {}
        self.gathering: Dict[int, object] = {}     # frame: the future of its ``lived_strokes``
        self.bands: Dict[int, List[Rows]] = {}     # frame: the rows of its JUDGE pieces, once its carry is made
        self.threads: Dict[str, int] = {}
        self.checked: Set[str] = set()          # the workers known to see the frames and the output folder

    def paint(self, report: dict, progress: ProgressFn, cancel: CancelFn) -> None:
        """Run pieces and commit frames in order until every frame is committed."""
        self.shared.join(self)
        try:
            self.paint_frames(report, progress, cancel)
        except BaseException:
            self.stop()
            raise
        finally:
            self.shared.leave(self)

    def stop(self) -> None:
        """Leave the output folder as its committed frames alone left it, before the run lets go of its lock.

        The pieces not done are cancelled, but a worker cannot be stopped midway through a piece: a WRITE piece
        already sent writes its staging folder whatever the cancel. So the WRITE pieces sent are waited for (at most
        STOP_SECONDS; each was sent with its inputs made) and then every staging folder not committed is removed.
        A lost scheduler or worker ends the wait early; the staging folders are removed all the same."""
        distributed = import_distributed()
        writing = [f for k, f in self.futures.items() if k.kind is PieceKind.WRITE and not f.done()]
        others = [f for k, f in self.futures.items() if k.kind is not PieceKind.WRITE and not f.done()]
        with signals.deferred(), contextlib.suppress(Exception):
            self.client.cancel(others + [f for f in self.gathering.values() if not f.done()])
            distributed.wait(writing, timeout=STOP_SECONDS)
        with signals.deferred():
            recover(self.folder.folder)

    def paint_frames(self, report: dict, progress: ProgressFn, cancel: CancelFn) -> None:
        """``paint``'s loop."""
        distributed = import_distributed()
        self.threads = self.client.nthreads()
        self.check_new_workers()
        where = describe(self.client)
        if self.start > 0:
            self.strokes[self.start - 1] = self.run.resumed_frame(self.folder.folder)
            if self.run.shot.measures:
                self.submit(PieceKey(PieceKind.SHOWN, self.start - 1))
        committed = living = self.start
        self.report_progress(progress, committed, where)
        while committed < self.count:
            if cancel is not None and cancel():
                raise Cancelled("The run was cancelled.")
            self.dispatch(committed, living)
            running = self.shared.futures()     # every run's pieces not done yet: a thread one frees wakes all
            if running:
                try:
                    distributed.wait(running, timeout=WAIT_SECONDS, return_when="FIRST_COMPLETED")
                except TimeoutError:
                    pass
            elif not any(future.done() for future in self.running):
                time.sleep(WAIT_SECONDS)
            for future in [f for f in self.running if f.done()]:
                worker = self.running.pop(future)
                self.shared.finished(future)
                if future.status != "finished":
                    raise_error(future, f"in the piece {future.key} (sent to {worker})")
            living = self.lived(living)
            while committed < living and self.made(PieceKey(PieceKind.WRITE, committed)):
                self.dispatch(committed, living)    # the next life's pieces leave before a commit holds this thread
                self.commit(committed, report)
                committed += 1
                self.report_progress(progress, committed, where)

    def lived(self, living: int) -> int:
        """Cut frame ``living``'s judging bands once its carry is made, gather its strokes once its BIRTH piece is
        made; return the first frame that has not lived."""
        if self.made(PieceKey(PieceKind.CARRY, living)) and living not in self.bands:
            step = self.futures[PieceKey(PieceKind.CARRY, living)].result()
            self.bands[living] = judging_bands(step, self.run.shot.shape[0],
                                               band_count(self.threads, self.shared.count()))
        if self.made(PieceKey(PieceKind.BIRTH, living)) and living not in self.gathering:
            birth = self.futures[PieceKey(PieceKind.BIRTH, living)]
            holders = list(self.client.who_has([birth]).values())
            worker = holders[0][0] if holders and holders[0] else None
            future = self.client.submit(lived_strokes, birth, key=f"paint-relief-lived-"
                                        f"{self.run.frames.numbers[living]}-{self.token}", pure=False,
                                        workers=worker and [worker], allow_other_workers=True)
            self.gathering[living] = future
            self.running[future] = worker
            self.shared.started(self, future, worker)
        if living in self.gathering and self.gathering[living].done():
            self.strokes[living] = self.gathering.pop(living).result()
            return living + 1
        return living

    def board(self) -> Board:
        """Where the run stands (``scheduling.Board``)."""
        return Board(self.count, set(self.futures), {k for k, f in self.futures.items() if f.done()},
                     set(self.strokes), {index: len(bands) for index, bands in self.bands.items()},
                     self.run.shot.measures)

    def dispatch(self, committed: int, living: int) -> None:
        """Start the most urgent pieces that can run, while fewer pieces run than the cluster has threads."""
        self.threads = self.client.nthreads()
        self.check_new_workers()
        ahead = frames_ahead(committed, self.count, self.threads)
        for key in list(urgent(self.board(), committed, living, ahead)):
            if not self.shared.may_start(self, self.threads):
                return
            self.submit(key)
        self.shared.satisfied(self)

    def check_new_workers(self) -> None:
        """Check that the workers not checked yet (every worker at the start, then any that joins) can read the
        frames still to paint and write into the output folder: OutputError naming the worker and the path."""
        check_new_workers(self.client, self.threads, self.checked, self.run.frames.paths[max(self.start - 1, 0):],
                          [self.folder.folder])

    def made(self, key: PieceKey) -> bool:
        """Whether the piece ``key`` has been made."""
        future = self.futures.get(key)
        return future is not None and future.done()

    def submit(self, key: PieceKey) -> None:
        """Submit the piece ``key`` (``pieces.ShotPieces.piece``) with its arguments
        (``frame_file.cluster_arguments``), keyed so on the dashboard, to the worker ``scheduling.place`` picks."""
        piece = self.pieces.piece(key, self.bands.get(key.index, ()))
        args = cluster_arguments(piece, self.futures, self.strokes, self.run.shot, self.run.frames.paths)
        inputs = [a for a in args if hasattr(a, "key")]
        holders = self.client.who_has(inputs).values() if inputs else ()
        worker = place(self.shared.free(self.threads), self.threads, holders)
        name = f"paint-relief-{key.kind.value}{key.band if key.kind is PieceKind.JUDGE else ''}"
        future = self.client.submit(piece.make, *args, key=f"{name}-{self.run.frames.numbers[key.index]}-{self.token}",
                                    pure=False, workers=worker and [worker], allow_other_workers=True)
        self.futures[key] = future
        self.running[future] = worker
        self.shared.started(self, future, worker)

    def commit(self, index: int, report: dict) -> None:
        """Commit frame ``index`` (``Run.commit``) and let go of what only it and the frame before needed."""
        self.run.commit(self.folder, index, self.strokes[index],
                        self.futures[PieceKey(PieceKind.WRITE, index)].result(), report)
        self.bands.pop(index, None)
        for key in [key for key in self.futures if key.index == index and key.kind is not PieceKind.SHOWN]:
            del self.futures[key]
        self.futures.pop(PieceKey(PieceKind.SHOWN, index - 1), None)
        self.strokes.pop(index - 1, None)

    def report_progress(self, progress: ProgressFn, committed: int, where: str) -> None:
        """"3/12 frames committed (2 workers, dashboard ...)"."""
        if progress is not None:
            progress(committed / self.count, f"{committed}/{self.count} frames committed ({where})")
