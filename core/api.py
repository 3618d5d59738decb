"""The one function callers outside the painter use: paint a file into a folder."""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import threading
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Callable, Optional

from .errors import InputError, OutputError, PaintReliefError, ParameterError
from .files import budget, reading
from .files.staging import output_folder
from .params import TEXTURE_SIZE_RANGE, Params, SequenceSettings
from .progress import CancelFn, ProgressFn, Stage


def check_input(input_path, params: Params, mask_path: Optional[str] = None,
                max_memory: Optional[int] = None) -> tuple:
    """Everything that can be refused before work, from headers only (well under a second); returns (width, height).

    The parameters' ranges, the input's and the mask's headers (readable,
    not empty, within ``params.max_megapixels``, not a decompression bomb),
    stroke sizes against the image, and the memory estimate against
    ``max_memory`` bytes (default: the memory available). Raises a
    PaintReliefError with one sentence.
    """
    params.validate()
    width, height, _ = reading.probe(input_path, params.max_megapixels)
    budget.check_bomb(input_path, width, height)
    if mask_path:
        mask_w, mask_h, _ = reading.probe(mask_path, params.max_megapixels, role="mask")
        budget.check_bomb(mask_path, mask_w, mask_h)
    budget.check_stroke_sizes(params, height, width)
    budget.check(input_path, width, height, params.layers, mask=bool(mask_path), max_memory=max_memory)
    return width, height


def paint_file(input_path, output_dir, params: Params, progress: ProgressFn = None, cancel: CancelFn = None,
               mask_path: Optional[str] = None, max_memory: Optional[int] = None, normal_map: bool = False,
               notice: Optional[Callable[[str], None]] = None, strokes_to_lay: bool = False,
               timelapse: int = 0) -> dict:
    """Read ``input_path``, paint it and write every output into ``output_dir``; return the report.

    Checks everything it can from headers first (``check_input``, and the
    free space of ``output_dir``'s file system against the painting's size),
    then locks ``output_dir`` (one writer per folder), checks that nothing
    stands where an output must go, and paints. An input holding several
    images (a multi-page TIFF, a multi-part EXR, an animated PNG or GIF) is
    painted from its first: ``notice`` (when given) receives one sentence
    saying so, and report.json records ``input_page`` (0) and
    ``input_pages``. Outputs are
    committed all together or not at all (see ``staging``); a failure raises
    a PaintReliefError whose message is one sentence naming the file and the
    problem, and leaves ``output_dir`` as it was (a folder this call created
    is removed again). Running out of memory is reported the same way.
    With ``normal_map`` normal.exr is written too (``export.write_painting``). report.json records the input
    file's SHA-256 ("input_sha256", read before the image), by which ``paint_batch`` knows the painting again.
    With ``strokes_to_lay``, strokes.json also records what laying each stroke again needs (``lay_file``).
    timelapse: 0 for none, else the frames (1 to ``files.timelapse.MAX_FRAMES``, ParameterError in one sentence
    otherwise) of the painting being painted, written as a painted shot into OUTDIR/timelapse/ and committed
    with the painting (``painting_timelapse``); report.json records it under "timelapse".
    """
    from .files.export import NORMAL_FILE, PAINTING_FILES, input_sha256, write_painting
    from .files.timelapse import FRAME_BYTES_PER_PIXEL, TIMELAPSE_DIR, check_frames
    from .methods.registry import paint

    if timelapse:
        check_frames(timelapse)
    width, height = check_input(input_path, params, mask_path, max_memory)
    budget.check_space(output_dir, input_path, width, height, normal_map, timelapse * FRAME_BYTES_PER_PIXEL)
    pages = reading.image_count(input_path)
    digest = input_sha256(input_path)
    if pages > 1 and notice is not None:
        notice(pages_notice(input_path, pages))

    def painted():
        image = reading.read_image(input_path, params.max_megapixels, params.canvas_colour)
        mask = reading.read_gray(mask_path, params.max_megapixels, role="mask") if mask_path else None
        if timelapse:
            from .strokes.snapshots import Snapshots

            caught["snapshots"] = Snapshots(image.shape[:2], timelapse)
        return paint(image, params, progress=progress, cancel=cancel, mask=mask, record_strokes=strokes_to_lay,
                     snapshots=caught.get("snapshots"))

    def written(staging: Path, painting) -> dict:
        if not timelapse:
            return write_painting(staging, painting, str(input_path), normal_map, pages=pages, source_sha256=digest)
        stopped = threading.Event()             # the painting's files failed: the time-lapse stops too
        with ThreadPoolExecutor(1) as pool:     # the time-lapse written while the painting's own files are
            lapse = pool.submit(painting_timelapse, staging, painting, caught["snapshots"], str(input_path),
                                Stage(progress, lambda: stopped.is_set() or bool(cancel is not None and cancel())))
            try:
                return write_painting(staging, painting, str(input_path), normal_map, pages=pages,
                                      source_sha256=digest, more=lambda: {"timelapse": lapse.result()})
            finally:
                stopped.set()

    caught: dict = {}
    return committed_painting(output_dir, input_path, PAINTING_FILES + ((NORMAL_FILE,) if normal_map else ()),
                              painted, written, (TIMELAPSE_DIR,) if timelapse else ())


