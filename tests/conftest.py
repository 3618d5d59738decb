"""Test collection: the shipped-package tests run only when given a built package (make test-shipped)."""

import os

# tests/shipped/ drives the extension installed from a zip (PAINT_RELIEF_ZIP) in bpy-only environments.
collect_ignore = [] if os.environ.get("PAINT_RELIEF_ZIP") else ["shipped"]
