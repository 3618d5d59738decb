"""Paint Scene inside Blender (tests/blender/scene_paint_checks.py): what the camera sees over the frames, the
size of its pixels, one set of stroke widths for a scene of several objects, a shared photograph painted once,
a refused object named, a second run keeping every texture, and the selection alone."""

import pytest
from blender_run import need_bpy, run_checks
from blender_run import step as _step

pytestmark = pytest.mark.blender
HELPER = __import__("pathlib").Path(__file__).resolve().parent / "blender" / "scene_paint_checks.py"


@pytest.fixture(scope="module")
def found(tmp_path_factory):
    need_bpy()
    work = tmp_path_factory.mktemp("scene")
    return run_checks(HELPER, work, work)


def test_the_meshes_the_camera_sees_in_some_frame_are_found_and_no_others(found):
    seen = _step(found, "seen_over_the_frames")
    assert seen["seen"] == ["Ahead", "Late"]        # not aside, behind, or hidden from renders
    assert seen["ahead"] == pytest.approx([10.0] * 5) and seen["late"] == pytest.approx([10.0])
    assert seen["frame_after"] == 2
    assert seen["scanned_long"] == 48 and seen["scanned_ends"] == [1, 1000]


def test_a_pixel_spans_the_picture_width_at_its_depth_over_the_render_width(found):
    size = _step(found, "pixel_size")
    assert size["render"] == [320, 180]
    assert size["perspective"] == pytest.approx(10.0 * 36.0 / 50.0 * 1000.0 / 320)    # depth x sensor / lens
    assert size["orthographic"] == pytest.approx(6.0 * 1000.0 / 320)


def test_every_object_is_painted_with_the_cameras_stroke_widths_and_a_shared_photograph_once(found):
    painted = _step(found, "scene_painted")
    assert painted["result"] == ["FINISHED"], painted["error"]
    assert sorted(painted["painted"]) == ["Ball", "Box", "Box Twin"]
    assert list(painted["refused"]) == ["Plane Without UVs"]
    assert "Plane Without UVs" in painted["refused"]["Plane Without UVs"]
    assert "UV map" in painted["refused"]["Plane Without UVs"]
    assert painted["paintings"] == {"Ball": ["Ball"], "Box": ["Box", "Box Twin"]}
    assert painted["painted"]["Box Twin"]["folder"] == "Box"
    how = painted["how"]
    assert how["chosen_by"] == "camera" and how["render_px"] == [640, 360]
    assert how["typical_depth_m"] == pytest.approx(painted["expected_depth"], rel=1e-4)
    assert painted["stroke_mm"] == pytest.approx(painted["expected_mm"], abs=0.005)     # rounded to 0.01 mm
    assert all(name.startswith("Paint Relief") for name in painted["materials"]["Box"] + painted["materials"]["Ball"])
    assert painted["materials"]["Plane Without UVs"] == ["Noise"]
    assert painted["files"] == ["Ball", "Box", "paint_scene.json"]


def test_painting_again_keeps_every_texture_and_writes_nothing(found):
    again = _step(found, "painted_again_keeps_every_texture")
    assert again["result"] == ["FINISHED"], again["error"]
    assert again["kept"] == {"Ball": True, "Box": True} and again["unchanged"]
    assert again["painted"] == ["Ball", "Box", "Box Twin"]


def test_a_stopped_run_keeps_what_it_finished_and_painting_again_gives_the_bytes_of_a_run_never_stopped(found):
    stopped = _step(found, "stopped_and_painted_again")
    done = stopped["done_when_stopped"]     # the textures committed before the stop was seen: one, or both
    assert len(done) >= 1 and (len(done) == 2 or "cancelled" in stopped["outcome"])
    assert stopped["result"] == ["FINISHED"], stopped["error"]
    assert stopped["kept"] == {"Ball": "Ball" in done, "Box": "Box" in done}
    assert stopped["same_bytes"] == {"Ball": True, "Box": True}, stopped["differ"]


def test_the_selection_alone_is_painted_when_asked(found):
    selection = _step(found, "selection_alone")
    assert selection.get("result") == ["FINISHED"], selection
    assert selection["painted"] == ["Ball"] and selection["folders"] == ["Ball"]
