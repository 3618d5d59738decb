"""``python -m core lay STROKES.json --reference INPUT -o OUTDIR``: a painting's own stroke list gives the painting's
bytes, an edited list another painting, and a list or reference it cannot lay one sentence, exit status 1 and
nothing written."""

import base64
import json

import numpy as np
import pytest
from oracles import one_sentence, same_bytes

from core.cli import main
from core.files import reading, writing

MAPS = ("color.exr", "height.exr", "opacity.exr", "painting.png", "lit_paper.png")


@pytest.fixture(scope="module")
def painted(tmp_path_factory, half_textured):
    """(the photograph, its folder painted with seed 3): 64 x 48 px."""
    folder = tmp_path_factory.mktemp("lay")
    photo = folder / "photo.png"
    writing.write_png(photo, half_textured(48, 64))
    assert main(["paint", str(photo), "-o", str(folder / "painted"), "-q", "--seed", "3", "--strokes-to-lay"]) == 0
    return photo, folder / "painted"


def lay(strokes, reference, out) -> int:
    return main(["lay", str(strokes), "--reference", str(reference), "-o", str(out), "-q"])


def test_the_paintings_own_list_gives_the_paintings_bytes(painted, tmp_path):
    photo, folder = painted
    assert lay(folder / "strokes.json", photo, tmp_path / "laid") == 0
    same_bytes(folder, tmp_path / "laid")                 # every file but report.json (its seconds)
    mine, theirs = (json.loads((f / "report.json").read_text()) for f in (folder, tmp_path / "laid"))
    for key in ("strokes", "strokes_per_layer", "detail_strokes", "stroke_shape", "grids", "psnr_db", "params",
                "width", "height", "input_sha256"):
        assert mine[key] == theirs[key], key


def test_every_other_stroke_deleted_changes_the_maps_and_drops_the_coverage(painted, tmp_path):
    photo, folder = painted
    document = json.loads((folder / "strokes.json").read_text())
    document["strokes"] = document["strokes"][::2]
    edited = tmp_path / "edited.json"
    edited.write_text(json.dumps(document))
    assert lay(edited, photo, tmp_path / "laid") == 0
    for name in MAPS:
        assert (folder / name).read_bytes() != (tmp_path / "laid" / name).read_bytes(), name
    before, after = (reading.read_exr(f / "opacity.exr")[0].mean() for f in (folder, tmp_path / "laid"))
    assert after < before - 0.01
    report = json.loads((tmp_path / "laid" / "report.json").read_text())
    assert report["strokes"] == len(document["strokes"]) == sum(report["strokes_per_layer"])
    assert json.loads((tmp_path / "laid" / "strokes.json").read_text())["strokes"] == document["strokes"]


def edited_list(folder, tmp_path, edit):
    """A copy of the painting's strokes.json changed by ``edit(document)`` (which may return text instead)."""
    document = json.loads((folder / "strokes.json").read_text())
    result = edit(document)
    path = tmp_path / "edited.json"
    path.write_text(result if isinstance(result, str) else json.dumps(document))
    return path


def fewer_bristles(document):
    lay = document["strokes"][5]["lay"]
    lay["bristles"] = base64.b64encode(base64.b64decode(lay["bristles"])[:-12]).decode()


def old_format(document):
    del document["format"]
    for stroke in document["strokes"]:
        del stroke["lay"]


@pytest.mark.parametrize("edit, words", [
    (lambda d: '{"type": "FeatureCollection", "features": []}', "no stroke list"),
    (lambda d: "[1, 2", "not valid JSON"),
    (old_format, "format 1"),
    (lambda d: d.update(format=3), "format 3"),
    (lambda d: d["strokes"][3].pop("lay"), "Stroke 3"),
    (lambda d: d["strokes"][4]["lay"].update(control="here"), "Stroke 4"),
    (fewer_bristles, "cannot be laid"),
    (lambda d: d["strokes"][2]["lay"].update(last=10**6), "cannot be laid"),
    (lambda d: d["params"].update(brush_size_unknown=3), "parameters"),
    (lambda d: d["params"].update(layers=-2), "parameters"),
])
def test_a_bad_list_is_one_sentence_exit_1_and_nothing_written(painted, tmp_path, capsys, edit, words):
    photo, folder = painted
    strokes = edited_list(folder, tmp_path, edit)
    out = tmp_path / "out"
    assert lay(strokes, photo, out) == 1
    message = capsys.readouterr().err.strip().removeprefix("paint-relief: error: ")
    assert words in one_sentence(message, naming=strokes)
    assert not out.exists()


def test_a_reference_of_another_size_is_one_sentence_exit_1_and_nothing_written(painted, tmp_path, capsys,
                                                                                 half_textured):
    _, folder = painted
    other = tmp_path / "other.png"
    writing.write_png(other, half_textured(50, 64))
    out = tmp_path / "out"
    out.mkdir()
    (out / "mine.txt").write_text("kept")
    assert lay(folder / "strokes.json", other, out) == 1
    message = one_sentence(capsys.readouterr().err.strip().removeprefix("paint-relief: error: "), naming=other)
    assert "64 x 50" in message and "64 x 48" in message
    assert [p.name for p in out.iterdir()] == ["mine.txt"]


def test_a_missing_list_is_one_sentence(painted, tmp_path, capsys):
    photo, _ = painted
    assert lay(tmp_path / "none.json", photo, tmp_path / "out") == 1
    one_sentence(capsys.readouterr().err.strip().removeprefix("paint-relief: error: "), naming=tmp_path / "none.json")
    assert not (tmp_path / "out").exists()


def test_an_empty_list_lays_a_bare_canvas(painted, tmp_path):
    photo, folder = painted
    strokes = edited_list(folder, tmp_path, lambda d: d.update(strokes=[]))
    assert lay(strokes, photo, tmp_path / "laid") == 0
    assert np.all(reading.read_exr(tmp_path / "laid" / "opacity.exr")[0] == 0)


def test_laying_shows_its_progress_and_a_cancel_leaves_the_folder_as_it_was(tmp_path, half_textured):
    from core.api import lay_file
    from core.errors import Cancelled

    photo, folder = tmp_path / "photo.png", tmp_path / "painted"
    writing.write_png(photo, half_textured(160, 200))
    assert main(["paint", str(photo), "-o", str(folder), "-q", "--seed", "3", "--strokes-to-lay"]) == 0
    heard = []
    lay_file(folder / "strokes.json", photo, tmp_path / "laid", progress=lambda f, m: heard.append((f, m)))
    fractions = [f for f, _ in heard]
    laid = [m for _, m in heard if m.startswith("Laid ")]
    strokes = json.loads((folder / "report.json").read_text())["strokes"]
    assert fractions == sorted(fractions) and len(laid) >= 2 and laid[-1] == f"Laid {strokes} of {strokes} strokes"
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("the user's own file\n")
    heard.clear()

    def cancel():
        return any(m.startswith("Laid ") for _, m in heard)

    with pytest.raises(Cancelled) as stopped:
        lay_file(folder / "strokes.json", photo, out, progress=lambda f, m: heard.append((f, m)), cancel=cancel)
    one_sentence(str(stopped.value))
    assert sum(m.startswith("Laid ") for _, m in heard) == 1 and heard[-1][1] != laid[-1]
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"]
