"""A sequence's frames painted on a Dask cluster, committed in order by this process (ALGORITHM §9).

Each frame's pieces (``pieces``) are Dask tasks: a frame's analysis and
its motion from the frame before run ahead on any worker, as far as
``ahead`` frames beyond the last committed. The strokes' life starts as
soon as the frame before has lived, in three steps: carrying the strokes
(one short task), laying the judging canvas they make (bands of rows side
by side, one task each: ``frame_step.settled_rows``), and the births on it
(one task). Laying the frame shown and writing its maps into a staging
folder of their own follow on any worker. This process commits each frame (the lives record, the
state, the report and the staging folder, ``shot.Run.commit``) in frame
order, so the output folder only ever holds complete frames, exactly as one
process writes them.

This process also decides which piece runs next and where: it keeps no
more pieces running than the cluster has threads, picks the next life
first, then what the next lives need, then laying and writing, earlier
frames first, and sends each to a worker with a free thread, the one that
holds most of its inputs. Handing Dask everything at once lets a worker
queue the next life behind other work where its inputs are while another
worker idles, and the life chain waits.

A frame's strokes come back to this process and travel with the next
frame's life task, so the life never depends on data held by one worker
alone: a lost worker's tasks run again elsewhere from their own arguments,
and the bytes are those of one process. A task that runs twice writes two
staging folders; one is committed and the other removed at the end.
"""

from __future__ import annotations

import concurrent.futures
import secrets
import time
from typing import Dict, List, Optional, Set, Tuple

from ..errors import Cancelled
from ..files.staging import recover
from ..progress import CancelFn, ProgressFn
from ..sequence.frame_step import Carried, settled_rows
from ..sequence.shot import VECTOR_PASS_MOTION, Run
from ..sequence.tasks import shown_frame
from .cluster import FarmError, address, check_new_workers, describe, import_distributed, large_arguments, raise_error
from .pieces import born, carried, motion_between, prepared, written

WAIT_SECONDS = 0.25
"""Seconds between looks at the cancel callback while tasks run."""

MAX_BANDS = 8
"""Bands of rows a frame's judging canvas is laid in at most, side by side (one per worker thread up to this): a
stroke across a band's edge is laid in both, so more bands than this cost more than they save."""


