# SPDX-License-Identifier: GPL-3.0-or-later
"""What the shipped-package scripts (flow.py, shot.py) share: the extension's module name, the findings each
step records and the way an operator is called headless. Imported by those scripts as a sibling module; nothing of
the product's checkout is imported."""

import traceback

REPO = "user_default"
MODULE = "bl_ext.{}.paint_relief".format(REPO)
RESULTS = {}
"""Each step's findings under its name (a step that raises records its traceback), printed as ``RESULTS <json>``."""


def step(function):
    """Run ``function`` now and record what it returns (or its traceback) under its name."""
    try:
        RESULTS[function.__name__] = function()
    except Exception:
        RESULTS[function.__name__] = {"exception": traceback.format_exc()}
    return function


def run_op(op, **kwargs):
    """Call an operator; return (sorted result or None, error text)."""
    try:
        return sorted(op(**kwargs)), ""
    except RuntimeError as error:  # an ERROR report raises in background mode
        return None, str(error)
