"""Model files painted in one step: sample_scenes/paint_object.py and ``core object`` take a .glb, .gltf, .obj or
.fbx (imported by Blender's own importers) as well as a .blend, paint the named object or every mesh that has a
material, and save the painted scene beside the scene as imported. The models are written by Blender's own
exporters (tests/blender/make_models.py): a textured ball, a crate of two image-textured materials, a floor without
a material."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from blender_run import need_bpy, run_checks, user_env

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "sample_scenes" / "paint_object.py"
SMALL = ["--views", "2", "--samples", "1", "--resolution", "64", "--texture-size", "64"]
PAINTED = {"Ball": ["Paint Relief Ball"], "Crate": ["Paint Relief Crate", "Paint Relief Crate 2"]}
ORIGINAL = {"Ball": ["Cat"], "Crate": ["Coffee", "Astronaut"]}
SHARED = "Object {} shares its mesh Crate with object {}: make it a single user (Object > Relation > Make Single " \
         "User > Object & Data) to paint it alone."


@pytest.fixture(scope="module")
def models(tmp_path_factory):
    need_bpy()
    work = tmp_path_factory.mktemp("models")
    found = run_checks(ROOT / "tests" / "blender" / "make_models.py", work, work / "files")
    assert all(found["exists"].values()), found
    return {kind: Path(path) for kind, path in found["files"].items()}


@pytest.fixture(scope="module")
def painted(models, tmp_path_factory):
    """Each format painted without --object, the .glb also with --object Crate and through ``core object``; the
    saved scenes' meshes read back."""
    work = tmp_path_factory.mktemp("painted")
    runs = {}
    for kind in ("glb", "gltf", "obj", "fbx", "shared"):
        runs[kind] = script([models[kind], "-o", work / kind, *SMALL], work)
    runs["one"] = script([models["glb"], "--object", "Crate", "-o", work / "one", *SMALL], work)
    env = {key: value for key, value in user_env(work).items() if key != "PAINT_RELIEF_BLENDER"}
    runs["core"] = subprocess.run([sys.executable, "-m", "core", "object", str(models["glb"]), "-o", str(work / "core"),
                                   "--object", "Ball", *SMALL], capture_output=True, text=True, timeout=600, cwd=ROOT,
                                  env=env)
    for kind, run in runs.items():
        assert run.returncode == 0, (kind, run.stderr[-3000:])
    scenes = run_checks(ROOT / "tests" / "blender" / "model_checks.py", work, *(work / kind for kind in runs))
    return work, runs, {kind: scenes[str(work / kind)] for kind in runs}


def script(args, work):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True, text=True,
                          timeout=600, cwd=work, env=user_env(work))


def slots(meshes):
    return {name: found["slots"] for name, found in meshes.items()}


@pytest.mark.parametrize("kind", ["glb", "gltf", "obj", "fbx"])
def test_each_format_is_imported_and_every_mesh_with_a_material_painted_and_the_scenes_saved(painted, kind):
    work, runs, scenes = painted
    out = work / kind
    scene, original = scenes[kind]["scene"], scenes[kind]["original"]
    floor = {} if kind == "obj" else {"Floor": []}       # the OBJ holds no Floor (make_models.py)
    assert slots(scene) == PAINTED | floor and slots(original) == ORIGINAL | floor
    assert all(scene[name]["painted"] for name in PAINTED) and not any(found["painted"] for found in original.values())
    assert all(scene[name]["modifiers"][-1] == "Paint Relief Displace" for name in PAINTED)
    assert scene.get("Floor", {}).get("modifiers", []) == []            # a mesh without a material is left alone
    assert sorted(p.name for p in (out / "maps").iterdir()) == ["Ball", "Crate"]
    assert (out / "maps" / "Crate" / "color.s1.exr").is_file() and (out / "maps" / "Ball" / "color.exr").is_file()
    summary = json.loads((out / "object.json").read_text())
    assert summary["objects"] == ["Ball", "Crate"] and summary["refused"] == {}
    assert set(summary["per_object"]) == {"Ball", "Crate"}
    assert summary["per_object"]["Crate"]["maps"] == "maps/Crate"
    assert {island["object"] for island in summary["islands"]} == {"Ball", "Crate"}
    for film in ("relit", "original", "paper"):
        assert len(summary["warping_error"][film]) == 1
        assert sorted(p.name for p in (out / "renders" / film).iterdir()) == ["0001.exr", "0002.exr"]
    assert not (out / "original.partial.blend").exists()


def test_with_object_the_one_object_layout_stays_and_through_core_object_too(painted):
    work, runs, scenes = painted
    for kind, name in (("one", "Crate"), ("core", "Ball")):
        out = work / kind
        assert slots(scenes[kind]["scene"])[name] == PAINTED[name]
        other = "Ball" if name == "Crate" else "Crate"
        assert slots(scenes[kind]["scene"])[other] == ORIGINAL[other]    # only the object named is painted
        assert slots(scenes[kind]["original"])[name] == ORIGINAL[name]
        assert (out / "maps" / "color.exr").is_file() and (out / "maps" / "report.json").is_file()
        summary = json.loads((out / "object.json").read_text())
        assert summary["object"] == name and "islands" in summary and "per_object" not in summary
        for film in ("relit", "original", "paper"):
            assert (out / "renders" / film / "0001.exr").is_file()
        assert (out / "scene.blend").is_file() and (out / "original.blend").is_file()