def painting_timelapse(staging: Path, painting, snapshots, source: str, stage: Optional[Stage] = None) -> dict:
    """Write the time-lapse of ``painting`` caught by ``snapshots`` (``strokes.snapshots.Snapshots``) into the
    staging folder's ``files.timelapse.TIMELAPSE_DIR``; return its summary (``files.timelapse.write_timelapse``,
    which reports to and polls ``stage``)."""
    from .files.export import map_attributes
    from .files.timelapse import TIMELAPSE_DIR, write_timelapse

    return write_timelapse(staging / TIMELAPSE_DIR, snapshots, (painting.colour, painting.height, painting.opacity),
                           painting.params.canvas_colour, painting.orientation, map_attributes(painting.params),
                           source, painting.params.to_dict(), stage)


def stroke_list_params(document: dict, path) -> Params:
    """The Params a strokes.json ``document`` (read from ``path``) records, validated; InputError in one sentence
    naming the file when it records none or ones this version cannot take."""
    import dataclasses

    recorded = document.get("params")
    names = {f.name for f in dataclasses.fields(Params)}
    if not isinstance(recorded, dict) or not set(recorded) <= names:
        raise InputError(f"The stroke list {path} does not record the painting's parameters as this version "
                         f"takes them.")
    try:
        return Params(**{k: tuple(v) if isinstance(v, list) else v for k, v in recorded.items()}).validate()
    except (TypeError, ParameterError) as exc:
        raise InputError(f"The stroke list {path} records parameters this version refuses: "
                         f"{str(exc).rstrip('.')}.") from None


def lay_file(strokes_path, reference_path, output_dir, progress: ProgressFn = None,
             normal_map: bool = False, cancel: CancelFn = None) -> dict:
    """Lay the stroke list ``strokes_path`` (a strokes.json of format 2) on a blank canvas, against the photograph
    ``reference_path`` it was painted from, and write the files ``paint_file`` writes into ``output_dir``; return
    the report.

    The painting's parameters and size are the list's own ("params", "width", "height"). A list that cannot be
    read or laid (not strict JSON, not a stroke list, another format, a stroke without laying data or whose data
    do not fit its brush) and a reference of another size than the list's are refused in one sentence naming the
    file, before anything is written; the outputs are committed all together or not at all, as ``paint_file``'s.
    progress(fraction, message) hears the analysis and the strokes laid, after each chunk of them; cancel() is
    polled as often, and when it returns True, Cancelled leaves ``output_dir`` as it was.
    """
    from .files.stroke_file import read_stroke_file

    path = Path(strokes_path)
    return lay_document(read_stroke_file(path), path, reference_path, output_dir, progress, normal_map, cancel)


def lay_document(document: dict, path: Path, reference_path, output_dir, progress: ProgressFn = None,
                 normal_map: bool = False, cancel: CancelFn = None) -> dict:
    """``lay_file`` of a stroke list ``document`` already read (``read_stroke_file``) from ``path``, the file its
    sentences name."""
    from .files.export import NORMAL_FILE, PAINTING_FILES, input_sha256, write_painting
    from .files.stroke_file import FORMAT
    from .methods.laying import lay_painting
    from .strokes.stroke_file_list import strokes_from_document

    if document.get("format", 1) != FORMAT:
        raise InputError(f"The stroke list {path} is of format {document.get('format', 1)}, which holds no laying "
                         f"data: paint the photograph again to get a list of format {FORMAT}.")
    params = stroke_list_params(document, path)
    size = document.get("width"), document.get("height")
    if not all(isinstance(v, int) and not isinstance(v, bool) and v > 0 for v in size):
        raise InputError(f"The stroke list {path} does not record the painting's width and height.")
    width, height, _ = reading.probe(reference_path, params.max_megapixels)
    if (width, height) != size:
        raise InputError(f"The reference {reference_path} is {width} x {height} pixels, but the stroke list {path} "
                         f"was painted at {size[0]} x {size[1]}.")
    budget.check_bomb(reference_path, width, height)
    budget.check(reference_path, width, height, params.layers)
    budget.check_space(output_dir, reference_path, width, height, normal_map)
    strokes, records = strokes_from_document(document, path)
    pages = reading.image_count(reference_path)
    digest = input_sha256(reference_path)

    def painted():
        image = reading.read_image(reference_path, params.max_megapixels, params.canvas_colour)
        try:
            return lay_painting(image, strokes, records, params, progress=progress, cancel=cancel)
        except (ValueError, IndexError) as exc:
            raise InputError(f"The stroke list {path} cannot be laid: {str(exc).rstrip('.')}.") from None

    def written(staging: Path, painting) -> dict:
        return write_painting(staging, painting, str(reference_path), normal_map, pages=pages, source_sha256=digest)

    return committed_painting(output_dir, reference_path, PAINTING_FILES + ((NORMAL_FILE,) if normal_map else ()),
                              painted, written)