def row_bands(height: int, parts: int) -> List[Tuple[int, int]]:
    """[(first, stop), ...]: ``parts`` (at least 1) consecutive runs of about equal numbers of a frame's ``height``
    rows."""
    parts = max(1, min(parts, height))
    cuts = [height * k // parts for k in range(parts + 1)]
    return list(zip(cuts[:-1], cuts[1:], strict=True))


class ClusterFrames:
    """``shot.paint_sequence``'s way of painting frames, on the cluster of ``client``."""

    def __init__(self, client):
        self.client = client

    def __call__(self, run: Run, start: int, report: dict, folder, progress: ProgressFn, cancel: CancelFn) -> None:
        """Paint ``run``'s frames ``start`` .. the last on the cluster, committing each in order."""
        distributed = import_distributed()
        try:
            with large_arguments(), self.client.as_current():
                Frames(self.client, run, start, folder).paint(report, progress, cancel)
        except (concurrent.futures.CancelledError, distributed.comm.CommClosedError, OSError):
            raise FarmError(f"Lost the Dask scheduler at {address(self.client)}; the complete frames in "
                            f"{folder.folder} stay, and the same command goes on after them.") from None
        except distributed.scheduler.KilledWorker as exc:
            raise FarmError(f"Dask workers died again and again on {exc.task}; the complete frames in "
                            f"{folder.folder} stay, and the same command goes on after them.") from None
        recover(folder.folder)


class Frames:
    """One run's pieces: which are running, which are made (their futures), and the strokes gathered."""

    def __init__(self, client, run: Run, start: int, folder):
        self.client, self.run, self.start, self.folder = client, run, start, folder
        self.count = len(run.frames.paths)
        self.token = secrets.token_hex(4)
        self.vector_pass = run.motion == VECTOR_PASS_MOTION
        self.shape = (run.frames.height, run.frames.width)
        self.futures: Dict[Tuple[str, int], object] = {}
        self.running: Dict[object, str] = {}      # future: the worker it was sent to
        self.strokes: Dict[int, object] = {}
        self.bands: Dict[int, List[Tuple[int, int]]] = {}     # frame: the rows of its judging canvas's pieces
        self.threads: Dict[str, int] = {}
        self.checked: Set[str] = set()          # the workers known to see the frames and the output folder

    def paint(self, report: dict, progress: ProgressFn, cancel: CancelFn) -> None:
        """Run pieces and commit frames in order until every frame is committed."""
        distributed = import_distributed()
        self.threads = self.client.nthreads()
        self.check_new_workers()
        where = describe(self.client)
        if self.start > 0:
            self.strokes[self.start - 1] = self.run.resumed_frame(self.folder.folder)
            self.submit("shown", self.start - 1, shown_frame, self.strokes[self.start - 1], self.run.params,
                        self.shape)
        committed = living = self.start
        self.report_progress(progress, committed, where)
        while committed < self.count:
            if cancel is not None and cancel():
                raise Cancelled("The run was cancelled.")
            self.dispatch(committed, living)
            if not self.running:
                time.sleep(WAIT_SECONDS)
                continue
            try:
                distributed.wait(list(self.running), timeout=WAIT_SECONDS, return_when="FIRST_COMPLETED")
            except TimeoutError:
                continue
            for future in [f for f in self.running if f.done()]:
                worker = self.running.pop(future)
                if future.status != "finished":
                    raise_error(future, f"in the piece {future.key} (sent to {worker})")
            living = self.lived(living)
            while committed < living and self.made("write", committed):
                self.commit(committed, report)
                committed += 1
                self.report_progress(progress, committed, where)

    def lived(self, living: int) -> int:
        """Gather frame ``living``'s strokes when its life is over; return the first frame that has not lived."""
        if self.made("carry", living) and living not in self.bands and ("life", living) not in self.futures:
            first_step = self.futures["carry", living].result()
            if isinstance(first_step, Carried):
                self.bands[living] = row_bands(self.shape[0], min(sum(self.threads.values()), MAX_BANDS))
            else:
                self.futures["life", living] = self.futures["carry", living]
        elif self.made("birth", living) and ("life", living) not in self.futures:
            self.futures["life", living] = self.futures["birth", living]
        if self.made("life", living):
            self.strokes[living] = self.futures["life", living].result()
            return living + 1
        return living

    def dispatch(self, committed: int, living: int) -> None:
        """Start the most urgent pieces that can run, while fewer pieces run than the cluster has threads."""
        self.threads = self.client.nthreads()
        self.check_new_workers()
        ahead = min(self.count, committed + 2 * max(sum(self.threads.values()), 1) + 2)
        for piece in self.urgent(committed, living, ahead):
            if not self.free_workers():
                return
            self.start_piece(*piece)

    def check_new_workers(self) -> None:
        """Check that the workers not checked yet (every worker at the start, then any that joins) can read the
        frames still to paint and write into the output folder: OutputError naming the worker and the path."""
        check_new_workers(self.client, self.threads, self.checked, self.run.frames.paths[max(self.start - 1, 0):],
                          [self.folder.folder])

    def free_workers(self) -> Dict[str, int]:
        """{worker: threads} of the workers running fewer of this run's pieces than they have threads."""
        busy: Dict[str, int] = {}
        for worker in self.running.values():
            busy[worker] = busy.get(worker, 0) + 1
        return {w: n - busy.get(w, 0) for w, n in self.threads.items() if n > busy.get(w, 0)}

    def place(self, inputs) -> Optional[str]:
        """The free worker that holds the most of the futures ``inputs`` (the first by address on a tie); when none
        is free, any worker; None when there is no worker."""
        free = sorted(self.free_workers()) or sorted(self.threads)
        if not free:
            return None
        held = {w: 0 for w in free}
        if inputs:
            for workers in self.client.who_has(inputs).values():
                for worker in workers:
                    if worker in held:
                        held[worker] += 1
        return max(free, key=lambda w: held[w])

    def urgent(self, committed: int, living: int, ahead: int):
        """(name, index) of the pieces that can start now, most urgent first: frames ``committed`` on are not
        committed, frames ``living`` on have not lived, frames ``ahead`` on wait."""
        if self.ready_to_live(living):
            yield "carry", living
        for band in range(len(self.bands.get(living, ()))):
            if (f"settle{band}", living) not in self.futures:
                yield f"settle{band}", living
        if (living in self.bands and ("birth", living) not in self.futures
                and all(self.made(f"settle{band}", living) for band in range(len(self.bands[living])))):
            yield "birth", living
        for index in range(living, min(living + 2, ahead)):
            yield from self.preparing(index)
        for index in range(committed, living):
            if ("shown", index) not in self.futures:
                yield "shown", index
            if self.ready_to_write(index):
                yield "write", index
        for index in range(living + 2, ahead):
            yield from self.preparing(index)

    def preparing(self, index: int):
        """The pieces frame ``index`` needs before it can live, not started yet."""
        if ("prepared", index) not in self.futures:
            yield "prepared", index
        if index > 0 and ("motion", index) not in self.futures:
            yield "motion", index

    def ready_to_live(self, index: int) -> bool:
        """Whether frame ``index``'s life can start: the frame before has lived, and its own pieces are made."""
        return (index < self.count and ("carry", index) not in self.futures
                and (index == 0 or index - 1 in self.strokes) and self.made("prepared", index)
                and (index == 0 or self.made("motion", index)))

    def ready_to_write(self, index: int) -> bool:
        """Whether frame ``index``'s maps can be written: it and the frame before are shown."""
        return (("write", index) not in self.futures and self.made("shown", index)
                and (index == 0 or (self.made("shown", index - 1) and self.made("motion", index))))

    def made(self, name: str, index: int) -> bool:
        """Whether the piece ``name`` of frame ``index`` has been made."""
        future = self.futures.get((name, index))
        return future is not None and future.done()

    def start_piece(self, name: str, index: int) -> None:
        """Submit the piece ``name`` of frame ``index``."""
        run, paths, number = self.run, self.run.frames.paths, self.run.frames.numbers[index]
        params, future = run.params, self.futures.get
        if name == "prepared":
            self.submit(name, index, prepared, paths[index], params, self.vector_pass, index > 0)
        elif name == "motion":
            self.submit(name, index, motion_between, paths[index - 1], paths[index], params, self.vector_pass)
        elif name == "carry":
            self.submit(name, index, carried, self.strokes.get(index - 1), index, future(("prepared", index)),
                        future(("motion", index)), params, run.settings.fade_frames)
        elif name.startswith("settle"):
            rows = self.bands[index][int(name[len("settle"):])]
            self.submit(name, index, settled_rows, future(("carry", index)), params, self.shape, rows)
        elif name == "birth":
            self.submit(name, index, born, self.strokes[index - 1], index, future(("prepared", index)),
                        future(("motion", index)), params, future(("carry", index)),
                        *(future((f"settle{band}", index)) for band in range(len(self.bands[index]))))
        elif name == "shown":
            self.submit(name, index, shown_frame, future(("life", index)), params, self.shape)
        else:
            self.submit(name, index, written, self.folder.folder, number, future(("life", index)),
                        future(("shown", index)), paths[index], future(("shown", index - 1)),
                        paths[index - 1] if index else None, future(("motion", index)), params,
                        run.settings.normal_map)

    def submit(self, name: str, index: int, function, *args) -> None:
        """Run ``function(*args)`` as the piece ``name`` of frame ``index``, keyed so on the dashboard."""
        key = f"paint-relief-{name}-{self.run.frames.numbers[index]}-{self.token}"
        worker = self.place([a for a in args if hasattr(a, "key")])
        future = self.client.submit(function, *args, key=key, pure=False, workers=worker and [worker],
                                    allow_other_workers=True)
        self.futures[name, index] = future
        self.running[future] = worker

    def commit(self, index: int, report: dict) -> None:
        """Commit frame ``index`` (``Run.commit``) and let go of what only it and the frame before needed."""
        self.run.commit(self.folder, index, self.strokes[index], self.futures["write", index].result(), report)
        for name in ("prepared", "motion", "carry", "birth", "life", "write",
                     *(f"settle{band}" for band in range(len(self.bands.pop(index, ()))))):
            self.futures.pop((name, index), None)
        self.futures.pop(("shown", index - 1), None)
        self.strokes.pop(index - 1, None)

    def report_progress(self, progress: ProgressFn, committed: int, where: str) -> None:
        """"3/12 frames committed (2 workers, dashboard ...)"."""
        if progress is not None:
            progress(committed / self.count, f"{committed}/{self.count} frames committed ({where})")

