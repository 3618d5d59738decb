"""Files: everything that touches the disk.

Reading photographs, masks and EXR maps (``reading``), writing EXR, PNG
and JSON (``writing``) and what the two share (``image_files``), the
painting's folder of maps and its report (``export``), its stroke list
strokes.json (``stroke_file``) and that list as SVG (``svg``), the all-or-nothing
commit of a folder's outputs (``staging``, with its folder lock and signal
handling), checks of a painted folder's maps (``maps``), the memory and
size budget of an input (``budget``), the frames of a sequence
(``frames``), the lives of a sequence's strokes (``lives``), where each
painting's folder goes (``folders``) and quieting the image libraries' own
messages (``quiet``).

``import core.files`` is light: the public functions below load their module
(and NumPy, OpenImageIO) on first use, so ``core.files.folders`` serves the
extension before the painter's libraries are loaded.
"""

from ..lazy import lazy_names

# {public name: the module of this package that defines it}
_HOMES = {
    "check": "budget", "check_bomb": "budget", "check_stroke_sizes": "budget", "estimate_bytes": "budget",
    "parse_size": "budget",
    "PAINTING_FILES": "export", "write_painting": "export",
    "check_maps": "maps", "check_painting": "maps",
    "probe": "reading", "read_exr": "reading", "read_gray": "reading", "read_image": "reading",
    "output_folder": "staging", "recover": "staging", "settle": "staging", "staged_outputs": "staging",
    "write_exr": "writing", "write_json": "writing", "write_png": "writing", "write_text": "writing",
    "folder_stem": "folders", "next_painting_folder": "folders", "painting_folders": "folders",
}

__all__ = list(_HOMES)

__getattr__, __dir__ = lazy_names(__name__, _HOMES)