def drawn_strokes(painted_dir):
    """The strokes of PAINTED_DIR/strokes.json (format 1 or 2) as polylines (``core.strokes.drawn.DrawnStrokes``,
    one per stroke in painting order, index i for stroke i): what a Grease Pencil object of the painting holds.
    InputError in one sentence naming the file when the folder has no stroke list this version reads or
    nothing says the painting's size."""
    from .files.stroke_file import STROKES_FILE, painting_size, read_stroke_file
    from .strokes.drawn import drawn_from_document

    folder = Path(painted_dir)
    path = folder / STROKES_FILE
    if not path.is_file():
        raise InputError(f"{path} does not exist: give a folder painted by Paint Relief.")
    document = read_stroke_file(path)
    size = painting_size(document, folder)
    if size is None:
        raise InputError(f"The stroke list {path} does not say the painting's size, nor does a report.json "
                         f"beside it.")
    return drawn_from_document(document, size)


def painted_reference(painted_dir) -> Path:
    """The photograph PAINTED_DIR was painted from, as its report.json names it; InputError in one sentence when
    it names none or the file is gone."""
    folder = Path(painted_dir)
    try:
        source = json.loads((folder / "report.json").read_text(encoding="utf-8")).get("input")
    except (OSError, ValueError, AttributeError):
        source = None
    if not isinstance(source, str) or not source:
        raise InputError(f"The painting {folder} does not name the photograph it was painted from (its report.json "
                         f"is missing or holds no input): give the photograph as the reference.")
    if not Path(source).is_file():
        raise InputError(f"The photograph {source} that {folder} was painted from is gone: give it as the "
                         f"reference.")
    return Path(source)


def lay_drawn(painted_dir, drawn, output_dir, reference_path=None, progress: ProgressFn = None,
              cancel: CancelFn = None) -> dict:
    """Lay ``drawn`` (``DrawnStrokes``: the painting's strokes as a drawing program holds them after editing, in
    laying order) into a new painting in ``output_dir``, as ``lay_file`` lays a list; return the report.

    The strokes kept from PAINTED_DIR's strokes.json (format 2, with laying data) keep their recorded laying
    data with their moves and colour changes applied, strokes drawn anew get the painting's brush
    (``core.strokes.redrawn``); the reference is ``reference_path``, else the photograph PAINTED_DIR's
    report.json names. One sentence naming the file for whatever cannot be read or laid, before anything is
    written; the outputs are committed all together or not at all. progress and cancel as ``lay_file``'s.
    """
    from .files.stroke_file import FORMAT, STROKES_FILE, read_stroke_file
    from .strokes.redrawn import redrawn_document

    folder = Path(painted_dir)
    path = folder / STROKES_FILE
    if not path.is_file():
        raise InputError(f"{path} does not exist: give a folder painted by Paint Relief.")
    document = read_stroke_file(path)
    if document.get("format", 1) != FORMAT:
        raise InputError(f"The stroke list {path} is of format {document.get('format', 1)}, which holds no laying "
                         f"data: paint the photograph again to get a list of format {FORMAT}.")
    params = stroke_list_params(document, path)
    if tuple(drawn.size) != (document.get("width"), document.get("height")):
        raise InputError(f"The drawn strokes are on a painting of {drawn.size[0]} x {drawn.size[1]} pixels, but the "
                         f"stroke list {path} was painted at {document.get('width')} x {document.get('height')}.")
    reference = Path(reference_path) if reference_path is not None else painted_reference(folder)
    try:
        edited = redrawn_document(document, drawn, params)
    except ValueError as exc:
        raise InputError(f"The stroke list {path} cannot be laid again: {str(exc).rstrip('.')}.") from None
    return lay_document(edited, path, reference, output_dir, progress, cancel=cancel)


def committed_painting(output_dir, input_path, names: tuple, painted: Callable[[], object],
                       written: Callable[[Path, object], dict], folders: tuple = ()) -> dict:
    """The skeleton every entry that paints into a folder shares (``paint_file``, ``paint_object``); returns the
    report with its "output_dir".

    Locks ``output_dir`` (one writer per folder, ``staging.output_folder``),
    refuses in one sentence anything standing where one of the file
    ``names`` must go, paints (``painted()`` -> Painting) and commits what
    ``written(staging folder, painting)`` writes there (it returns the
    report) all together or not at all. A MemoryError becomes the
    one-sentence ``out_of_memory`` naming ``input_path``. ``folders``: the
    names of folders ``written`` makes (a time-lapse), each replacing the
    folder of its name at the commit, refused in one sentence when a file
    stands there.
    """
    try:
        with output_folder(output_dir) as folder:
            folder.check_names(names)
            folder.check_folders(list(folders))
            painting = painted()
            with folder.staged() as staging:
                report = written(staging, painting)
    except MemoryError:
        raise out_of_memory(input_path) from None
    report["output_dir"] = str(Path(output_dir).resolve())
    return report


