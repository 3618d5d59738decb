"""Models made by others (tests/models), each painted as a user would (sample_scenes/paint_object.py on the model
as Blender's own importer reads it), keep what they were: the shading of their normal maps and custom normals
with the paint's relief at 0, their colour in the relit turntable, and their glow."""

import json
from pathlib import Path

import numpy as np
import pytest
from blender_run import need_bpy, run_checks, run_script

ROOT = Path(__file__).resolve().parent.parent
MODELS = ROOT / "tests" / "models"
SCRIPT = ROOT / "sample_scenes" / "paint_object.py"
FIGURES = ROOT / "tests" / "blender" / "model_figures.py"
LISTED = json.loads((MODELS / "models.json").read_text())
PAINTED = [(model["name"], name) for model in LISTED
           for name in ([model["object"]] if model["object"] else model.get("test_objects", []))]
"""(model, object) pairs painted: the model's object, or for a model of many the ones models.json picks."""
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def film_luminance(folder):
    """The mean linear luminance over the object's pixels (depth < 1e9) of the multilayer EXRs in ``folder``."""
    import OpenImageIO as oiio

    total, count = 0.0, 0
    for path in sorted(folder.glob("*.exr")):
        channels = {}
        for part in range(max(oiio.ImageBuf(str(path)).nsubimages, 1)):    # Blender 5 writes a part per pass
            buffer = oiio.ImageBuf(str(path), part, 0)
            pixels = buffer.get_pixels(oiio.FLOAT)
            for index, name in enumerate(buffer.spec().channelnames):
                channels[".".join(name.split(".")[-2:])] = pixels[..., index]
        rgb = np.stack([channels["Combined." + channel] for channel in "RGB"], -1)
        covered = channels["Depth.Z"] < 1e9
        total += float((rgb[covered] @ LUMINANCE).sum())
        count += int(covered.sum())
    return total / max(count, 1)


@pytest.fixture(scope="module")
def paintings(tmp_path_factory):
    """{(model, object): (findings of model_figures.py, relit luminance, original luminance)}."""
    need_bpy()
    work = tmp_path_factory.mktemp("paintings")
    found = {}
    for model, name in PAINTED:
        out = work / "{}-{}".format(model, name)
        run = run_script(SCRIPT, [MODELS / dict((m["name"], m["file"]) for m in LISTED)[model], "--object", name,
                                  "-o", out, "--views", "8", "--samples", "4", "--resolution", "96",
                                  "--texture-size", "256"], work, timeout=600)
        assert run.returncode == 0, "{} {}:\n{}".format(model, name, run.stderr[-3000:])
        figures = run_checks(FIGURES, work, out / "original.blend", out / "scene.blend", name, out / "figures",
                             "--views", "4", "--res", "96", timeout=600)
        found[model, name] = (figures, film_luminance(out / "renders" / "relit"),
                              film_luminance(out / "renders" / "original"))
        print(model, name, json.dumps(figures), "colour {:.3f}".format(found[model, name][1] / found[model, name][2]))
    return found


@pytest.mark.blender
@pytest.mark.parametrize("model, name", PAINTED)
def test_the_shading_stays_with_the_relief_at_0(paintings, model, name):
    figures = paintings[model, name][0]
    assert figures["pixels"] > 1000
    assert figures["shading_mean"] <= 2.0 and figures["shading_p95"] <= 6.0, figures


@pytest.mark.blender
@pytest.mark.parametrize("model, name", PAINTED)
def test_the_relit_colour_stays_within_0_8_to_1_25_of_the_original(paintings, model, name):
    _, relit, original = paintings[model, name]
    assert original > 1e-3 and 0.8 <= relit / original <= 1.25, (relit, original)


@pytest.mark.blender
@pytest.mark.parametrize("model, name", PAINTED)
def test_what_glows_still_glows(paintings, model, name):
    figures = paintings[model, name][0]
    if figures["glow_original"] < 1.0:                      # it gives no light of its own
        assert figures["glow_painted"] < 1.0 + 0.2 * figures["glow_original"], figures
    else:
        assert figures["glow_painted"] >= 0.8 * figures["glow_original"], figures
