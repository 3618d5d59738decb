"""``paint_objects``: several objects' textures painted side by side in worker processes, with a resume.

One painting keeps the machine's cores busy only part of the time (much of
it is serial, and threads share one interpreter lock), so the objects are
painted each in a process of its own (``worker``), as many at once as there
are cores, each process with its share of the cores as worker threads. Each
is painted by ``core.paint_object`` with the job's own arguments, so its
folder holds the bytes ``paint_object`` alone writes (the number of threads
changes no byte: ``core.workers``), committed all together or not at all.

A job whose folder already holds its painting (``kept_report``) is kept and
not painted again, so a run stopped anywhere and run again paints only what
is missing or changed. With a farm the jobs not kept are painted on a Dask
cluster instead, one task each (``farm.objects``), with the same bytes.
"""

from __future__ import annotations

import importlib
import json
import os
import queue
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Callable, Dict, List, NamedTuple, Optional

from .. import errors, tuning
from ..errors import Cancelled, PaintReliefError, ParameterError
from ..progress import CancelFn, ProgressFn
from .jobs import checked_job, write_job
from .worker import DONE_TAG, PROGRESS_TAG, STOP_FILE, result_name

ROOT = Path(__file__).resolve().parents[2]
"""The folder holding the ``core`` package (the extension's own folder inside Blender): the workers' path."""

KEPT, PAINTED = "kept", "painted"
"""What ``paint_objects`` did with a job, its report's "batch": kept the painting its folder held, or painted it."""

WAIT_SECONDS = 0.1
"""Seconds between looks at the cancel callback and the workers."""

STOP_SECONDS = 20.0
"""Seconds a worker is given to stop after it is asked to (it stops at its next look at the cancel callback,
well under a second while painting) before it is killed."""



class ObjectOutcome(NamedTuple):
    """What became of one job of ``paint_objects``: exactly one of the two is not None."""

    report: Optional[dict]
    """``paint_object``'s report (as report.json holds it, with "output_dir"), and "batch": ``KEPT`` or
    ``PAINTED``; None when the job failed."""
    error: Optional[PaintReliefError]
    """The job's failure (an InputError, OutputError, ParameterError or PaintReliefError), its message one
    sentence; None when it was painted or kept."""

    @property
    def ok(self) -> bool:
        """Whether the job's folder holds its painting."""
        return self.error is None