def paint_sequence_files(inputs, output_dir, params: Params, settings=None, frame_range: Optional[str] = None,
                         progress: ProgressFn = None, cancel: CancelFn = None, max_memory: Optional[int] = None,
                         farm=None, notice: Optional[Callable[[str], None]] = None) -> dict:
    """Paint the image sequence named by ``inputs`` into ``output_dir`` with strokes that live across frames;
    return the sequence's report (``core.sequence.shot.paint_sequence``).

    inputs: one folder, one ``#`` pattern or frame files in order (``files.frames.find_frames``; a single path
    may be given as it is, not in a list); frame_range:
    ``"A-B"`` or None for every frame; settings: a ``SequenceSettings`` (None for the defaults). The parameters
    (the paper's method and layout: ``Params.validate_shot``), the frames (``find_frames``), an output folder
    that would mix the shot's files with its frames (``check_output_folder``), the stroke sizes and the memory
    estimate of one frame are checked from names and headers before any work (a PaintReliefError of one
    sentence). Every frame is committed whole; stopped anywhere (an error, a signal,
    ``cancel``), the folder keeps complete frames only and the same call goes on after the last of them.
    farm: a ``core.farm.cluster.Farm`` (local workers or a scheduler's address) to paint the frames on a Dask
    cluster, with the same bytes; None paints in this process and imports no Dask. notice(sentence) hears what a
    resume repaired in the folder (``sequence.shot.paint_sequence``).
    """
    inputs = [str(path) for path in ([inputs] if isinstance(inputs, (str, os.PathLike)) else inputs)]
    frames = check_shot(inputs, output_dir, params, settings, frame_range, max_memory)
    with connected_farm(farm) as client:
        return painted_shot(frames, output_dir, params, settings, progress, cancel, client, notice)


def check_shot(inputs, output_dir, params: Params, settings: Optional[SequenceSettings] = None,
               frame_range: Optional[str] = None, max_memory: Optional[int] = None):
    """Everything about a shot that can be refused before work, from names and headers (``paint_sequence_files``
    says what; the output folder's own check left for later when ``output_dir`` is None); returns its
    ``files.frames.Frames``."""
    from .files.frames import check_output_folder, find_frames

    params.validate_shot()
    settings = (settings or SequenceSettings()).validate()
    frames = find_frames(inputs, frame_range, params.max_megapixels)
    if output_dir is not None:
        check_output_folder(inputs, frames, output_dir, settings.normal_map)
    budget.check_stroke_sizes(params, frames.height, frames.width)
    budget.check(frames.paths[0], frames.width, frames.height, params.layers, max_memory=max_memory)
    return frames


def painted_shot(frames, output_dir, params: Params, settings: Optional[SequenceSettings], progress: ProgressFn,
                 cancel: CancelFn, client=None, notice: Optional[Callable[[str], None]] = None, shared=None) -> dict:
    """The checked shot ``frames`` painted into ``output_dir`` (on ``client``'s Dask cluster when given, its threads
    ``shared`` with other shots painted at once when that is a ``farm.shared_threads.SharedThreads``); its report,
    with its "output_dir"."""
    from .sequence.shot import paint_sequence

    painter = None
    if client is not None:
        from .farm.sequence import ClusterFrames

        painter = ClusterFrames(client, shared)
    try:
        report = paint_sequence(frames, output_dir, params, settings or SequenceSettings(), progress=progress,
                                cancel=cancel, frames_painter=painter, notice=notice)
    except MemoryError:
        raise out_of_memory(frames.paths[0]) from None
    report["output_dir"] = str(Path(output_dir).resolve())
    return report


def is_shot(source) -> bool:
    """Whether a batch's input ``source`` is a shot (a folder of frames or a ``#`` pattern), not a still."""
    from .files.shot_files import is_pattern

    return os.path.isdir(source) or is_pattern(str(source))


KEPT, WENT_ON, PAINTED = "kept", "went on", "painted"
"""What ``paint_batch`` did with an input, its report's "batch": kept the folder an earlier run painted whole, went on
with a shot an earlier run left partly painted (or repaired it), or painted it (anew, or into a folder a stopped run
left unfinished)."""


