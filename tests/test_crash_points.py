"""The crash matrices of tests/crash_points.py under pytest: a still, a shot, a damaged shot's repair, a batch and
the farm's commit, each crashed after every one of its write boundaries (one run per boundary), read as readers read
it, and run again to the bytes of a run never stopped with nothing left behind."""

import pytest
from crash_points import MATRICES, crash_matrix


@pytest.mark.crash_matrix
@pytest.mark.parametrize("matrix", [pytest.param(m, id=m.name, marks=[pytest.mark.cluster] if m.cluster else [])
                                    for m in MATRICES])
def test_every_crash_point_goes_on_to_the_bytes_of_a_run_never_stopped(tmp_path, matrix):
    failures = crash_matrix(matrix, tmp_path)
    assert not failures, f"{len(failures)} crash points fall short:\n" + "\n".join(failures[:20])
