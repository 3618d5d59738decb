# SPDX-License-Identifier: GPL-3.0-or-later
"""What the user sets: the scene's settings (``properties``, ``scene.paint_relief``), the add-on's preferences
(``preferences``) and presets of the painter's settings (``presets``)."""
