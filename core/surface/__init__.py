"""Painting on objects: a mesh's texture painted in its UV space (ALGORITHM §10).

``islands``: which UV island each texel shows, each island's texel density
(how many metres a texel spans on the surface) and paint bled past the
islands' borders.
"""
