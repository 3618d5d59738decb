# SPDX-License-Identifier: GPL-3.0-or-later
"""The relit painted film inside Blender: every frame of the animated canvas rendered under a raking light, and
the side-by-side movie (``relit``), and the whole run from a command line (``film_command``, shared by
``blender --command paint_relief animate`` and sample_scenes/animate.py)."""
