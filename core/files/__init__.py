"""Files: everything that touches the disk.

Reading photographs, masks and EXR maps (``reading``), writing EXR, PNG
and JSON (``writing``) and what the two share (``image_files``), the
painting's folder of maps and its report (``export``), the all-or-nothing
commit of a folder's outputs (``staging``, with its folder lock and signal
handling), checks of a painted folder's maps (``maps``), the memory and
size budget of an input (``budget``), the frames of a sequence
(``frames``), the lives of a sequence's strokes (``lives``) and quieting
the image libraries' own messages (``quiet``).
"""

from .budget import check, check_bomb, check_stroke_sizes, estimate_bytes, parse_size
from .export import PAINTING_FILES, write_painting
from .maps import check_maps, check_painting
from .reading import probe, read_exr, read_gray, read_image
from .staging import output_folder, recover, settle, staged_outputs
from .writing import write_exr, write_json, write_png, write_text

__all__ = [
    "check", "check_bomb", "check_stroke_sizes", "estimate_bytes", "parse_size",
    "PAINTING_FILES", "write_painting",
    "probe", "read_exr", "read_gray", "read_image", "write_exr", "write_json", "write_png", "write_text",
    "check_maps", "check_painting",
    "output_folder", "recover", "settle", "staged_outputs",
]
