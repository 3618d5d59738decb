"""``python -m core svg PAINTED_DIR -o FILE.svg``: one path per stroke of strokes.json, in painting order, and one
sentence with exit status 1 (no file written) for a folder or a stroke list it cannot read."""

import json
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from oracles import one_sentence

from core.cli import main
from core.files import writing
from core.files.stroke_file import bristle_colours
from core.files.svg import hex_colour, path_data

SVG = "{http://www.w3.org/2000/svg}"


@pytest.fixture(scope="module")
def painted(tmp_path_factory, half_textured):
    """A 64 x 48 photograph painted with seed 3."""
    folder = tmp_path_factory.mktemp("svg")
    writing.write_png(folder / "photo.png", half_textured(48, 64))
    assert main(["paint", str(folder / "photo.png"), "-o", str(folder / "painted"), "-q", "--seed", "3",
                 "--strokes-to-lay"]) == 0
    return folder / "painted"


def paths_of(svg_file):
    """(the root element, its <path> elements in order), parsed strictly by xml.etree."""
    root = ET.parse(svg_file).getroot()
    return root, list(root.iter(f"{SVG}path"))


def test_every_stroke_is_one_path_in_painting_order(painted, tmp_path):
    out = tmp_path / "strokes.svg"
    assert main(["svg", str(painted), "-o", str(out), "-q"]) == 0
    strokes = json.loads((painted / "strokes.json").read_text())["strokes"]
    root, paths = paths_of(out)
    assert root.tag == f"{SVG}svg" and root.get("viewBox") == "0 0 64 48"
    assert (root.get("width"), root.get("height")) == ("64", "48")
    group = root.find(f"{SVG}g")
    assert group.get("stroke-linecap") == "round" and group.get("stroke-linejoin") == "round"
    assert group.get("fill") == "none"
    assert len(paths) == len(strokes) > 100
    for path, stroke in zip(paths, strokes, strict=True):
        assert path.get("d") == path_data(stroke["path"])
        assert path.get("stroke-width") == str(stroke["size"])
        mean = bristle_colours(stroke).mean(axis=0, dtype=np.float64)
        assert path.get("stroke") == hex_colour(mean)
        assert path.get("stroke-opacity") is None            # a still's strokes are laid at full contact
    first = strokes[0]["path"]
    assert paths[0].get("d").startswith(f"M{first[0][0]:g} {first[0][1]:g} L")
    assert not [p.name for p in tmp_path.iterdir() if p.name != "strokes.svg"]


def test_a_list_without_bristles_or_size_takes_anchor_colours_and_the_reports_size(painted, tmp_path):
    """Format 1 (no "format", the records alone): the anchor colour, the size from report.json beside it."""
    folder = tmp_path / "old"
    folder.mkdir()
    document = json.loads((painted / "strokes.json").read_text())
    records = [{k: s[k] for k in ("layer", "anchor", "size", "path", "colour")} for s in document["strokes"]]
    records[0] = dict(records[0], path=[records[0]["path"][0]])           # a dab of one point
    (folder / "strokes.json").write_text(json.dumps({"version": "0.1", "strokes": records}))
    (folder / "report.json").write_text((painted / "report.json").read_text())
    assert main(["svg", str(folder), "-o", str(tmp_path / "old.svg"), "-q"]) == 0
    root, paths = paths_of(tmp_path / "old.svg")
    assert root.get("viewBox") == "0 0 64 48"
    assert [p.get("stroke") for p in paths] == [hex_colour(s["colour"]) for s in records]
    assert paths[0].get("d").count(" L") == 1


def test_hex_colour_and_path_data():
    assert hex_colour([1.0, 0.5, 0.0]) == "#ff8000" and hex_colour([-1, 2, 0.2]) == "#00ff33"
    assert path_data([[1.5, 2.0]]) == "M1.5 2 L1.5 2"
    assert path_data([[0.004, -3.1], [10.25, 7]]) == "M0 -3.1 L10.25 7"


@pytest.mark.parametrize("content, words", [
    (None, "does not exist"),
    ("{not json", "not valid JSON"),
    ('{"type": "FeatureCollection", "features": []}', "no stroke list"),
    ('{"format": 7, "strokes": []}', "format 7"),
    ('{"format": 2, "strokes": [{"layer": 0, "size": 4}]}', "Stroke 0"),
    ('{"format": 2, "strokes": []}', "size"),
])
def test_a_bad_folder_or_list_is_one_sentence_and_no_file(tmp_path, capsys, content, words):
    folder = tmp_path / "painted"
    folder.mkdir()
    if content is not None:
        (folder / "strokes.json").write_text(content)
    out = tmp_path / "out" / "strokes.svg"
    out.parent.mkdir()
    assert main(["svg", str(folder), "-o", str(out), "-q"]) == 1
    message = capsys.readouterr().err.strip().removeprefix("paint-relief: error: ")
    assert words in one_sentence(message, naming=folder / "strokes.json")
    assert list(out.parent.iterdir()) == []


def test_a_missing_folder_is_one_sentence(tmp_path, capsys):
    assert main(["svg", str(tmp_path / "nowhere"), "-o", str(tmp_path / "x.svg"), "-q"]) == 1
    one_sentence(capsys.readouterr().err.strip().removeprefix("paint-relief: error: "), naming=tmp_path / "nowhere")
    assert list(tmp_path.iterdir()) == []
