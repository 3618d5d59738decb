"""`core batch`: unrelated stills painted each into a folder named as the panel names it, in one process or on a
local Dask cluster, the same bytes as each painted alone; a bad input refused before anything is painted."""

import errno
import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from core import paint_file
from core.api import paint_batch
from core.errors import InputError
from core.files.reading import read_image
from core.files.writing import write_png
from core.params import Params, SequenceSettings

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = ["coffee.png", "chelsea.png", "astronaut.png", "hubble.jpg"]
PARAMS = Params(seed=9)


def photos(folder: Path) -> list:
    """Six small photographs (128 x 96 windows of the sample scenes), two of them named photo.png in two
    folders."""
    paths = []
    for k in range(6):
        picture = read_image(ROOT / "sample_scenes" / SAMPLES[k % 4])[40 + 20 * k:136 + 20 * k, 60:188]
        name = "photo.png" if k in (1, 4) else f"still {k}.png"
        path = folder / f"set{k % 2}" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        write_png(path, np.ascontiguousarray(picture))
        paths.append(path)
    return paths


def painted(folder: Path) -> dict:
    """{name: bytes} of a painting's files, report.json without its seconds (the only thing a run's timing
    changes)."""
    files = {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file() and p.name != "report.json"}
    report = json.loads((folder / "report.json").read_text())
    report.pop("seconds")
    return dict(files, report=report)


@pytest.mark.cluster
def test_a_batch_on_two_local_workers_paints_each_still_as_painting_it_alone(tmp_path):
    pytest.importorskip("distributed")
    inputs = photos(tmp_path / "in")
    (tmp_path / "out" / "photo_001").mkdir(parents=True)       # a folder holding something else is never written over
    (tmp_path / "out" / "photo_001" / "painting.png").write_bytes(b"an earlier painting")
    reports = paint_batch([str(p) for p in inputs], tmp_path / "out", PARAMS, farm=farm(2))
    folders = [Path(r["output_dir"]).name for r in reports]
    assert folders == ["still_0_001", "photo_002", "still_2_001", "still_3_001", "photo_003", "still_5_001"]
    for source, folder in zip(inputs, folders, strict=True):
        paint_file(str(source), tmp_path / "alone" / folder, PARAMS)
        assert painted(tmp_path / "out" / folder) == painted(tmp_path / "alone" / folder), folder


