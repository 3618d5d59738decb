"""Where paintings go (core/files/folders.py): each painting's own folder ``<stem>_NNN``, named by one rule for the
extension's Paint button (addon/values.py) and the command line."""

import os
import subprocess
import sys
from pathlib import Path

import pytest
from addon_values import values

from core.files import folders

REPO = Path(__file__).resolve().parent.parent


@pytest.mark.parametrize("image_path, stem", [
    ("My photo (1).JPG", "My_photo_1"),
    ("/a/b/coffee.png", "coffee"),
    ("shot-2_final.tar.exr", "shot-2_final_tar"),
    ("été.png", "t"),
    ("(((.png", "painting"),
    ("/a/folder/", "folder"),
])
def test_folder_stem_keeps_letters_digits_dashes_underscores(image_path, stem):
    assert folders.folder_stem(image_path) == stem


def test_next_painting_folder_is_the_first_free_counter(tmp_path):
    assert folders.next_painting_folder(tmp_path, "x/photo.png") == str(tmp_path / "photo_001")
    (tmp_path / "photo_001").mkdir()
    (tmp_path / "photo_002").write_text("a file takes the name too")
    assert folders.next_painting_folder(tmp_path, "photo.jpg") == str(tmp_path / "photo_003")
    assert folders.next_painting_folder(tmp_path, "photo.jpg", digits=5) == str(tmp_path / "photo_00001")
    assert sorted(os.listdir(tmp_path)) == ["photo_001", "photo_002"], "nothing is created"


def test_the_counter_grows_past_its_width(tmp_path):
    for counter in range(1, 10):
        (tmp_path / "p_{}".format(counter)).mkdir()
    assert folders.next_painting_folder(tmp_path, "p.png", digits=1) == str(tmp_path / "p_10")


def test_painting_folders_names_inputs_of_one_stem_apart(tmp_path):
    inputs = ["a/photo.png", "b/photo.png", "c/photo.jpg"]
    assert folders.painting_folders(tmp_path, inputs) == [str(tmp_path / n) for n in
                                                          ("photo_001", "photo_002", "photo_003")]


def test_painting_folders_skips_existing_folders(tmp_path):
    (tmp_path / "photo_001").mkdir()
    (tmp_path / "photo_003").mkdir()
    (tmp_path / "other_001").mkdir()
    got = folders.painting_folders(tmp_path, ["photo.png", "other.png", "a/photo.png", "b/photo.png"])
    assert got == [str(tmp_path / n) for n in ("photo_002", "other_002", "photo_004", "photo_005")]
    assert sorted(os.listdir(tmp_path)) == ["other_001", "photo_001", "photo_003"], "nothing is created"


def test_a_folder_left_by_a_run_stopped_before_its_first_commit_is_free_again(tmp_path):
    """A killed run leaves its lock file (held by no process) and a staging folder: that folder is cleared and named
    again; one whose lock a living run holds, or that holds anything else, stays taken."""
    from core.files import folderlock
    from core.files.staging import STAGING_PREFIX

    stopped, writing, painted = tmp_path / "photo_001", tmp_path / "photo_002", tmp_path / "photo_003"
    for folder in (stopped, writing, painted):
        (folder / f"{STAGING_PREFIX}1-ab").mkdir(parents=True)
        (folder / folderlock.LOCK_NAME).write_text("99999999")
    (painted / "painting.png").write_bytes(b"png")
    with folderlock.acquire(writing):
        got = folders.painting_folders(tmp_path, ["photo.png", "photo.png"])
    assert got == [str(stopped), str(tmp_path / "photo_004")]
    assert os.listdir(stopped) == [] and sorted(os.listdir(painted)) == sorted(
        [f"{STAGING_PREFIX}1-ab", folderlock.LOCK_NAME, "painting.png"])


def test_painting_folders_are_distinct_whatever_the_case(tmp_path):
    got = folders.painting_folders(tmp_path, ["Photo.png", "photo.png", "PHOTO.PNG"])
    assert got == [str(tmp_path / n) for n in ("Photo_001", "photo_002", "PHOTO_003")]
    assert len({path.casefold() for path in got}) == 3


