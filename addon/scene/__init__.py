# SPDX-License-Identifier: GPL-3.0-or-later
"""What builds and changes the Blender scene: the painted canvas (``canvas``) with its maps as images (``maps``)
and its material (``material``), the animated canvas of a painted sequence (``animated``), its camera
(``camera``), its lights and world (``lighting``), and the operators that stage them (``ops_scene``: Build
Canvas, Add Lights, Add Camera, Reload Maps, Add > Paint Relief Canvas)."""
