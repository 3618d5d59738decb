# SPDX-License-Identifier: GPL-3.0-or-later
"""The lighting comparison inside Blender: the render sweep of the canvas with and without relief
(``compare``), the Render Comparison operator (``ops_compare``) and the whole run from a command line
(``compare_command``, shared by ``blender --command paint_relief compare`` and sample_scenes/compare.py)."""
