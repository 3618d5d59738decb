"""The Grease Pencil round trip from the installed zip (tests/shipped/grease_pencil.py), on every Blender
`make test-shipped` builds: Grease Pencil 3 from 4.3 on, the legacy Grease Pencil on 4.2."""

import pytest
from conftest import script_results
from conftest import step as _step


@pytest.fixture(scope="module")
def trip(package_zip, tmp_path_factory):
    return script_results("grease_pencil.py", package_zip, tmp_path_factory.mktemp("grease_pencil"))


def test_one_grease_pencil_stroke_per_stroke_with_its_width_and_colour(trip):
    assert trip["install"]["result"] == ["FINISHED"] and trip["install"]["enabled"]
    found = _step(trip, "paint_and_strokes_as_grease_pencil")
    assert found["painted"] == ["FINISHED"], found["error"]
    assert found["made"] == ["FINISHED"], found["made_error"]
    assert found["type"] == ("GREASEPENCIL" if found["grease_pencil_3"] else "GPENCIL")
    assert found["grease_pencil_3"] == (tuple(trip["install"]["blender"]) >= (4, 3, 0))
    assert found["parent"] == "canvas"
    assert found["strokes"] == found["strokes_json"] > 10
    assert found["min_points"] >= 2 and found["min_radius"] > 0
    assert found["colour_error"] < 1e-3, "vertex colours are not the strokes' bristle colours"
    assert found["index"]


def test_the_build_modifier_reveals_the_strokes_in_paint_order(trip):
    found = _step(trip, "paint_and_strokes_as_grease_pencil")
    assert found["modifiers"] == ["GREASE_PENCIL_BUILD" if found["grease_pencil_3"] else "GP_BUILD"]
    first, middle, last = found["visible"]
    assert first < middle < last == found["strokes"], found["visible"]


def test_unedited_strokes_lay_the_paintings_bytes_and_the_canvas_follows(trip):
    found = _step(trip, "laid_again_unedited")
    assert found["result"] == ["FINISHED"], found["error"]
    assert found["new_folder"] and all(found["same"].values()), found["same"]
    assert found["gp_folder"] and found["canvas_folder"] and found["canvases"] == 1


def test_half_the_strokes_deleted_leave_relief_only_where_strokes_remain(trip):
    found = _step(trip, "half_deleted")
    assert found["result"] == ["FINISHED"], found["error"]
    assert found["deleted"] > 5 and found["laid"] == found["kept"] > 5
    assert found["height_max"] > 0 and found["outside_share"] > 0.05
    assert found["outside"] == 0.0, "relief where no stroke remains"
    before, after = found["coverage"]
    assert after < before - 0.01


def test_a_recoloured_stroke_and_one_drawn_anew_are_laid(trip):
    found = _step(trip, "recoloured_and_drawn_anew")
    assert found["result"] == ["FINISHED"], found["error"]
    assert found["laid"] == found["before"] + 1
    assert found["new_size"] == 6 and found["new_brush"] == 0
    red, green, blue = found["new_blue"]
    assert blue > 0.5 and red < 0.1 and green < 0.1, found["new_blue"]
    assert found["first_colour"][0] > 0.9 and max(found["first_colour"][1:]) < 0.6, found["first_colour"]


def test_the_command_refuses_bad_inputs_in_one_sentence(trip):
    found = _step(trip, "command_line_refusals")
    assert (found["bad"], found["not_blend"]) == (1, 1) and not found["written"]
