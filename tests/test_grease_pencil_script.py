# SPDX-License-Identifier: GPL-3.0-or-later
"""sample_scenes/grease_pencil.py end to end: a painting's strokes saved as a Grease Pencil scene, the saved scene
laid again to the painting's maps, and its refusals, in subprocesses with the bpy module."""

from functools import partial
from pathlib import Path

import numpy as np
import pytest
from blender_run import need_bpy, run_script
from oracles import one_sentence_run

from core.cli import main
from core.files import reading, writing

REPO = Path(__file__).resolve().parent.parent
SCRIPT = REPO / "sample_scenes" / "grease_pencil.py"

_script = partial(run_script, SCRIPT)


@pytest.fixture(scope="module")
def saved(tmp_path_factory, half_textured):
    need_bpy()
    work = tmp_path_factory.mktemp("grease_pencil")
    photo = work / "photo.png"
    writing.write_png(photo, half_textured(48, 64))
    assert main(["paint", str(photo), "-o", str(work / "painted"), "-q", "--strokes-to-lay"]) == 0
    assert main(["paint", str(photo), "-o", str(work / "unlayable"), "-q"]) == 0
    made = _script([work / "painted", "-o", work / "scenes" / "strokes.blend", "--frames", "1-24", "--quiet"], work)
    assert made.returncode == 0, made.stdout[-3000:] + made.stderr[-3000:]
    return work


@pytest.mark.blender
def test_the_scene_is_saved_whole_and_lays_the_paintings_bytes(saved):
    assert sorted(p.name for p in (saved / "scenes").iterdir()) == ["strokes.blend"]
    laid = _script([saved / "scenes" / "strokes.blend", "--lay", "-o", saved / "laid", "--quiet"], saved)
    assert laid.returncode == 0, laid.stdout[-3000:] + laid.stderr[-3000:]
    # Blender's own OpenImageIO compresses the maps otherwise than PyPI's: the same pixels, other bytes.
    assert (saved / "laid" / "strokes.json").read_bytes() == (saved / "painted" / "strokes.json").read_bytes()
    for name in ("color.exr", "height.exr", "opacity.exr"):
        assert np.array_equal(reading.read_exr(saved / "laid" / name)[0], reading.read_exr(saved / "painted" / name)[0])
    assert np.array_equal(reading.read_image(saved / "laid" / "painting.png"),
                          reading.read_image(saved / "painted" / "painting.png"))


@pytest.mark.blender
def test_bad_inputs_are_one_sentence(saved):
    cases = [
        ([saved / "nowhere", "-o", saved / "x.blend"], saved / "nowhere"),
        ([saved / "painted", "-o", saved / "x.txt"], saved / "x.txt"),
        ([saved / "painted", "--lay", "-o", saved / "y"], saved / "painted"),
    ]
    for args, naming in cases:
        one_sentence_run(_script(args + ["--quiet"], saved))
        assert str(naming) in _script(args + ["--quiet"], saved).stderr
    assert not (saved / "x.blend").exists() and not (saved / "x.txt").exists() and not (saved / "y").exists()
    made = _script([saved / "unlayable", "-o", saved / "unlayable.blend", "--quiet"], saved)
    assert made.returncode == 0, made.stderr
    refused = _script([saved / "unlayable.blend", "--lay", "-o", saved / "z", "--quiet"], saved)
    assert "strokes.json" in one_sentence_run(refused) and not (saved / "z").exists()
    assert _script([saved / "painted", "-o", saved / "x.blend", "--frames", "9-3"], saved).returncode == 2
