"""The shot's fault catalogue (tests/shot_faults.py) under pytest: each case one test, held to the catalogue's
standard (one sentence or the whole shot, the folder as it was or complete frames only, and the same bytes as a
run never stopped once the cause is gone)."""

import pytest
import shot_faults
from shot_faults import CASES, Place, Skipped, run_case


@pytest.fixture(scope="module")
def place(tmp_path_factory):
    return Place(tmp_path_factory.mktemp("shot_faults"))


@pytest.mark.parametrize("case", [pytest.param(c, id=c.id, marks=[pytest.mark.cluster] if c.cluster else [])
                                  for c in CASES])
def test_the_case_meets_the_standard(place, case):
    try:
        run_case(place, case)
    except Skipped as why:
        pytest.skip(str(why))


def test_the_catalogue_holds_at_least_sixty_cases_in_every_group():
    groups = {case.group for case in CASES}
    assert len(CASES) >= 60 and groups == {"frames", "output", "kills", "damage", "disk", "batch", "farm"}
    assert len({case.id for case in CASES}) == len(CASES), "two cases of one name"
    assert shot_faults.main(["--list"]) == 0
