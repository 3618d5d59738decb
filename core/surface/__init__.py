"""Painting on objects: a mesh's texture painted in its UV space (ALGORITHM §10).

``islands``: which UV island each texel shows, each island's texel density
(how many metres a texel spans on the surface) and paint bled past the
islands' borders. ``texture``: the texture painted island by island, each
from its own texels alone, with strokes of one size in millimetres on the
surface, and each island's figures for the report.
"""
