# SPDX-License-Identifier: GPL-3.0-or-later
"""The painting's strokes in Blender: a Grease Pencil object of them, and its strokes laid again into relief."""