def paint_batch(inputs, output_root, params: Params, normal_map: bool = False, progress: ProgressFn = None,
                cancel: CancelFn = None, max_memory: Optional[int] = None, farm=None,
                settings: Optional[SequenceSettings] = None, fresh: bool = False,
                notice: Optional[Callable[[str], None]] = None) -> list:
    """Paint each still image and each shot of ``inputs`` into a folder of its own under ``output_root``; return
    the reports in the inputs' order (each with its "output_dir", and its "batch": ``KEPT``, ``WENT_ON`` or
    ``PAINTED``; ``batch_counts`` counts them).

    A shot is an input that is a folder of frames or a ``#`` pattern (``is_shot``): it is painted as
    ``paint_sequence_files`` paints it alone (``settings``: its ``SequenceSettings``), with the same bytes. The
    folders are named as the panel names a painting's (``<stem>_001``, the first free counter; a shot's stem is
    ``shot_files.shot_name``), and no folder holding another painting is ever written into. Run again, the batch
    goes on where it stopped (``batch_folders``): an input whose folder holds its painting whole, from the same
    input file (its SHA-256) with the same settings, is kept as it is; a shot's folder of the same frames and
    settings is gone on with as ``paint_sequence_files`` goes on (a complete one is checked and kept); a folder a
    stopped run left unfinished is painted into; a changed input or setting is painted into the next free folder.
    With ``fresh`` every input is painted anew into the first free folder (``files.folders.painting_folders``).
    Every input is checked from its headers first (``check_input``, ``check_shot``): a bad file is refused in one
    sentence before any folder is looked at. Stills are painted by ``paint_file``, in this process one after
    another, or on a Dask cluster with ``farm`` (a ``core.farm.cluster.Farm``), with the same bytes; shots after
    them, one after another in one process, all at once on a cluster (``farm.batch.paint_shots``). The folders are
    chosen here, before anything is sent to a cluster. Stopped anywhere, the stills and the complete frames painted
    stay. notice(sentence) hears what a shot's resume repaired, and that a still painted in this process holds
    several images.
    """
    from .files.frames import check_output_folder

    if not inputs:
        raise ParameterError("Name at least one image to paint.")
    inputs = [str(source) for source in inputs]
    shots = [is_shot(source) for source in inputs]
    frames = {}
    for source, shot in zip(inputs, shots, strict=True):
        if shot:
            frames[source] = check_shot([source], None, params, settings, max_memory=max_memory)
        else:
            check_input(source, params, max_memory=max_memory)
    folders, found = batch_folders(inputs, shots, frames, output_root, params, normal_map, settings, fresh)
    for source, shot, folder in zip(inputs, shots, folders, strict=True):
        if shot:
            check_output_folder([source], frames[source], folder, (settings or SequenceSettings()).normal_map)
    reports: list = [None] * len(inputs)
    for k, report in found.items():
        if not shots[k]:
            reports[k] = dict(report, output_dir=str(Path(folders[k]).resolve()), batch=KEPT)
    stills = [k for k, shot in enumerate(shots) if not shot and reports[k] is None]
    with connected_farm(farm if stills or any(shots) else None) as client:  # no cluster when every still is kept
        if stills and client is not None:
            from .farm.batch import paint_stills

            Path(output_root).mkdir(parents=True, exist_ok=True)
            painted = paint_stills(client, paint_file, [(inputs[k], folders[k]) for k in stills], Path(output_root),
                                   params, normal_map, progress, cancel)
            for k, report in zip(stills, painted, strict=True):
                reports[k] = dict(report, batch=PAINTED)
        shot_indices = [k for k, shot in enumerate(shots) if shot]
        if len(shot_indices) > 1 and client is not None:
            from .farm.batch import paint_shots

            def paint_shot(j, shot_progress, shot_cancel, shared):
                k = shot_indices[j]
                return painted_shot(frames[inputs[k]], folders[k], params, settings,
                                    lambda fraction, message: shot_progress(fraction, f"Shot {k + 1}/{len(inputs)}: "
                                                                                      f"{message}"),
                                    shot_cancel, client, notice, shared=shared)

            start = len(stills) / len(inputs)
            painted = paint_shots(paint_shot, len(shot_indices), None if progress is None else (
                lambda fraction, message: progress(start + (1 - start) * fraction, message)), cancel)
            for k, report in zip(shot_indices, painted, strict=True):
                reports[k] = dict(report, batch=shot_done(found.get(k), report))
        for k, (source, folder) in enumerate(zip(inputs, folders, strict=True)):
            if reports[k] is not None:
                continue
            stage = Stage(progress, cancel, k / len(inputs), (k + 1) / len(inputs))
            kind = "Shot" if shots[k] else "Still"
            named = None if progress is None else (
                lambda fraction, message, k=k, stage=stage, kind=kind: stage.report(
                    fraction, f"{kind} {k + 1}/{len(inputs)}: {message}"))
            if shots[k]:
                report = painted_shot(frames[source], folder, params, settings, named, cancel, client, notice)
                reports[k] = dict(report, batch=shot_done(found.get(k), report))
            else:
                report = paint_file(source, folder, params, progress=named, cancel=cancel, normal_map=normal_map,
                                    notice=notice)
                reports[k] = dict(report, batch=PAINTED)
    return reports


