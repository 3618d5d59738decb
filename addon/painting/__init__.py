# SPDX-License-Identifier: GPL-3.0-or-later
"""Painting a photograph into maps from Blender: the Paint operator (``ops_paint``), one paint at a time per
scene (``jobs``) and images dropped on the viewport as the picture to paint (``dropped``)."""