def test_a_batch_in_one_process_is_the_same_bytes_and_the_command_names_each_folder(tmp_path):
    inputs = photos(tmp_path / "in")[:2]
    result = subprocess.run([sys.executable, "-m", "core", "batch", *map(str, inputs), "-o", str(tmp_path / "out"),
                             "--seed", "9", "-q"], capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines() == [f"{inputs[0]} -> {tmp_path / 'out' / 'still_0_001'}",
                                          f"{inputs[1]} -> {tmp_path / 'out' / 'photo_001'}"]
    paint_file(str(inputs[1]), tmp_path / "alone", PARAMS)
    assert painted(tmp_path / "out" / "photo_001") == painted(tmp_path / "alone")


def test_a_bad_input_is_refused_in_one_sentence_before_any_still_is_painted(tmp_path):
    inputs = photos(tmp_path / "in")[:3]
    broken = tmp_path / "in" / "broken.png"
    broken.write_bytes(b"not a picture")
    with pytest.raises(InputError) as refused:
        paint_batch([str(inputs[0]), str(broken), str(inputs[2])], tmp_path / "out", PARAMS)
    assert str(broken) in str(refused.value)
    assert not (tmp_path / "out").exists()


def unreadable(source, folder, params, normal_map=False):
    """A still that fails for itself on its worker, as reading from a lost mount does."""
    raise OSError(errno.EIO, "Input/output error", source)


@pytest.mark.cluster
def test_a_still_that_fails_with_an_os_error_is_named_and_not_taken_for_a_lost_scheduler(tmp_path):
    distributed = pytest.importorskip("distributed")
    from core.farm.batch import paint_stills
    from core.farm.cluster import FarmError

    source = photos(tmp_path / "in")[0]
    (tmp_path / "out").mkdir()
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as \
            local, distributed.Client(local) as client:
        with pytest.raises(FarmError) as failed:
            paint_stills(client, unreadable, [(source, tmp_path / "out" / "still_0_001")], tmp_path / "out",
                         PARAMS, False)
    assert str(failed.value) == (f"A Dask worker failed painting {source}: the device reported an input/output error "
                                  f"({source}).")


def farm(workers: int):
    from core.farm.cluster import Farm

    return Farm(workers=workers)


# --- shots in a batch ----------------------------------------------------------------------------------------------

def shot_painted(folder: Path) -> dict:
    """``painted`` of a shot's folder: its frames' maps, state and lives file, report.json without seconds."""
    files = {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file() and p.name != "report.json"}
    report = json.loads((folder / "report.json").read_text())
    report.pop("seconds")
    for entry in report["per_frame"]:
        entry.pop("seconds")
    return dict(files, report=report)


@pytest.fixture(scope="module")
def shots(tmp_path_factory):
    """Two shots of three 48 x 64 frames (a folder, and frames named for a # pattern) and one still."""
    from test_sequence import write_moving_frames

    root = tmp_path_factory.mktemp("shots")
    write_moving_frames(root / "walk", 3, shape=(48, 64))
    write_moving_frames(root / "pan", 3, shape=(48, 64), step=(-1.0, 1.0))
    return root


@pytest.mark.parametrize("name, shot", [("render/shot_####.exr", "shot"), ("render/####.exr", "render"),
                                        ("take.v2_####_beauty.exr", "take.v2__beauty"), ("a/walk/", "walk"),
                                        ("a/walk", "walk")])
def test_a_shot_is_named_by_its_folder_or_its_pattern_without_the_frame_number(name, shot):
    from core.files.shot_files import shot_name

    assert shot_name(name) == shot


def test_a_batch_of_shots_and_a_still_paints_each_as_painting_it_alone(tmp_path, shots):
    from core.api import paint_sequence_files

    still = shots / "walk" / "frame_0001.png"
    inputs = [shots / "walk", shots / "pan" / "frame_####.png", still]
    run = subprocess.run([sys.executable, "-m", "core", "batch", *map(str, inputs), "-o", str(tmp_path / "out"),
                          "-q", "--seed", "9"], cwd=ROOT, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert run.stdout.splitlines() == [f"{inputs[0]} -> {tmp_path / 'out' / 'walk_001'}",
                                       f"{inputs[1]} -> {tmp_path / 'out' / 'frame_001'}",
                                       f"{inputs[2]} -> {tmp_path / 'out' / 'frame_0001_001'}"]
    for source, folder in ((inputs[0], "walk"), (inputs[1], "pan")):
        paint_sequence_files(source, tmp_path / "alone" / folder, PARAMS)
    assert shot_painted(tmp_path / "out" / "walk_001") == shot_painted(tmp_path / "alone" / "walk")
    assert shot_painted(tmp_path / "out" / "frame_001") == shot_painted(tmp_path / "alone" / "pan")
    paint_file(still, tmp_path / "alone" / "still", PARAMS)
    assert painted(tmp_path / "out" / "frame_0001_001") == painted(tmp_path / "alone" / "still")


def test_a_bad_shot_is_refused_before_anything_is_painted(tmp_path, shots):
    import shutil

    shutil.copytree(shots / "walk", tmp_path / "odd")
    write_png(tmp_path / "odd" / "frame_0002.png", np.full((40, 64, 3), 0.5))
    with pytest.raises(InputError, match="frame_0002.png"):
        paint_batch([shots / "walk" / "frame_0001.png", tmp_path / "odd"], tmp_path / "out", PARAMS)
    assert not (tmp_path / "out").exists()


def test_a_batch_with_hertzmann_1998_and_a_shot_is_refused_before_anything_is_painted(tmp_path, shots):
    from core.errors import ParameterError

    with pytest.raises(ParameterError, match="paper"):
        paint_batch([shots / "walk" / "frame_0001.png", shots / "walk"], tmp_path / "out",
                    Params(seed=9, method="hertzmann98"))
    assert not (tmp_path / "out").exists()


@pytest.mark.cluster
def test_a_batch_of_shots_on_two_local_workers_paints_the_bytes_of_one_process(tmp_path, shots):
    pytest.importorskip("distributed")
    from core.farm.cluster import Farm

    inputs = [shots / "walk", shots / "pan", shots / "walk" / "frame_0002.png"]
    here = paint_batch(inputs, tmp_path / "here", PARAMS)
    there = paint_batch(inputs, tmp_path / "there", PARAMS, farm=Farm(workers=2))
    for mine, theirs in zip(here, there, strict=True):
        mine, theirs = Path(mine["output_dir"]), Path(theirs["output_dir"])
        assert mine.name == theirs.name
        same = shot_painted if (mine / "strokes.lives").exists() else painted
        assert same(mine) == same(theirs)


# --- a batch run again goes on where it stopped --------------------------------------------------------------------

def small_stills(folder: Path, count: int) -> list:
    """``count`` 48 x 64 photographs (windows of the sample scenes), still_0.png, still_1.png, ..."""
    paths = []
    for k in range(count):
        picture = read_image(ROOT / "sample_scenes" / SAMPLES[k % 4])[60 + 10 * k:108 + 10 * k, 80:144]
        path = folder / f"still_{k}.png"
        path.parent.mkdir(parents=True, exist_ok=True)
        write_png(path, np.ascontiguousarray(picture))
        paths.append(path)
    return paths


def batch(inputs, out: Path, *options) -> subprocess.CompletedProcess:
    """``core batch INPUTS -o OUT -q --seed 9 OPTIONS`` in a child process; it must succeed."""
    run = subprocess.run([sys.executable, "-m", "core", "batch", *map(str, inputs), "-o", str(out), "-q",
                          "--seed", "9", *map(str, options)], capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert run.returncode == 0, run.stderr
    return run


def counted(run: subprocess.CompletedProcess, kept: int, went_on: int, painted_now: int) -> None:
    """The run's stderr is the one line of its counts."""
    assert run.stderr.splitlines() == [f"paint-relief: batch: kept {kept}, went on with {went_on}, "
                                       f"painted {painted_now}."]


def untouched(folder: Path) -> dict:
    """{name: (bytes, inode, mtime in ns)} of everything in ``folder``, hidden files included."""
    return {p.name: (p.read_bytes() if p.is_file() else None, p.stat().st_ino, p.stat().st_mtime_ns)
            for p in sorted(folder.iterdir())}


def dead_lock(folder: Path) -> None:
    """The lock file a killed run left in ``folder``: it names a process that no longer holds it."""
    from core.files.folderlock import LOCK_NAME

    (folder / LOCK_NAME).write_text("99999999")


def test_a_batch_run_again_keeps_whole_folders_completes_a_commit_and_paints_only_what_is_missing(tmp_path):
    """Stopped in every way a kill can stop it: a still committed whole, one killed midway through its commit (the
    journal names a staging folder holding the files not yet renamed), one killed before its commit (a staging
    folder of half its files, no journal), one whose folder was made and left empty, one never begun."""
    from core.files.staging import JOURNAL_NAME, STAGING_PREFIX

    inputs = small_stills(tmp_path / "in", 5)
    out = tmp_path / "out"
    first = batch(inputs, out)
    counted(first, 0, 0, 5)
    whole = {name: painted(out / name) for name in (f"still_{k}_001" for k in range(5))}
    kept = untouched(out / "still_0_001")

    midway = out / "still_1_001"                      # killed between the commit point and the last rename
    staging = midway / f"{STAGING_PREFIX}99999999-0123456789abcdef"
    staging.mkdir()
    names = sorted(p.name for p in midway.iterdir() if p.is_file())
    for name in names[3:]:
        (midway / name).rename(staging / name)
    (midway / JOURNAL_NAME).write_text(json.dumps({"staging": staging.name, "files": names}))
    dead_lock(midway)

    before = out / "still_2_001"                      # killed while writing into its staging folder
    staging = before / f"{STAGING_PREFIX}99999999-fedcba9876543210"
    staging.mkdir()
    for p in sorted(before.iterdir()):
        if p.is_file():
            if p.suffix == ".exr":
                p.rename(staging / p.name)
            else:
                p.unlink()
    dead_lock(before)

    for name in ("still_3_001", "still_4_001"):
        shutil.rmtree(out / name)
    (out / "still_3_001").mkdir()                     # killed once its folder was made

    again = batch(inputs, out)
    assert again.stdout.splitlines() == [f"{source} -> {out / f'still_{k}_001'}" for k, source in enumerate(inputs)]
    counted(again, 2, 0, 3)
    assert sorted(p.name for p in out.iterdir()) == sorted(whole)
    assert untouched(out / "still_0_001") == kept, "a whole folder is kept as it was, byte for byte"
    for name, files in whole.items():
        assert sorted(p.name for p in (out / name).iterdir()) == sorted(p.name for p in (out / "still_0_001").iterdir())
        assert painted(out / name) == files, name

    third = batch(inputs, out)
    counted(third, 5, 0, 0)
    assert sorted(p.name for p in out.iterdir()) == sorted(whole)


def test_a_changed_input_or_option_is_painted_into_the_next_folder_and_fresh_paints_all_anew(tmp_path):
    from core.files.export import NORMAL_FILE

    source = small_stills(tmp_path / "in", 1)[0]
    out = tmp_path / "out"
    batch([source], out)
    first = untouched(out / "still_0_001")

    counted(batch([source], out, "--seed", "10"), 0, 0, 1)          # another seed: another painting
    counted(batch([source], out, "--normal-map"), 0, 0, 1)          # another file asked for
    assert (out / "still_0_003" / NORMAL_FILE).is_file() and not (out / "still_0_001" / NORMAL_FILE).exists()
    counted(batch([source], out, "--fresh"), 0, 0, 1)               # asked to paint anew
    assert painted(out / "still_0_004") == painted(out / "still_0_001")
    assert json.loads((out / "still_0_002" / "report.json").read_text())["params"]["seed"] == 10

    counted(batch([source], out, "--seed", "10", "--normal-map"), 0, 0, 1)
    counted(batch([source], out, "--seed", "10"), 1, 0, 0)         # the first folder of these settings is kept
    picture = read_image(source)
    write_png(source, np.ascontiguousarray(picture[:, ::-1]))       # the input changed
    changed = batch([source], out)
    counted(changed, 0, 0, 1)
    assert changed.stdout.strip() == f"{source} -> {out / 'still_0_006'}"
    assert untouched(out / "still_0_001") == first, "a folder of another input is never written into"
    paint_file(str(source), tmp_path / "alone", PARAMS)
    assert painted(out / "still_0_006") == painted(tmp_path / "alone")


def test_a_folder_changed_since_its_commit_or_held_by_a_living_run_is_left_as_it_is(tmp_path):
    """A commit writes all its files or none, so a folder whose report lists a file that is missing was changed by
    someone else: it is not kept, nor written into; neither is a folder another run holds."""
    from core.files import folderlock
    from core.files.staging import STAGING_PREFIX

    inputs = small_stills(tmp_path / "in", 2)
    out = tmp_path / "out"
    batch(inputs, out)
    (out / "still_0_001" / "painting.png").unlink()
    changed = untouched(out / "still_0_001")
    (out / "still_1_001" / f"{STAGING_PREFIX}1-ab").mkdir()
    with folderlock.acquire(out / "still_1_001"):
        held = untouched(out / "still_1_001")
        reports = paint_batch(inputs, out, PARAMS)
        assert untouched(out / "still_1_001") == held
    assert [Path(r["output_dir"]).name for r in reports] == ["still_0_002", "still_1_002"]
    assert [r["batch"] for r in reports] == ["painted", "painted"]
    assert untouched(out / "still_0_001") == changed
    assert painted(out / "still_1_002") == painted(out / "still_1_001")


def test_a_bad_input_in_a_batch_run_again_is_refused_before_any_folder_is_settled(tmp_path):
    from core.files.staging import JOURNAL_NAME, STAGING_PREFIX

    inputs = small_stills(tmp_path / "in", 2)
    out = tmp_path / "out"
    batch(inputs, out)
    staging = out / "still_1_001" / f"{STAGING_PREFIX}99999999-ab"
    staging.mkdir()
    (out / "still_1_001" / "report.json").rename(staging / "report.json")
    (out / "still_1_001" / JOURNAL_NAME).write_text(json.dumps({"staging": staging.name, "files": ["report.json"]}))
    dead_lock(out / "still_1_001")
    before = {folder.name: untouched(folder) for folder in out.iterdir()}
    broken = tmp_path / "in" / "broken.png"
    broken.write_bytes(b"not a picture")
    with pytest.raises(InputError) as refused:
        paint_batch([*inputs, broken], out, PARAMS)
    assert str(broken) in str(refused.value)
    assert {folder.name: untouched(folder) for folder in out.iterdir()} == before


def test_a_batch_run_again_goes_on_with_a_partly_painted_shot_to_the_bytes_of_the_shot_painted_whole(tmp_path,
                                                                                                       shots):
    """A shot stopped after frame 2 (its staging folder and lock left too) goes on in its own folder as
    `core sequence` goes on; a whole shot is checked and kept; a shot of other settings gets the next folder."""
    from core.api import KEPT, PAINTED, WENT_ON, batch_counts, paint_sequence_files
    from core.files.staging import STAGING_PREFIX

    still = shots / "pan" / "frame_0002.png"
    inputs = [shots / "walk", shots / "pan", still]
    whole = tmp_path / "whole"
    paint_sequence_files(shots / "walk", whole, PARAMS)
    out = tmp_path / "out"
    paint_sequence_files(shots / "walk", out / "walk_001", PARAMS, frame_range="1-2")
    (out / "walk_001" / f"{STAGING_PREFIX}99999999-0a").mkdir()
    (out / "walk_001" / f"{STAGING_PREFIX}99999999-0a" / "color_0003.exr").write_bytes(b"half")
    dead_lock(out / "walk_001")

    reports = paint_batch(inputs, out, PARAMS)
    assert [Path(r["output_dir"]).name for r in reports] == ["walk_001", "pan_001", "frame_0002_001"]
    assert [r["batch"] for r in reports] == [WENT_ON, PAINTED, PAINTED]
    assert shot_painted(out / "walk_001") == shot_painted(whole)

    pan = untouched(out / "pan_001")
    again = paint_batch(inputs, out, PARAMS)
    assert batch_counts(again) == {KEPT: 3, WENT_ON: 0, PAINTED: 0}
    assert [r["output_dir"] for r in again] == [r["output_dir"] for r in reports]
    assert untouched(out / "pan_001") == pan
    other = paint_batch([shots / "pan"], out, PARAMS, settings=SequenceSettings(fade_frames=2))
    assert [(Path(r["output_dir"]).name, r["batch"]) for r in other] == [("pan_002", PAINTED)]
    assert untouched(out / "pan_001") == pan


@pytest.mark.cluster
def test_a_batch_run_again_on_a_cluster_keeps_and_paints_the_same_folders(tmp_path):
    pytest.importorskip("distributed")
    inputs = small_stills(tmp_path / "in", 3)
    out = tmp_path / "out"
    batch(inputs, out)
    whole = {k: painted(out / f"still_{k}_001") for k in range(3)}
    kept = untouched(out / "still_0_001")
    shutil.rmtree(out / "still_1_001")
    for p in (out / "still_2_001").iterdir():
        p.unlink()
    dead_lock(out / "still_2_001")
    reports = paint_batch(inputs, out, PARAMS, farm=farm(1))
    assert [(Path(r["output_dir"]).name, r["batch"]) for r in reports] == [
        ("still_0_001", "kept"), ("still_1_001", "painted"), ("still_2_001", "painted")]
    assert untouched(out / "still_0_001") == kept
    assert {k: painted(out / f"still_{k}_001") for k in range(3)} == whole


def test_a_stopped_batch_says_the_same_command_goes_on_or_without_fresh():
    from types import SimpleNamespace

    from core.cli import _interrupted_message

    stopped = SimpleNamespace(name="SIGTERM")
    args = SimpleNamespace(command="batch", input=["a.png"], output="out", fresh=False)
    assert _interrupted_message(stopped, args) == ("Stopped by SIGTERM; the stills painted stay in out, each folder "
                                                   "complete, and the same command goes on where it stopped.")
    args.fresh = True
    assert _interrupted_message(stopped, args).endswith("the same command without --fresh goes on where it stopped.")
