"""The relit film's file names: one rule for the film's renders (the extension's ``relit/``) and its figures
(``paper/``, ``side_by_side/``).

Only the standard library is used, so Blender imports this module without
loading NumPy.
"""


def frame_file(number: int) -> str:
    """"0016.png": a film frame's file name, the frame number zero-padded to 4 digits."""
    return f"{int(number):04d}.png"