def batch_counts(reports) -> dict:
    """{KEPT: n, WENT_ON: n, PAINTED: n} of ``paint_batch``'s reports."""
    counts = {KEPT: 0, WENT_ON: 0, PAINTED: 0}
    for report in reports:
        counts[report["batch"]] += 1
    return counts


def shot_done(found: Optional[dict], report: dict) -> str:
    """What painting a shot did (``KEPT``, ``WENT_ON`` or ``PAINTED``): ``found`` is the report its folder held
    before (None for a new or unfinished folder), ``report`` the one painting it returned."""
    if found is None:
        return PAINTED
    whole = len(found["per_frame"]) >= len(report["per_frame"]) and "repaired" not in report
    return KEPT if whole else WENT_ON


def batch_folders(inputs, shots, frames, output_root, params: Params, normal_map: bool,
                  settings: Optional[SequenceSettings], fresh: bool):
    """(folders, found) of ``paint_batch``: each input's folder under ``output_root``, and {index: the report its
    folder holds} for the inputs whose folder holds their painting (a still's whole, a shot's whole or in part).

    ``fresh``: the first free folders (``files.folders.painting_folders``), none found. Else
    ``files.folders.resumed_folders``, ``still_report`` and ``shot_report`` judging which folder holds which
    input's painting; ``frames``: {shot input: its checked ``Frames``}."""
    from .files.folders import painting_folders, resumed_folders
    from .files.shot_files import shot_name

    names = [f"{shot_name(source)}.shot" if shot else source  # an extension for folder_stem to take off
             for source, shot in zip(inputs, shots, strict=True)]
    if fresh:
        return painting_folders(str(output_root), names), {}
    digests: dict = {}
    runs: dict = {}

    def owns(k: int, folder: str) -> Optional[dict]:
        source = inputs[k]
        if shots[k]:
            if source not in runs:
                from .sequence.shot import Run, shot_settings

                shot = (settings or SequenceSettings()).validate()
                runs[source] = Run(frames[source], shot_settings(frames[source], params, shot))
            return shot_report(runs[source], folder)
        if source not in digests:
            from .files.export import input_sha256

            digests[source] = input_sha256(source)
        return still_report(folder, digests[source], params, normal_map)

    chosen = resumed_folders(str(output_root), names, owns)
    return [folder for folder, _ in chosen], {k: report for k, (_, report) in enumerate(chosen) if report}


def still_report(folder, digest: str, params: Params, normal_map: bool) -> Optional[dict]:
    """The report.json of the still painting in ``folder`` when it is whole and was painted by this version from
    the input file of SHA-256 ``digest`` with ``params`` (seed included) and ``normal_map``; else None.

    Whole: every file its report lists is there with the size listed (a commit writes them all or none, so a
    file missing or of another size was changed since, and the folder is left as it is)."""
    from .files.export import NORMAL_FILE
    from .files.shot_files import is_shot_report, read_report
    from .version import __version__

    try:
        report = read_report(folder)
        if (report is None or is_shot_report(report) or report.get("input_sha256") != digest
                or report.get("version") != __version__
                or report.get("params") != json.loads(json.dumps(params.to_dict()))
                or not isinstance(report.get("files"), dict) or (NORMAL_FILE in report["files"]) != normal_map):
            return None
        for name, entry in report["files"].items():
            path = Path(folder) / name
            if Path(name).name != name or not path.is_file() or path.stat().st_size != entry["bytes"]:
                return None
    except (OSError, ValueError, TypeError, KeyError):
        return None
    return report


def shot_report(run, folder) -> Optional[dict]:
    """The report.json of the shot in ``folder`` when ``run`` (a ``sequence.shot.Run``) goes on from it as
    ``paint_sequence_files`` would: the same fingerprint (version, parameters, seed, fade, normal map, motion) and
    every frame committed painted from the same frame file; else None."""
    from .errors import OutputError
    from .files.shot_files import is_shot_report, read_report

    try:
        report = read_report(folder)
        if report is None or not is_shot_report(report):
            return None
        return run.resumed_report(Path(folder))
    except (OSError, ValueError, TypeError, KeyError, OutputError):
        return None


SOURCE_COPY = "source"
"""The name (before the source's own suffix) of the copy of a texture's source that ``paint_object`` keeps."""


