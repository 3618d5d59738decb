"""The headless flow from the installed zip: paint, canvas, lights, camera, a Cycles render, the comparison.

Runs in the environments `make test-shipped` builds (bpy of one Blender
version, its NumPy, pytest; no PyPI SciPy or OpenImageIO), so every library
the painter uses comes from Blender or from the zip's wheels.
"""

import pytest

from conftest import run_script


@pytest.fixture(scope="module")
def flow(package_zip, tmp_path_factory):
    work = tmp_path_factory.mktemp("flow")
    run, results = run_script("flow.py", package_zip, work, user_dir=work / "blender_user", cwd=work)
    assert results, "flow.py printed no results:\n{}\n{}".format(run.stdout[-3000:], run.stderr[-3000:])
    return results


def _step(flow, name):
    found = flow[name]
    assert "exception" not in found, found.get("exception")
    return found


def test_installs_without_importing_the_painter(flow):
    found = flow["install"]
    assert found["result"] == ["FINISHED"] and found["enabled"]
    assert found["imported_at_enable"] == []


def test_libraries_come_from_blender_or_the_zip(flow):
    found = _step(flow, "libraries")
    assert found["problem"] is None
    user = found["user_resources"]
    assert found["scipy_file"].startswith(user), "SciPy must come from the zip's wheel"
    if tuple(flow["install"]["blender"]) >= (4, 4, 0):
        assert found["openimageio_source"] == "blender", found["openimageio"]
    else:
        assert found["openimageio_source"] == "wheel" and found["openimageio"].startswith(user)


def test_paint(flow):
    found = _step(flow, "paint")
    assert found["result"] == ["FINISHED"], found["error"]
    assert {"color.exr", "height.exr", "opacity.exr", "normal.exr", "painting.png"} <= set(found["files"])


def test_canvas_lights_camera(flow):
    found = _step(flow, "stage")
    assert all(result == ["FINISHED"] for result, _ in found["results"].values()), found["results"]
    assert found["canvas_dimensions"] == pytest.approx([0.40, 0.30], abs=0.002)


def test_cycles_render(flow):
    found = _step(flow, "cycles_render")
    assert found["exists"] and found["size"][0] > 0 and found["std"] > 0.01


def test_comparison_with_labels(flow):
    found = _step(flow, "comparison")
    assert found["result"] == ["FINISHED"], found["error"]
    assert {"comparison.png", "correlation.png", "comparison.md", "light_sweep.gif"} <= set(found["files"])
    assert found["label_pixels"] > 100, "the comparison sheet's labels are missing"
    assert found["chart_title_dark_pixels"] > 50, "the chart's title is missing"