def test_painting_folders_of_one_input_is_next_painting_folder(tmp_path):
    (tmp_path / "coffee_001").mkdir()
    assert folders.painting_folders(tmp_path, ["coffee.png"]) == [folders.next_painting_folder(tmp_path, "coffee.png")]
    assert folders.painting_folders(tmp_path, []) == []
    assert folders.painting_folders(tmp_path, iter(["x.png", "x.png"]), digits=2) == [str(tmp_path / "x_01"),
                                                                                     str(tmp_path / "x_02")]


def test_the_extension_names_folders_by_cores_rule(tmp_path, monkeypatch):
    (tmp_path / "photo_001").mkdir()
    assert values.next_painting_folder(str(tmp_path), "photo.png") == str(tmp_path / "photo_002")
    assert values.folder_stem("My photo (1).JPG") == "My_photo_1"
    # values holds no rule of its own: it asks core's module, so a change there reaches the Paint button.
    monkeypatch.setattr(folders, "folder_stem", lambda image_path: "ruled_by_core")
    assert values.folder_stem("photo.png") == "ruled_by_core"
    assert values.next_painting_folder(str(tmp_path), "photo.png") == str(tmp_path / "ruled_by_core_001")


def test_naming_folders_loads_none_of_the_painters_libraries():
    """The extension names folders while drawing its panel, before the painter's libraries are loaded (Blender
    4.2.0 needs addon/dependencies.py to pick its SciPy first)."""
    code = ("import sys, core.files.folders; "
            "print(sorted(m for m in sys.modules if m.split('.')[0] in "
            "('numpy', 'scipy', 'OpenImageIO', 'threadpoolctl')))")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, timeout=600)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "[]"


def test_resumed_folders_give_each_input_its_own_folder_else_an_unfinished_one_else_the_next_free(tmp_path):
    """A batch run again: each input gets the first folder ``owns`` says is its own (asked only of folders that hold
    something, after settling), else the first a stopped run left empty, else the next free counter; two inputs
    never get one folder, and a folder another run holds is passed over."""
    from core.files import folderlock
    from core.files.staging import STAGING_PREFIX

    for name, mark in (("photo_001", "other"), ("photo_002", "a"), ("photo_004", "a"), ("photo_005", "b")):
        (tmp_path / name).mkdir()
        (tmp_path / name / "mark").write_text(mark)
    (tmp_path / "photo_003" / f"{STAGING_PREFIX}1-ab").mkdir(parents=True)    # a run stopped before its commit
    (tmp_path / "photo_003" / folderlock.LOCK_NAME).write_text("99999999")
    (tmp_path / "photo_006").mkdir()                                          # made, never written
    (tmp_path / "photo_007").write_text("a file takes the name")
    (tmp_path / "photo_1").mkdir()                                           # not a name the rule gives
    (tmp_path / "photo_1" / "mark").write_text("a")
    asked = []

    def owns(k, folder):
        asked.append((k, os.path.basename(folder)))
        return "yes" if (Path(folder) / "mark").read_text() == "abcb"[k] else None

    inputs = ["a/photo.png", "b/photo.png", "c/photo.png", "x/photo.jpg"]
    got = folders.resumed_folders(tmp_path, inputs, owns)
    assert [(os.path.basename(folder), found) for folder, found in got] == [
        ("photo_002", "yes"), ("photo_005", "yes"), ("photo_003", None), ("photo_006", None)]
    assert os.listdir(tmp_path / "photo_003") == []
    assert all(name not in ("photo_003", "photo_006", "photo_007", "photo_1") for _, name in asked)
    got = folders.resumed_folders(tmp_path, ["a/photo.png"] * 3, lambda k, folder: (Path(folder) / "mark").read_text()
                                  == "a")
    assert [os.path.basename(folder) for folder, _ in got] == ["photo_002", "photo_004", "photo_003"]

    with folderlock.acquire(tmp_path / "photo_006"):
        got = folders.resumed_folders(tmp_path, ["c/photo.png", "c/photo.png"], lambda k, folder: None)
    assert [os.path.basename(folder) for folder, _ in got] == ["photo_003", "photo_008"]
    assert folders.next_painting_folder(tmp_path, "photo.png") == str(tmp_path / "photo_008")
