# SPDX-License-Identifier: GPL-3.0-or-later
"""Model files opened as a user opens them: imported by Blender's own importer for the file's extension
(glTF 2.0 .glb and .gltf, Wavefront .obj, Autodesk .fbx) into an empty scene.

    objects = open_model(path)      # the imported mesh objects, in name order

A file of another extension, a missing file or one the importer cannot read raises ``ModelError`` whose
message is one sentence naming the file.
"""

from pathlib import Path

IMPORTERS = {
    ".glb": ("glTF", "io_scene_gltf2", ("import_scene", "gltf")),
    ".gltf": ("glTF", "io_scene_gltf2", ("import_scene", "gltf")),
    ".obj": ("OBJ", None, ("wm", "obj_import")),
    ".fbx": ("FBX", "io_scene_fbx", ("import_scene", "fbx")),
}
"""Extension: (the format's name, the importer's add-on or None when it is built in, the operator)."""
MODEL_EXTENSIONS = tuple(IMPORTERS)


class ModelError(Exception):
    """A model file that cannot be opened: the message is one sentence naming it."""


def is_model(path):
    """Whether ``path`` names a model file by its extension (.glb, .gltf, .obj, .fbx; any case)."""
    return Path(path).suffix.lower() in IMPORTERS


def open_model(path):
    """Empty the scene (Blender's home file, without its objects) and import the model file ``path`` with
    Blender's importer for its extension; return the imported mesh objects, sorted by name."""
    import bpy

    path = Path(path)
    kind = IMPORTERS.get(path.suffix.lower())
    if kind is None:
        raise ModelError(f"The model {path} is no file Blender imports here: give a .glb, .gltf, .obj or .fbx "
                         f"file, or a .blend scene.")
    if not path.is_file():
        raise ModelError(f"The model {path} does not exist.")
    name, addon, (category, operator) = kind
    bpy.ops.wm.read_homefile(use_empty=True)
    if addon is not None:
        import addon_utils

        loaded, enabled = addon_utils.check(addon)
        if not enabled and addon_utils.enable(addon, default_set=False) is None:
            raise ModelError(f"Blender {bpy.app.version_string} has no {name} importer (the add-on {addon}), so "
                             f"it cannot open the model {path}.")
    before = set(bpy.data.objects)
    try:
        result = getattr(getattr(bpy.ops, category), operator)(filepath=str(path.resolve()))
    except Exception:   # the importer's own error, often a traceback of its insides
        result = None
    if result is None or "FINISHED" not in result:
        raise ModelError(f"Blender's {name} importer cannot read the model {path}: it is no {name} file, or a "
                         f"damaged one.")
    meshes = [obj for obj in bpy.data.objects if obj not in before and obj.type == "MESH"]
    if not meshes:
        raise ModelError(f"The model {path} holds no mesh.")
    return sorted(meshes, key=lambda obj: obj.name)
