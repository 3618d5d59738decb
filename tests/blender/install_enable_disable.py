# SPDX-License-Identifier: GPL-3.0-or-later
"""Install the built Paint Relief zip into Blender, then enable, disable, enable.

Run in its own process (``bpy`` can be imported once per process), with
``BLENDER_USER_RESOURCES`` pointing at a throw-away folder so nothing lands
in a real user profile::

    BLENDER_USER_RESOURCES=/tmp/x python tests/blender/install_enable_disable.py dist/paint_relief-0.1.0.zip

Exits 1 with a one-line reason on the first failed check; on success the last
line printed is ``OK_LINE``.
"""

import os
import sys

OK_LINE = "paint_relief extension: install, enable, disable, enable OK"
REPO = "user_default"
MODULE = "bl_ext.{:s}.paint_relief".format(REPO)
HEAVY_MODULES = ("scipy", "OpenImageIO", MODULE + ".core")


def fail(message):
    print("FAILED: " + message, file=sys.stderr)
    sys.exit(1)


def check(condition, message):
    if not condition:
        fail(message)


# Every class object the extension has defined so far (a re-enable may reload modules).
SEEN_CLASSES = set()


def extension_classes():
    """Return the classes the loaded ``addon`` modules declare, remembering them."""
    classes = set()
    for name in ("settings.properties", "painting.ops_paint", "scene.ops_scene", "panels"):
        module = sys.modules.get("{:s}.addon.{:s}".format(MODULE, name))
        if module is not None:
            classes.update(module.classes)
    SEEN_CLASSES.update(classes)
    return classes


def registered(bpy):
    """Return which parts of the extension Blender currently has registered."""
    classes = extension_classes()
    return {
        "enabled": MODULE in bpy.context.preferences.addons,
        "panel": hasattr(bpy.types, "VIEW3D_PT_paint_relief"),
        "operators": all(hasattr(bpy.types, name) for name in (
            "PAINT_RELIEF_OT_paint", "PAINT_RELIEF_OT_build_canvas",
            "PAINT_RELIEF_OT_add_lights", "PAINT_RELIEF_OT_add_camera")),
        "classes": bool(classes) and all(cls.is_registered for cls in classes),
        "any class": any(cls.is_registered for cls in SEEN_CLASSES),
        "scene property": "paint_relief" in bpy.types.Scene.bl_rna.properties,
    }


def check_all(bpy, expected, when):
    state = registered(bpy)
    wrong = sorted(name for name, present in state.items() if present != expected)
    check(not wrong, "{:s}: expected {:s} to be {:s}; registered: {!r}".format(
        when, ", ".join(wrong), "registered" if expected else "gone", state))


def main(zip_path):
    user_resources = os.environ.get("BLENDER_USER_RESOURCES", "")
    check(user_resources, "BLENDER_USER_RESOURCES is not set: refusing to install into a real user profile")
    check(os.path.isfile(zip_path), "{:s}: no such package".format(zip_path))

    import bpy

    check(REPO in {repo.module for repo in bpy.context.preferences.extensions.repos},
          "Blender has no {!r} extension repository".format(REPO))
    check(not registered(bpy)["enabled"], "{:s} is enabled before it was installed".format(MODULE))

    result = bpy.ops.extensions.package_install_files(
        filepath=os.path.abspath(zip_path), repo=REPO, enable_on_install=True)
    check(result == {"FINISHED"}, "package_install_files returned {!r}".format(result))
    check_all(bpy, True, "after install")

    # Installed under the temporary user folder, not in a real profile.
    package = sys.modules[MODULE]
    check(os.path.realpath(package.__file__).startswith(os.path.realpath(user_resources)),
          "{:s} was installed to {:s}, outside BLENDER_USER_RESOURCES".format(MODULE, package.__file__))

    # Enabling imports nothing heavy: the painter loads only when an operator runs.
    loaded = [name for name in HEAVY_MODULES if name in sys.modules]
    check(not loaded, "enabling the extension imported {:s}".format(", ".join(loaded)))

    # The settings work; an unsaved file paints into the preferences' folder, never the extension's user folder.
    scene = bpy.context.scene
    scene.paint_relief.image_path = "//photo.png"
    check(scene.paint_relief.image_path == "//photo.png", "scene.paint_relief.image_path did not keep its value")
    properties = sys.modules[MODULE + ".addon.settings.properties"]
    chosen = os.path.join(user_resources, "chosen")
    bpy.context.preferences.addons[MODULE].preferences.output_dir = chosen
    out_dir = properties.output_dir(bpy.context)
    check(out_dir == os.path.join(chosen, "photo_001"),
          "the first painting of photo.png should go to {!r}, not {!r}".format(os.path.join(chosen, "photo_001"),
                                                                                 out_dir))
    extension_folder = bpy.utils.extension_path_user(MODULE, create=False)
    check(not out_dir.startswith(extension_folder), "paintings must not go to the extension's user folder")

    result = bpy.ops.preferences.addon_disable(module=MODULE)
    check(result == {"FINISHED"}, "addon_disable returned {!r}".format(result))
    check_all(bpy, False, "after disable")

    result = bpy.ops.preferences.addon_enable(module=MODULE)
    check(result == {"FINISHED"}, "addon_enable returned {!r}".format(result))
    check_all(bpy, True, "after enabling again")
    check(scene.paint_relief.output_dir == "", "scene.paint_relief.output_dir should default to empty")

    result = bpy.ops.preferences.addon_disable(module=MODULE)
    check(result == {"FINISHED"}, "second addon_disable returned {!r}".format(result))
    check_all(bpy, False, "after the second disable")

    print(OK_LINE, flush=True)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        fail("usage: install_enable_disable.py PACKAGE.zip")
    main(sys.argv[1])
