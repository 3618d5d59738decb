"""`core batch`: unrelated stills painted each into a folder named as the panel names it, in one process or on a
local Dask cluster, the same bytes as each painted alone; a bad input refused before anything is painted."""

import errno
import json
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
from core.params import Params

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
    (tmp_path / "out" / "photo_001").mkdir(parents=True)       # an earlier painting's folder is never written over
    reports = paint_batch([str(p) for p in inputs], tmp_path / "out", PARAMS, farm=farm(2))
    folders = [Path(r["output_dir"]).name for r in reports]
    assert folders == ["still_0_001", "photo_002", "still_2_001", "still_3_001", "photo_003", "still_5_001"]
    for source, folder in zip(inputs, folders, strict=True):
        paint_file(str(source), tmp_path / "alone" / folder, PARAMS)
        assert painted(tmp_path / "out" / folder) == painted(tmp_path / "alone" / folder), folder


def test_a_batch_in_one_process_is_the_same_bytes_and_the_command_names_each_folder(tmp_path):
    inputs = photos(tmp_path / "in")[:2]
    result = subprocess.run([sys.executable, "-m", "core", "batch", *map(str, inputs), "-o", str(tmp_path / "out"),
                             "--seed", "9", "-q"], capture_output=True, text=True, cwd=ROOT, timeout=300)
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