def paint_object(texture_path, mesh, output_dir, params: Params, texture_size: Optional[int] = None,
                 stroke_mm=None, progress: ProgressFn = None, cancel: CancelFn = None,
                 max_memory: Optional[int] = None, normal_map: bool = False, keep_source: bool = False,
                 across_seams: bool = True, extensions=None) -> dict:
    """Paint the texture ``texture_path`` of ``mesh`` in its UV space (ALGORITHM §10) and write every output into
    ``output_dir``, as ``paint_file`` writes a still's; return the report.

    texture_path: a path, or a list of paths whose k-th is the source of the triangles whose source is k
    (``SurfaceMesh.source``). A path holding ``<UDIM>`` is a tiled image (``surface.atlas``): each tile the mesh
    uses is read from the path with its number there, and a missing one is refused in one sentence naming it. A
    plain source shows beyond the UV square 0..1 what its rule in ``extensions`` says. Each (source, tile) used is a cell of the painted texture, the
    atlas (``surface.atlas``), painted at once with strokes of one size on the surface.
    mesh: a ``core.surface.mesh.SurfaceMesh`` (Blender's loop triangles) or the path of a Wavefront OBJ file.
    texture_size: each cell's side in texels (default: the sources' longest side, within
    ``TEXTURE_SIZE_RANGE``); each source is resampled to that square. The atlas of G x G cells is G times as wide,
    at most ``TEXTURE_SIZE_RANGE``'s largest (the default shrinks to fit, a size given is refused in one sentence).
    stroke_mm: the stroke widths in mm on the surface (default:
    ``texture.default_stroke_mm``). The maps are the atlas's (one cell: the texture's); report.json adds "islands"
    (each island's texel density and stroke widths in mm), "stroke_mm", "bleed_texels" and "atlas"
    (``surface.atlas.atlas_figures``: the grid, each cell's source, tile, place and map files). With several cells
    each cell's maps are written too, color.s{k}.exr, height.s{k}.exr, opacity.s{k}.exr (and normal.s{k}.exr with
    ``normal_map``) for a plain source k, color.s{k}.{tile}.exr and the like for a tiled one, so each source's
    maps fit its own UV map. keep_source: a copy of the source is
    committed with the maps as ``SOURCE_COPY`` plus its suffix, and the report's "input" names that copy (for a
    source that lives only as long as the caller's temporary folder); with several cells, and whenever
    ``texture_path`` is a list of several, the composed atlas source is written as source.png and named instead.
    Checks, locking, all-or-nothing and
    one-sentence failures as ``paint_file`` (``committed_painting``). The texture is painted with the paper's
    method and layout, whose strokes are laid on each island's texels alone: any other is refused in one sentence
    before any work (``Params.validate_object``), and report.json names the "method" painted.
    across_seams: strokes run on across the UV seams (``surface.apron``), the borders between cells included
    where the surface runs on (the default); False paints each island apart, its strokes stopping at its
    borders. Across the seams, an island's canvas spans at most ``surface.apron.APRON_AREA`` (1.2) times its box
    painted apart (the apron reaches less far for an island whose strokes are wide against it), so painting
    across costs about as much as apart (bench/seam_cost.py: about 1.0 to 1.2 times the processor seconds) and
    a source that runs on over the surface steps across the seams about as it does (docs/objects.md).
    extensions: one rule per source for UVs beyond the square 0..1, as Blender's Image Texture node's
    ``extension`` (``surface.atlas.EXTENSIONS``): "REPEAT" (a face in another unit square is painted where the
    repeated image shows it), "MIRROR" (alike, mirrored in every other square), "CLIP" or "EXTEND" (only the
    faces' parts inside 0..1 are painted); one string for all, None for all "REPEAT", ignored for a tiled source.
    A mesh none of whose faces then covers a texel is refused in one sentence. report.json's "atlas" gives each
    cell's "extension", and "inputs_sha256" the digest of everything but ``params`` the painting was made from
    (``surface.fingerprint``), by which ``paint_objects`` knows the painting again.
    """
    from .files.export import NORMAL_FILE, PAINTING_FILES, cell_map_names, write_cell_maps, write_painting
    from .files.writing import write_png
    from .surface.atlas import (
        atlas_figures,
        build_atlas,
        cell_box,
        cell_file_suffix,
        checked_extensions,
        composed,
        is_tiled,
        tile_path,
    )
    from .surface.fingerprint import inputs_sha256
    from .surface.mesh import SurfaceMesh, check_mesh, read_obj
    from .surface.texture import paint_texture, square_texture, surface_layout

    params.validate_object()
    listed = isinstance(texture_path, (list, tuple))
    paths = list(texture_path) if listed else [texture_path]
    if not paths:
        raise ParameterError("No texture was given to paint the mesh from.")
    low, high = TEXTURE_SIZE_RANGE
    if texture_size is not None and not (isinstance(texture_size, int) and not isinstance(texture_size, bool)
                                         and low <= texture_size <= high):
        raise ParameterError(f"The texture size must be a whole number of texels from {low} to {high}, "
                             f"got {texture_size}.")
    if stroke_mm is not None and not (len(stroke_mm) and all(0 < float(w) < 1e6 for w in stroke_mm)):
        raise ParameterError(f"Stroke widths must be positive millimetres, got {list(stroke_mm)}.")
    rules = checked_extensions(extensions, len(paths))
    surface = (check_mesh(mesh, "given") if isinstance(mesh, SurfaceMesh) else read_obj(mesh))
    if surface.source is not None and int(surface.source.max()) >= len(paths):
        raise InputError(f"A face of the mesh is painted from source {int(surface.source.max())}, but only "
                         f"{len(paths)} texture{'s were' if len(paths) > 1 else ' was'} given.")
    tiled = [is_tiled(path) for path in paths]
    atlas = build_atlas(surface.uv, surface.source, tiled, rules)
    files = [tile_path(paths[cell.source], cell.tile) for cell in atlas.cells]
    for cell, file in zip(atlas.cells, files, strict=True):
        if cell.tile is not None and not Path(file).is_file():
            raise InputError(f"The UDIM tile {file} that the mesh's UV map uses does not exist.")
    sides = []
    for file in files:
        width, height, _ = reading.probe(file, params.max_megapixels)
        budget.check_bomb(file, width, height)
        sides.append(max(width, height))
    side = atlas.columns
    if texture_size is None:
        size = min(max(max(sides), low), high // side)
    elif texture_size * side > high:
        raise ParameterError(f"The atlas of {side} x {side} cells of {texture_size} texels would be "
                             f"{texture_size * side} texels wide, above the largest texture of {high}: give a "
                             f"texture size of at most {high // side}.")
    else:
        size = texture_size
    full = size * side
    several = len(atlas.cells) > 1
    digest = inputs_sha256(files, surface, listed, texture_size, stroke_mm, rules, normal_map, keep_source,
                           across_seams)
    budget.check(files[0], full, full, params.layers, max_memory=max_memory)
    budget.check_space(output_dir, files[0], full, 2 * full if several else full, normal_map)
    if several:
        copy = SOURCE_COPY + ".png" if keep_source or listed else None
    else:
        copy = SOURCE_COPY + Path(files[0]).suffix.lower() if keep_source else None
    cell_names = [cell_map_names(cell_file_suffix(cell), normal_map) if several else
                  dict({"color": "color.exr", "height": "height.exr", "opacity": "opacity.exr"},
                       **({"normal": NORMAL_FILE} if normal_map else {})) for cell in atlas.cells]
    extra = [name for names in cell_names for name in names.values()] if several else []
    texture = {}

    def painted():
        pictures = [square_texture(reading.read_image(file, params.max_megapixels, params.canvas_colour), size)
                    for file in files]
        texture["atlas"] = composed(atlas, pictures, size, params.canvas_colour) if several else pictures[0]
        layout = surface_layout(SurfaceMesh(atlas.uv, surface.position), full, across_seams, atlas)
        return paint_texture(texture["atlas"], layout, params, stroke_mm, progress, cancel)

    def written(staging: Path, painting) -> dict:
        if copy and several:
            write_png(staging / copy, texture["atlas"])
        elif copy:
            copy_file(files[0], staging / copy)
        if several:
            write_cell_maps(staging, painting, [(cell_file_suffix(cell), *cell_box(atlas, i, size))
                                                for i, cell in enumerate(atlas.cells)], normal_map)
        painting.statistics["atlas"] = atlas_figures(atlas, paths, size, cell_names)
        painting.statistics["inputs_sha256"] = digest
        source = Path(output_dir).resolve() / copy if copy else (paths[0] if several else files[0])
        return write_painting(staging, painting, str(source), normal_map, extra_files=extra)

    return committed_painting(output_dir, files[0], PAINTING_FILES + ((NORMAL_FILE,) if normal_map else ())
                              + tuple(extra) + ((copy,) if copy else ()), painted, written)


def copy_file(source, target: Path) -> None:
    """Copy ``source`` to ``target``; OutputError naming ``target`` when it cannot be written."""
    try:
        shutil.copyfile(source, target)
    except OSError as error:
        why = error.strerror or str(error)
        raise OutputError(f"Cannot write {target}: {why}.", target, why) from error


@contextlib.contextmanager
def connected_farm(farm):
    """A Dask client of ``farm`` (a ``core.farm.cluster.Farm``) for the block, or None without one."""
    if farm is None:
        yield None
        return
    from .farm.cluster import connected

    with connected(farm) as client:
        yield client


def pages_notice(input_path, pages: int) -> str:
    """The one-line notice for an input holding ``pages`` images, of which the first is used."""
    return f"{input_path} holds {pages} images; painting the first."


def out_of_memory(input_path) -> PaintReliefError:
    """The one-sentence error for a MemoryError while working on ``input_path``."""
    available = budget.available_bytes()
    free = f" ({budget.format_bytes(available)} available now)" if available is not None else ""
    return InputError(f"The machine ran out of memory while painting {input_path}{free}; "
                      f"use a smaller image or fewer layers, or free some memory.")
