# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared by the Blender check scripts: record each check's findings or its traceback."""

import traceback

RESULTS = {}


def check(function):
    """Run one check now, recording what it returns (or its traceback) under its name."""
    try:
        RESULTS[function.__name__] = function()
    except Exception:
        RESULTS[function.__name__] = {"exception": traceback.format_exc()}
    return function
