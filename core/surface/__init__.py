"""Painting on objects: a mesh's texture painted in its UV space (ALGORITHM §10).

``mesh``: a mesh's triangles (from an OBJ file). ``islands``: which UV island
each texel shows, each island's texel density (how many metres a texel spans
on the surface) and paint bled past the islands' borders. ``seams``: the
texture's steps across UV seams and inner edges, measured on the surface.
``apron``: the surface beyond each seam unfolded into an island's UV frame
(the chart maps), the island's apron and the paint carried back over the
seam. ``texture``: the texture painted island by island, with strokes of
one size in millimetres on the surface that run on across the seams, and
each island's figures for the report.
"""