def core_count() -> int:
    """The cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:                      # not on Linux
        return os.cpu_count() or 1


def paint_objects(jobs, progress: ProgressFn = None, cancel: CancelFn = None, processes: Optional[int] = None,
                  notice: Optional[Callable[[str], None]] = None, farm=None) -> List[ObjectOutcome]:
    """Paint every job of ``jobs``, side by side on the machine's cores; return an ``ObjectOutcome`` per job, in
    order.

    jobs: dicts of ``core.paint_object``'s keyword arguments (``jobs.ARGUMENTS``: texture_path, mesh (a
    ``SurfaceMesh`` or an OBJ path), output_dir and params at least), each painted as ``paint_object`` paints it
    alone, the same bytes, into its own folder (two jobs naming one folder: the second fails). A job whose folder
    holds its painting already (``kept_report``: the same sources' bytes, mesh arrays, parameters, texture size,
    stroke widths, normal map, extensions, by this version) is kept, not painted. One job's failure (a bad input,
    a job that is not one) is its outcome's one-sentence error, and the others are painted.
    processes: how many jobs are painted at once, each in a worker process of its own (``worker``) with the
    cores shared out as its threads (None: one per core; never more than the jobs to paint, nor than the memory
    available holds). With one, or one job to paint, or no Python to start (``python_program``), the jobs are
    painted one after another in this process, and ``notice`` (when given) hears why when it is the last.
    progress(fraction, message): the fraction of all jobs done (a job's own progress counted in), the message
    the one of the job that spoke, "Object k/N: ...". cancel(): when it returns True every worker stops (each
    unfinished folder stays as it was) and Cancelled is raised; the jobs painted stay painted.
    farm: a ``core.farm.cluster.Farm`` (local workers or a scheduler's address) to paint the jobs not kept on a Dask
    cluster instead, each as one task (``farm.objects``), with the same bytes; ``processes`` is then not used, and
    the progress is spoken as each job is done, "Object k/N: painted (2 workers)". Its workers must read the
    sources and write the folders at the same paths (one sentence naming the worker and the path); a lost
    scheduler is a FarmError. No cluster is reached when every job is kept or failed its checks.
    ParameterError in one sentence for no jobs or a wrong ``processes``; the temporary folder handing the
    jobs over is removed whatever happens.
    """
    from ..api import paint_object

    if not isinstance(jobs, (list, tuple)) or not jobs:
        raise ParameterError("Give at least one object to paint, as a list of paint_object's arguments.")
    if processes is not None and (isinstance(processes, bool) or not isinstance(processes, int) or processes < 1):
        raise ParameterError(f"The number of processes must be a whole number from 1, got {processes!r}.")
    total = len(jobs)
    outcomes: List[Optional[ObjectOutcome]] = [None] * total
    checked: Dict[int, dict] = {}
    folders: Dict[str, int] = {}
    for k, job in enumerate(jobs):
        try:
            checked[k] = checked_job(job, k + 1)
            folder = str(Path(checked[k]["output_dir"]).resolve())
            if folder in folders:
                raise ParameterError(f"Object {k + 1} would be painted into {folder}, as object "
                                     f"{folders[folder] + 1} is.")
            folders[folder] = k
        except PaintReliefError as exc:
            outcomes[k] = ObjectOutcome(None, exc)
            checked.pop(k, None)
    for k, job in checked.items():
        found = kept_report(job)
        if found is not None:
            outcomes[k] = ObjectOutcome(dict(found, output_dir=str(Path(job["output_dir"]).resolve()), batch=KEPT),
                                        None)
    todo = [k for k in range(total) if outcomes[k] is None]
    shares = [0.0 if outcome is None else 1.0 for outcome in outcomes]
    speak = Progress(progress, shares)
    for k in range(total):
        if outcomes[k] is not None:
            speak(k, 1.0, "kept, painted before" if outcomes[k].ok else "not painted")
    if farm is not None and todo:
        on_farm(farm, checked, todo, outcomes, speak, cancel)
        return outcomes
    count = min(processes or core_count(), len(todo), memory_bound([checked[k] for k in todo]))
    python = python_program()
    if count > 1 and python is None and notice is not None:
        notice(f"The objects are painted one after another: {sys.executable} is no Python interpreter to paint "
               f"them side by side with.")
    if count > 1 and python is not None:
        in_processes(python, checked, todo, count, outcomes, speak, cancel)
    else:
        for k in todo:
            if cancel is not None and cancel():
                raise cancelled(outcomes)
            try:
                report = paint_object(**checked[k], progress=lambda f, m, k=k: speak(k, f, m), cancel=cancel)
            except Cancelled:
                raise cancelled(outcomes) from None
            except PaintReliefError as exc:
                outcomes[k] = ObjectOutcome(None, exc)
            else:
                outcomes[k] = ObjectOutcome(dict(report, batch=PAINTED), None)
            speak(k, 1.0, "painted" if outcomes[k].ok else "not painted")
    return outcomes


def on_farm(farm, jobs: Dict[int, dict], todo: List[int], outcomes: list, speak: "Progress",
            cancel: CancelFn) -> None:
    """Paint the jobs ``todo`` (indices into ``jobs``) on the Dask cluster of ``farm``, one task each
    (``farm.objects.paint_objects_on``), setting their ``outcomes``; Cancelled when ``cancel()`` says so.

    The tasks are sent by the package ``core`` of its own (``top_level``), as the workers import it: held inside
    another package (the extension's inside Blender), whose name no worker imports, the jobs, the farm and the
    outcomes are carried over between the two by value."""
    twin = top_level()
    if twin is sys.modules[__name__]:
        return farm_jobs(farm, jobs, todo, outcomes, speak, cancel)
    from ..params import Params
    from ..surface.mesh import SurfaceMesh

    params, mesh, cluster = (importlib.import_module(f"core.{name}") for name in ("params", "surface.mesh",
                                                                                 "farm.cluster"))
    theirs = {k: dict(job, params=params.Params(**{name: getattr(job["params"], name)
                                                    for name in Params.__dataclass_fields__}),
                      mesh=mesh.SurfaceMesh(*job["mesh"]) if isinstance(job["mesh"], SurfaceMesh) else job["mesh"])
              for k, job in jobs.items() if k in todo}
    their_outcomes = [None] * len(outcomes)
    try:
        twin.farm_jobs(cluster.Farm(*farm), theirs, todo, their_outcomes, speak, cancel)
    except Exception as exc:
        raise own_error(exc) from None
    finally:
        for k, outcome in enumerate(their_outcomes):
            if outcome is not None:
                outcomes[k] = ObjectOutcome(outcome.report, outcome.error and own_error(outcome.error))


def farm_jobs(farm, jobs: Dict[int, dict], todo: List[int], outcomes: list, speak: "Progress",
              cancel: CancelFn) -> None:
    """``on_farm``'s painting, by this package."""
    from ..api import connected_farm, paint_object
    from ..farm.cluster import describe
    from ..farm.objects import paint_objects_on

    with connected_farm(farm) as client:
        where = describe(client)

        def finished(k: int, report: Optional[dict], error: Optional[PaintReliefError]) -> None:
            outcomes[k] = ObjectOutcome(None, error) if error is not None else ObjectOutcome(
                dict(report, batch=PAINTED), None)
            speak(k, 1.0, f"painted ({where})" if error is None else f"not painted ({where})")

        try:
            paint_objects_on(client, paint_object, {k: jobs[k] for k in todo}, finished, cancel)
        except Cancelled:
            raise cancelled(outcomes) from None


def top_level():
    """This module as the package ``core`` of its own imports it, ``ROOT`` on the path (so its tasks name what a
    Dask worker imports): itself when ``core`` is that package. ParameterError (one sentence) when another
    package named ``core`` is found first."""
    if __name__ == "core.objects.side_by_side":
        return sys.modules[__name__]
    if str(ROOT) not in sys.path:
        sys.path.append(str(ROOT))
    twin = importlib.import_module("core.objects.side_by_side")
    if Path(twin.__file__).resolve() != Path(__file__).resolve():
        raise ParameterError(f"The objects cannot be painted on a farm from here: the package core imported is "
                             f"{Path(twin.__file__).parents[1]}, not the painter's {ROOT / 'core'}.")
    return twin


def own_error(exc: BaseException) -> BaseException:
    """An error of the package ``core`` of its own (``top_level``) as this package's class of the same name (a
    PaintReliefError when there is none); any other exception as it is."""
    from ..farm import cluster

    if not type(exc).__module__.startswith("core."):
        return exc
    kind = getattr(errors, type(exc).__name__, None) or getattr(cluster, type(exc).__name__, None)
    if not (isinstance(kind, type) and issubclass(kind, PaintReliefError)):
        kind = PaintReliefError
    return kind(str(exc))


class Progress:
    """The batch's progress: ``shares[k]`` in [0, 1], job k's own fraction done; each call sets one and reports
    their mean with the job's message."""

    def __init__(self, progress: ProgressFn, shares: List[float]):
        self.progress = progress
        self.shares = shares

    def __call__(self, k: int, fraction: float, message: str) -> None:
        self.shares[k] = min(max(float(fraction), 0.0), 1.0)
        if self.progress is not None:
            self.progress(sum(self.shares) / len(self.shares), f"Object {k + 1}/{len(self.shares)}: {message}")


def cancelled(outcomes) -> Cancelled:
    """The Cancelled of a batch stopped with ``outcomes`` (None for a job not done)."""
    painted = sum(1 for outcome in outcomes if outcome is not None and outcome.ok)
    return Cancelled(f"Painting the objects was cancelled; the {painted} painted stay in their folders and the "
                     f"others are as they were.")


def kept_report(job: dict) -> Optional[dict]:
    """The report.json in the checked ``job``'s folder when the folder holds the job's painting whole (every file
    the report lists there with its size), painted by this version from the same inputs (its "inputs_sha256",
    ``surface.fingerprint``) with the same parameters; else None (nothing readable, another painting, or inputs
    ``paint_object`` would refuse)."""
    from ..files.shot_files import read_report
    from ..surface.fingerprint import job_inputs_sha256

    try:
        digest = job_inputs_sha256(job["texture_path"], job["mesh"], job.get("texture_size"), job.get("stroke_mm"),
                                   bool(job.get("normal_map", False)), bool(job.get("keep_source", False)),
                                   bool(job.get("across_seams", True)), job.get("extensions"))
        report = read_report(job["output_dir"])
        if (report is None or report.get("inputs_sha256") != digest
                or report.get("params") != json.loads(json.dumps(job["params"].to_dict()))
                or not isinstance(report.get("files"), dict)):
            return None
        for name, entry in report["files"].items():
            path = Path(job["output_dir"]) / name
            if Path(name).name != name or not path.is_file() or path.stat().st_size != entry["bytes"]:
                return None
    except (PaintReliefError, OSError, ValueError, TypeError, KeyError):
        return None
    return report


def memory_bound(jobs: List[dict]) -> int:
    """How many of ``jobs`` can be painted at once in the memory available: the available bytes over the largest
    job's estimate (``files.budget.estimate_bytes`` of its texture), at least 1; no bound when either is
    unknown."""
    from ..files import budget

    available = budget.available_bytes()
    largest = max((budget.estimate_bytes(side, side, job["params"].layers) for job in jobs
                   for side in [texture_side(job)] if side), default=0)
    if available is None or largest <= 0:
        return max(1, len(jobs))
    return max(1, int(available // largest))


def texture_side(job: dict) -> int:
    """A job's texture side in texels: its texture size, else its first source's longest side; 0 when unknown."""
    from ..files import reading

    if isinstance(job.get("texture_size"), int):
        return int(job["texture_size"])
    texture = job["texture_path"]
    first = texture[0] if isinstance(texture, (list, tuple)) and texture else texture
    try:
        width, height, _ = reading.probe(first, job["params"].max_megapixels)
    except (PaintReliefError, OSError, TypeError, ValueError):
        return 0
    return max(width, height)


def python_program() -> Optional[str]:
    """The Python interpreter to start workers with: ``sys.executable`` (inside Blender 2.91 and later its bundled
    Python, with the bpy module the venv's), None when that is no file or is a Blender program."""
    program = sys.executable
    if not program or not os.path.isfile(program) or Path(program).name.lower().startswith("blender"):
        return None
    return program


def worker_environment() -> dict:
    """The environment of a worker: this one, with this process's path on PYTHONPATH after ``ROOT`` (so it
    imports ``core`` as a package of its own and finds the wheels this process finds)."""
    environment = dict(os.environ)
    paths = []
    for entry in [str(ROOT)] + [str(p) for p in sys.path if p]:
        if entry not in paths:
            paths.append(entry)
    environment["PYTHONPATH"] = os.pathsep.join(paths)
    return environment


class Worker:
    """A running worker process (``worker``), the job it paints (None: idle) and the thread reading what it says
    into ``events``: (worker, job, fraction, message) for progress, (worker, job, None, DONE_TAG) when the job's
    result is written, (worker, None, None, None) at its end."""

    def __init__(self, python: str, folder: Path, number: int, threads: int, events: queue.Queue):
        self.job: Optional[int] = None
        self.error_path = folder / f"worker{number}.stderr"
        self.error_log = open(self.error_path, "wb")
        self.process = subprocess.Popen(
            [python, "-m", "core.objects.worker", str(folder), str(threads)], cwd=str(ROOT),
            env=worker_environment(), stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=self.error_log,
            encoding="utf-8", errors="replace", start_new_session=os.name == "posix",
            creationflags=getattr(subprocess, "CREATE_NO_WINDOW", 0))
        self.reader = threading.Thread(target=self.read, args=(events,), daemon=True)
        self.reader.start()

    def read(self, events: queue.Queue) -> None:
        """Put what the worker says on ``events`` (class docstring)."""
        for line in self.process.stdout:
            words = line.split(" ", 2)
            try:
                if words[0] == PROGRESS_TAG and len(words) == 3:
                    fraction, message = json.loads(words[2])
                    events.put((self, int(words[1]), float(fraction), str(message)))
                elif words[0] == DONE_TAG and len(words) == 2:
                    events.put((self, int(words[1]), None, DONE_TAG))
            except (ValueError, TypeError):
                continue
        events.put((self, None, None, None))

    def paint(self, k: int) -> bool:
        """Hand job ``k`` to the worker; False when it cannot take it (it has ended)."""
        self.job = k
        try:
            self.process.stdin.write(f"paint {k}\n")
            self.process.stdin.flush()
        except (OSError, ValueError):
            return False
        return True

    def finish(self) -> None:
        """Tell the worker that no job follows (it ends after the one it paints)."""
        try:
            self.process.stdin.close()
        except OSError:
            pass

    def last_words(self) -> str:
        """The last line the worker wrote on stderr, '' for none."""
        lines = self.error_path.read_text(encoding="utf-8", errors="replace").strip().splitlines()
        return lines[-1].strip().rstrip(".") if lines else ""

    def close(self) -> None:
        """Wait for the process's end (it has ended or been killed) and close its streams."""
        self.finish()
        self.process.wait()
        self.reader.join()
        self.process.stdout.close()
        self.error_log.close()


def in_processes(python: str, jobs: Dict[int, dict], todo: List[int], count: int, outcomes: list,
                 speak: Progress, cancel: CancelFn) -> None:
    """Paint the jobs ``todo`` (indices into ``jobs``) in ``count`` worker processes, each taking the next job
    when it is done, the largest textures first, setting their ``outcomes``; Cancelled when ``cancel()`` says so
    (module docstring). A worker that ends without a job's result fails that job and is replaced while jobs
    wait."""
    threads = max(1, min(tuning.MAX_WORKERS, core_count() // count))
    with tempfile.TemporaryDirectory(prefix="paint-relief-objects-", ignore_cleanup_errors=True) as name:
        folder = Path(name)
        pending = []
        for k in sorted(todo, key=lambda k: -texture_side(jobs[k])):
            try:
                write_job(folder, k, jobs[k])
                pending.append(k)
            except PaintReliefError as exc:
                outcomes[k] = ObjectOutcome(None, exc)
                speak(k, 1.0, "not painted")
            except OSError as exc:
                raise errors.OutputError(f"Cannot hand the objects over to worker processes in {folder}: "
                                         f"{errors.plain_cause(exc, folder)}.") from None
        events: queue.Queue = queue.Queue()
        workers: List[Worker] = []
        started = 0
        try:
            while pending or any(worker.job is not None for worker in workers):
                while len(workers) < count and sum(worker.job is None for worker in workers) < len(pending):
                    workers.append(Worker(python, folder, started, threads, events))
                    started += 1
                for worker in workers:
                    if worker.job is None and pending:
                        worker.paint(pending.pop(0))
                try:
                    event = events.get(timeout=WAIT_SECONDS)
                    while True:
                        handle(event, folder, jobs, workers, outcomes, speak)
                        event = events.get_nowait()
                except queue.Empty:
                    pass
                if cancel is not None and cancel():
                    raise cancelled(outcomes)
        finally:
            stop(folder, workers)


def handle(event: tuple, folder: Path, jobs: Dict[int, dict], workers: List["Worker"], outcomes: list,
           speak: Progress) -> None:
    """Take one event of a worker (``Worker``): its progress spoken, a job's result read into ``outcomes``, or
    its end, which fails the job it painted and takes it out of ``workers``."""
    worker, k, fraction, message = event
    if fraction is not None:
        speak(k, fraction, message)
    elif message == DONE_TAG:
        outcomes[k] = worker_outcome(folder, k)
        worker.job = None
        speak(k, 1.0, "painted" if outcomes[k].ok else "not painted")
    else:
        workers.remove(worker)
        worker.close()
        if worker.job is not None:
            said = worker.last_words()
            outcomes[worker.job] = ObjectOutcome(None, PaintReliefError(
                f"Painting object {worker.job + 1} into {jobs[worker.job]['output_dir']} ended without a result"
                f"{', its last words: ' + said if said else ''}."))
            speak(worker.job, 1.0, "not painted")


def stop(folder: Path, workers: List[Worker]) -> None:
    """Tell ``workers`` that no job follows, ask those painting to stop (``worker.STOP_FILE``), give them
    ``STOP_SECONDS`` together, kill those still running, and wait for all."""
    if any(worker.job is not None for worker in workers):
        (folder / STOP_FILE).touch()
    for worker in workers:
        worker.finish()
    deadline = time.monotonic() + STOP_SECONDS
    for worker in workers:
        try:
            worker.process.wait(timeout=max(0.0, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            worker.process.kill()
        worker.close()


def worker_outcome(folder: Path, k: int) -> ObjectOutcome:
    """Job ``k``'s outcome from the result its worker wrote into ``folder``."""
    result = json.loads((folder / result_name(k)).read_text(encoding="utf-8"))
    if "report" in result:
        return ObjectOutcome(dict(result["report"], batch=PAINTED), None)
    kind = getattr(errors, result["error"]["kind"], PaintReliefError)
    if not (isinstance(kind, type) and issubclass(kind, PaintReliefError)):
        kind = PaintReliefError
    return ObjectOutcome(None, kind(result["error"]["message"]))