def test_objects_sharing_a_mesh_are_each_refused_in_a_sentence_and_the_others_painted(painted, models, tmp_path):
    work, runs, scenes = painted
    run = runs["shared"]
    assert run.stderr.strip().splitlines()[-2:] == [SHARED.format("Left", "Right"), SHARED.format("Right", "Left")]
    assert slots(scenes["shared"]["scene"]) == {"Ball": PAINTED["Ball"], "Left": ORIGINAL["Crate"],
                                                "Right": ORIGINAL["Crate"]}
    summary = json.loads((work / "shared" / "object.json").read_text())
    assert summary["objects"] == ["Ball"] and set(summary["refused"]) == {"Left", "Right"}
    run = script([models["twins"], "-o", tmp_path / "out", *SMALL], tmp_path)     # nothing painted: exit 1
    assert run.returncode == 1 and "Traceback" not in run.stderr
    assert run.stderr.strip().splitlines()[-1] == (f"No object of {models['twins']} was painted: Paint Object refused "
                                                   f"each of its 2 mesh objects with a material, as said above.")
    assert not (tmp_path / "out").exists()


def test_a_missing_an_unknown_and_a_damaged_model_are_each_one_sentence_and_leave_no_folder(models, tmp_path):
    damaged = tmp_path / "damaged.glb"
    damaged.write_bytes(models["glb"].read_bytes()[:3000])
    notes = tmp_path / "notes.txt"
    notes.write_text("no model")
    for model, sentence in (
            (tmp_path / "missing.glb", f"The model {tmp_path / 'missing.glb'} does not exist."),
            (notes, f"The model {notes} is no file Blender imports here: give a .glb, .gltf, .obj or .fbx file, "
                    f"or a .blend scene."),
            (damaged, f"Blender's glTF importer cannot read the model {damaged}: it is no glTF file, or a damaged "
                      f"one.")):
        out = tmp_path / f"out_{model.stem}"
        run = script([model, "-o", out, *SMALL], tmp_path)
        assert run.returncode == 1 and "Traceback" not in run.stderr + run.stdout, run.stderr[-3000:]
        assert run.stderr.strip().splitlines()[-1] == sentence
        assert not out.exists()


def test_core_object_finds_blender_in_the_environment_variable_then_the_bpy_module_then_the_path(monkeypatch,
                                                                                                 tmp_path):
    from core import blender
    from core.errors import InputError

    model = tmp_path / "model.glb"
    program = tmp_path / "blender"
    program.write_text("#!/bin/sh\n")
    program.chmod(0o755)
    monkeypatch.setenv("PAINT_RELIEF_BLENDER", str(program))
    assert blender.find_blender(model) == [str(program), "-b", "--python-exit-code", "1", "--python"]
    monkeypatch.setenv("PAINT_RELIEF_BLENDER", sys.executable)
    assert blender.find_blender(model) == [sys.executable]
    monkeypatch.setenv("PAINT_RELIEF_BLENDER", str(tmp_path / "nowhere"))
    with pytest.raises(InputError, match="names .*nowhere, which is no program here"):
        blender.find_blender(model)
    monkeypatch.delenv("PAINT_RELIEF_BLENDER")
    monkeypatch.setattr(blender.importlib.util, "find_spec", lambda name: object())
    assert blender.find_blender(model) == [sys.executable]
    monkeypatch.setattr(blender.importlib.util, "find_spec", lambda name: None)
    monkeypatch.setenv("PATH", str(tmp_path))
    assert blender.find_blender(model) == [str(program), "-b", "--python-exit-code", "1", "--python"]
    monkeypatch.setenv("PATH", str(tmp_path / "empty"))
    with pytest.raises(InputError) as refused:
        blender.find_blender(model)
    assert refused.value.status == 1 and str(refused.value) == (
        f"Painting the model {model} needs Blender, and none was found: install Blender (blender on the PATH) or the "
        f"bpy module (pip install bpy), or set PAINT_RELIEF_BLENDER to a blender program or a Python with bpy.")


def test_core_object_without_blender_is_one_sentence_and_exit_1_and_a_texture_without_a_mesh_is_refused(tmp_path):
    env = dict(os.environ, PAINT_RELIEF_BLENDER=str(tmp_path / "nowhere"))
    run = subprocess.run([sys.executable, "-m", "core", "object", str(tmp_path / "m.fbx"), "-o", str(tmp_path / "o")],
                         capture_output=True, text=True, timeout=120, cwd=ROOT, env=env)
    assert run.returncode == 1 and run.stderr.strip() == (
        f"paint-relief: error: Painting the model {tmp_path / 'm.fbx'} needs Blender, but PAINT_RELIEF_BLENDER names "
        f"{tmp_path / 'nowhere'}, which is no program here: set it to a blender program or a Python with the bpy "
        f"module.")
    run = subprocess.run([sys.executable, "-m", "core", "object", str(tmp_path / "t.png"), "-o", str(tmp_path / "o")],
                         capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert run.returncode == 2 and run.stderr.strip() == (
        f"paint-relief: error: {tmp_path / 't.png'} is no model file (.glb, .gltf, .obj, .fbx, .blend): give the "
        f"mesh of the texture with --mesh MESH.obj.")
    assert not (tmp_path / "o").exists()
