# SPDX-License-Identifier: GPL-3.0-or-later
"""Paint Object: the active mesh's texture painted in its UV space and its relief on the object itself
(``surface``: the mesh's triangles and its texture's source; ``object_material``: the painted material and the
way back to the original material; ``relief``: the relief modifiers; ``ops_object``: the operators)."""
