"""The collection of models made by others (tests/models): at most 25 MB, every model credited under CC0 or
CC-BY, each imported by Blender's own importer (tests/blender/model_collection.py), and together they cover
the cases the painter must meet: glTF UVs outside the unit square under a repeating image, a normal map, metal,
emission, a smooth low-poly mesh and a base colour from a node group."""

import json
import re
import time
from pathlib import Path

import pytest
from blender_run import need_bpy, run_checks

MODELS = Path(__file__).resolve().parent / "models"
HELPER = Path(__file__).resolve().parent / "blender" / "model_collection.py"
LIMIT = 25_000_000
"""Bytes the collection may take."""
LISTED = json.loads((MODELS / "models.json").read_text())
LICENCE = re.compile(r"^- Licence: (CC0 1\.0|CC-BY [1-4]\.0)[ ,(]")


def outside_the_unit_square(uv_range):
    return uv_range is not None and (min(uv_range[0]) < -1e-3 or max(uv_range[1]) > 1 + 1e-3)


COVERS = {
    "glTF UVs outside 0..1 under a repeating image":
        lambda model, found: model["file"].endswith((".gltf", ".glb"))
        and outside_the_unit_square(found["uv_range"])
        and any(image["wrap"] in ("REPEAT", "MIRROR") for image in found["images"]),
    "normal map": lambda model, found: found["normal_map"],
    "metal": lambda model, found: found["metal"],
    "emission": lambda model, found: found["emission"],
    "smooth low-poly mesh":
        lambda model, found: 200 <= found["faces"] <= 5000 and found["smooth_faces"] >= 0.9 * found["faces"],
    "colour from a node group": lambda model, found: found["node_group_colour"],
}
"""Each case the collection covers, as a test of one model's findings."""


def credits():
    """CREDITS.md's sections by model name: the lines under each ``## name``."""
    sections, name = {}, None
    for line in (MODELS / "CREDITS.md").read_text().splitlines():
        if line.startswith("## "):
            name = line[3:].strip()
            sections[name] = []
        elif name is not None:
            sections[name].append(line)
    return sections


def test_the_collection_takes_at_most_25_mb():
    size = sum(path.stat().st_size for path in MODELS.rglob("*") if path.is_file())
    assert size <= LIMIT, "tests/models takes {:.1f} MB".format(size / 1e6)


def test_the_collection_holds_six_models_each_in_a_folder_of_its_own():
    names = [model["name"] for model in LISTED]
    assert len(names) >= 6 and len(set(names)) == len(names)
    for model in LISTED:
        assert (MODELS / model["file"]).is_file(), model["file"]
        assert Path(model["file"]).parts[0] == model["name"]
        assert set(model["covers"]) <= set(COVERS), model["covers"]
    folders = {path.name for path in MODELS.iterdir() if path.is_dir()}
    assert folders == set(names), "folders not in models.json: {}".format(folders - set(names))


def test_every_model_is_credited_under_cc0_or_cc_by():
    sections = credits()
    for model in LISTED:
        lines = sections.get(model["name"])
        assert lines, "{} is not in CREDITS.md".format(model["name"])
        for field in ("Title", "Author", "Source", "Licence", "Changes"):
            assert any(line.startswith("- {}: ".format(field)) for line in lines), (model["name"], field)
        licence = [line for line in lines if line.startswith("- Licence: ")]
        assert len(licence) == 1 and LICENCE.match(licence[0]), licence
        assert "https://creativecommons.org/" in licence[0]


@pytest.fixture(scope="module")
def collection(tmp_path_factory):
    need_bpy()
    work = tmp_path_factory.mktemp("collection")
    started = time.perf_counter()
    found = run_checks(HELPER, work, work / "out", timeout=300)
    print("model collection imported in {:.1f} s".format(time.perf_counter() - started))
    return found


@pytest.mark.blender
def test_each_model_imports_with_blenders_own_importer_as_listed(collection):
    for model in LISTED:
        found = collection[model["name"]]
        assert "exception" not in found, found.get("exception")
        assert Path(found["saved"]).is_file()
        assert found["objects"] and found["materials"], model["name"]
        assert found["missing_images"] == [], (model["name"], found["missing_images"])
        assert found["faces"] == model["faces"], (model["name"], found["faces"])
        corners = [value for corner in found["uv_range"] for value in corner]
        listed = [value for corner in model["uv_range"] for value in corner]
        assert corners == pytest.approx(listed, abs=2e-3), (model["name"], found["uv_range"])


@pytest.mark.blender
def test_each_model_covers_what_models_json_says(collection):
    for model in LISTED:
        for case in model["covers"]:
            assert COVERS[case](model, collection[model["name"]]), (model["name"], case)


@pytest.mark.blender
def test_the_collection_covers_every_case(collection):
    covered = {case for model in LISTED for case in COVERS if COVERS[case](model, collection[model["name"]])}
    assert covered == set(COVERS), "not covered: {}".format(set(COVERS) - covered)
