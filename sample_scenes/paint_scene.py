"""Paint a whole scene with Paint Scene (every mesh the camera sees, one stroke size), then film its animation
four ways: the painted world relit by the scene's lights, the scene as it was, each object showing the paper's
2-D lighting, and the original film painted as a 2-D shot.

    blender -b --python-exit-code 1 --python sample_scenes/paint_scene.py -- SCENE.blend -o OUTDIR \\
        [--frames A-B] [--texture-size N] [--samples S] [--resolution-percentage P] [--seed N] \\
        [--relief DISPLACE|CYCLES_ADAPTIVE|NORMAL_MAP] [--workers N | --scheduler tcp://HOST:PORT]
    .venv/bin/python sample_scenes/paint_scene.py SCENE.blend -o OUTDIR [options]

Steps, each printed with its time:

1. ``scene``: SCENE.blend is opened and saved as it is as ``OUTDIR/original.blend``; ``--frames`` and
   ``--resolution-percentage`` set the scene's frame range and render size;
2. ``paint``: Paint Scene paints every mesh object the scene's camera sees over the frame range into
   ``OUTDIR/maps`` (a folder per texture, and ``paint_scene.json``), with the stroke widths read from the
   camera (``addon/objects/ops_scene_paint.py``), and gives each object its painted material and relief; an
   object it cannot paint is named in one sentence on stderr and the others are painted. With ``--workers N``
   the textures are painted on a local Dask cluster of N worker processes, with ``--scheduler`` on the cluster
   whose scheduler is there (its workers see the sources and OUTDIR at the same paths), each texture one task,
   with the same bytes (``core.paint_objects``' farm); without Dask distributed either is refused in one
   sentence before anything is painted;
3. ``renders``: the frame range rendered by Cycles with the Vector pass, with the painted world
   (``renders/relit``), the original materials (``renders/original``) and the paper's Eq. 6-7 lighting of each
   texture as emission (``renders/paper``), as multilayer EXR;
4. ``shot``: the original film painted as a 2-D shot by ``core sequence`` with its Vector pass
   (``shot/``, painted anew as ``shot.partial/`` and put in the place of an earlier one once whole);
5. ``figures``: the four films as PNG frames in ``film/relit``, ``film/original``, ``film/paper`` and
   ``film/shot``, and ``film/side_by_side`` (original | relit above, paper | shot below); ``scene.json`` with
   each film's warping error from frame to frame by the Vector pass (the relit and paper films by their own
   renders', the original and the shot by the original render's), the stroke widths and how they were chosen,
   each object's figures, what was refused, and the seconds of every stage;
6. ``blend``: ``OUTDIR/scene.blend``, the painted scene, saved at the frame it was opened at.

Run again into the same OUTDIR, Paint Scene keeps every texture whose painting is there (same sources, mesh
and settings) and paints only what is missing or changed; a run stopped while painting keeps the textures
finished. A bad input ends with one sentence on stderr and exit code 1 (2 for a malformed command line, 130
for Ctrl-C outside the painter).
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import json
import shutil
import signal
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from extension import extension_package  # noqa: E402 (the launcher's folder first)
from paint_object import Failure, paper_material, render_film  # noqa: E402

FILMS = ("relit", "original", "paper", "shot")


def arguments(argv):
    parser = argparse.ArgumentParser(prog="paint_scene.py", description=__doc__.splitlines()[0])
    parser.add_argument("scene", type=Path, metavar="SCENE.blend", help="the animated scene")
    parser.add_argument("-o", "--output", type=Path, required=True, metavar="OUTDIR", help="folder for the results")
    parser.add_argument("--frames", default=None, metavar="A-B",
                        help="the frames to paint for and render (default: the scene's frame range)")
    parser.add_argument("--texture-size", type=int, default=1024, metavar="N",
                        help="texels a side of each painted texture, 64 to 16384 (default 1024)")
    parser.add_argument("--samples", type=int, default=16, metavar="S", help="Cycles samples (default 16)")
    parser.add_argument("--resolution-percentage", type=int, default=None, metavar="P",
                        help="the render's size in percent of the scene's resolution (default: the scene's)")
    parser.add_argument("--seed", type=int, default=0, help="the painter's seed (default 0)")
    parser.add_argument("--relief", default="DISPLACE", choices=("DISPLACE", "CYCLES_ADAPTIVE", "NORMAL_MAP"),
                        help="how the paint's thickness shows on the objects, as the panel's Relief")
    farm = parser.add_mutually_exclusive_group()
    farm.add_argument("--workers", type=int, default=None, metavar="N",
                      help="paint the textures on a local Dask cluster of N worker processes (needs Dask)")
    farm.add_argument("--scheduler", default=None, metavar="ADDRESS",
                      help="paint the textures on the Dask cluster whose scheduler is at ADDRESS (tcp://host:8786); "
                           "its workers must see the sources and OUTDIR at the same paths")
    args = parser.parse_args(argv[argv.index("--") + 1:] if "--" in argv else argv[1:])
    if args.samples < 1 or (args.resolution_percentage is not None and not 1 <= args.resolution_percentage <= 100):
        parser.error("give at least 1 sample and a resolution percentage from 1 to 100")
    if args.frames is not None:
        try:
            first, last = (int(part) for part in args.frames.split("-"))
        except ValueError:
            parser.error(f"--frames must be two frame numbers as A-B, got {args.frames!r}")
        if last < first:
            parser.error(f"--frames {args.frames} ends before it starts")
        args.frames = first, last
    return args


def open_scene(args):
    """Open SCENE.blend and set the frame range and render size the options give; returns the scene."""
    import bpy

    if args.scene.suffix.lower() != ".blend" or not args.scene.is_file():
        raise Failure(f"The scene {args.scene} is no .blend file: give an animated scene saved by Blender.")
    try:
        bpy.ops.wm.open_mainfile(filepath=str(args.scene.resolve()))
    except RuntimeError:
        raise Failure(f"Blender {bpy.app.version_string} cannot open the scene {args.scene}: it is not a .blend "
                      f"file, or one this Blender cannot read.") from None
    scene = bpy.context.scene
    if scene.camera is None:
        raise Failure(f"The scene {args.scene} has no camera to film it with: give it one.")
    if args.frames is not None:
        scene.frame_start, scene.frame_end = args.frames
    if args.resolution_percentage is not None:
        scene.render.resolution_percentage = args.resolution_percentage
    return scene


def film_settings(scene, samples):
    """Cycles on the CPU with ``samples`` samples, the Vector pass (motion blur off, so Cycles writes it), the
    Standard view transform and multilayer EXR frames."""
    import bpy

    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False
    scene.render.use_motion_blur = False
    scene.view_settings.view_transform = "Standard"
    bpy.context.view_layer.use_pass_vector = True
    image = scene.render.image_settings
    if hasattr(image, "media_type"):
        image.media_type = "MULTI_LAYER_IMAGE"
    image.file_format = "OPEN_EXR_MULTILAYER"
    image.color_depth = "32"


def scene_farm(args, package):
    """Hand ``--workers`` or ``--scheduler`` to Paint Scene (``ops_scene_paint.FARM``), checked: ParameterError (one
    sentence) for a wrong one, or when Dask distributed is missing here (as inside Blender without it)."""
    if args.workers is None and args.scheduler is None:
        return
    cluster = importlib.import_module(package.__name__ + ".core.farm.cluster")
    farm = cluster.Farm(args.workers, args.scheduler)
    farm.validate()
    try:        # looked for, not imported: Dask loaded before the bakes changes how Blender compresses them
        missing = importlib.util.find_spec("distributed") is None
    except (ImportError, ValueError):
        missing = True
    if missing:
        cluster.import_distributed()
    importlib.import_module(package.__name__ + ".addon.objects.ops_scene_paint").FARM = farm


def paint(args, maps):
    """Paint Scene into ``maps`` through its operator, as the panel does; returns its paint_scene.json."""
    import bpy

    settings = bpy.context.scene.paint_relief
    settings.scene_output_dir = str(maps)
    settings.scene_selected_only = False
    settings.seed = args.seed
    settings.object_relief = args.relief
    try:
        result = bpy.ops.paint_relief.paint_scene(texture_size=args.texture_size)
    except RuntimeError as error:
        if "KeyboardInterrupt" in str(error):
            raise KeyboardInterrupt from None
        text = " ".join(str(error).split())
        raise Failure(text[len("Error: "):] if text.startswith("Error: ") else text) from None
    if "FINISHED" not in result:
        raise Failure("Paint Scene did not finish.")
    return json.loads((maps / "paint_scene.json").read_text())


def show_paper(objects, maps, painted, object_material, surface):
    """Give each painted object a material showing its texture's paper lighting (``lit_paper.png``)."""
    made = {}
    for name, entry in painted.items():
        obj = objects[name]
        atlas = obj.data.uv_layers.get(object_material.ATLAS_UV_MAP)
        uv_map = (atlas or obj.data.uv_layers[surface.uv_map_name(obj)]).name
        key = (entry["folder"], uv_map)
        if key not in made:
            made[key] = paper_material(maps / entry["folder"], uv_map)
        for slot in obj.material_slots:
            slot.material = made[key]


def width_agreement(reports, stroke_mm):
    """How far the stroke widths laid on the textures of ``reports`` ({folder: report.json}) stray from one
    another: {"per_width": for each width of ``stroke_mm``, the widest over the narrowest (mm) of that width as
    laid on every island of every texture, "worst": the largest, "islands": how many}. An island lays width w
    as a whole number of its texels, at least 2 (``island_sizes``): round(w / texel) texels of texel mm."""
    laid = [[max(2, round(width / island["texel_mm"])) * island["texel_mm"] for width in stroke_mm]
            for report in reports.values() for island in report.get("islands", [])]
    ratios = [max(column) / min(column) for column in zip(*laid, strict=True)] if laid else []
    return {"per_width": [round(r, 3) for r in ratios], "worst": round(max(ratios), 3) if ratios else None,
            "islands": len(laid)}


def film_figures(core, films, shot_frames, out):
    """Write the four films' PNG frames and the side-by-side frames into ``out``/film; return each film's warping
    error from frame to frame by the Vector pass (relit and paper: their own renders'; original and shot: the
    original render's), with their means and ratios to the original's."""
    import numpy as np

    reading = importlib.import_module(core.__name__ + ".files.reading")
    writing = importlib.import_module(core.__name__ + ".files.writing")
    frames_module = importlib.import_module(core.__name__ + ".files.frames")
    motion = importlib.import_module(core.__name__ + ".motion")
    pictures = {name: [reading.read_image(path) for path in paths] for name, paths in films.items()}
    pictures["shot"] = [reading.read_image(path) for path in shot_frames]
    for name, frames in pictures.items():
        (out / "film" / name).mkdir(parents=True, exist_ok=True)
        for number, picture in enumerate(frames, 1):
            writing.write_png(out / "film" / name / f"{number:04d}.png", picture)
    (out / "film" / "side_by_side").mkdir(parents=True, exist_ok=True)
    for number in range(len(pictures["relit"])):
        top = np.concatenate([pictures["original"][number], pictures["relit"][number]], axis=1)
        bottom = np.concatenate([pictures["paper"][number], pictures["shot"][number]], axis=1)
        writing.write_png(out / "film" / "side_by_side" / f"{number + 1:04d}.png", np.concatenate([top, bottom]))
    by_pass = {"relit": "relit", "paper": "paper", "original": "original", "shot": "original"}
    vectors = {name: [frames_module.read_vector_pass(path) for path in films[name]] for name in ("relit", "paper",
                                                                                                 "original")}
    errors = {name: [] for name in pictures}
    for k in range(len(pictures["relit"]) - 1):
        for name, frames in pictures.items():
            forward, backward = motion.motion_pair(vectors[by_pass[name]][k], vectors[by_pass[name]][k + 1])
            visible = motion.visible_in_both(forward, backward)
            errors[name].append(float(motion.warping_error(frames[k], frames[k + 1], forward, visible)))
    means = {name: float(np.nanmean(values)) if values else None for name, values in errors.items()}
    original = means["original"]
    return {"warping_error": errors, "mean_warping_error": means,
            "over_original": {name: (value / original if original else None) for name, value in means.items()},
            "vector_pass_of": by_pass}


def main(argv):
    args = arguments(argv)
    started, times = time.perf_counter(), []
    out = args.output.resolve()
    created = not out.exists()

    def step(name):
        signal.signal(signal.SIGINT, signal.default_int_handler)    # Ctrl-C is this script's in every step
        times.append((name, time.perf_counter()))
        print(f"[{name}]", flush=True)

    partial = out / "original.partial.blend"
    try:
        step("scene")
        import bpy

        scene = open_scene(args)
        shown_frame = scene.frame_current
        if out.exists() and not out.is_dir():
            raise Failure(f"Cannot write to output folder {out}: a file of that name is in the way.")
        if not 64 <= args.texture_size <= 16384:
            raise Failure(f"The texture size must be a whole number of texels from 64 to 16384, got "
                          f"{args.texture_size}.")
        out.mkdir(parents=True, exist_ok=True)
        bpy.ops.wm.save_as_mainfile(filepath=str(partial), copy=True, check_existing=False)
        package = extension_package("PAINT_RELIEF_OT_paint_scene")
        if not hasattr(bpy.types, "PAINT_RELIEF_OT_paint_scene"):
            package.register()
        core = importlib.import_module(package.__name__ + ".core")
        object_material = importlib.import_module(package.__name__ + ".addon.objects.object_material")
        surface = importlib.import_module(package.__name__ + ".addon.objects.surface")
        ops_paint = importlib.import_module(package.__name__ + ".addon.painting.ops_paint")
        scene_farm(args, package)

        step("paint")
        painted_scene = paint(args, out / "maps")
        for sentence in painted_scene["refused"].values():
            sys.stderr.write(f"{sentence}\n")
        objects = {name: scene.objects[name] for name in painted_scene["painted"]}

        step("renders")
        film_settings(scene, args.samples)
        films = {"relit": render_film(scene, out / "renders" / "relit")}
        for obj in objects.values():
            object_material.show_painting(obj, False)
        films["original"] = render_film(scene, out / "renders" / "original")
        show_paper(objects, out / "maps", painted_scene["painted"], object_material, surface)
        films["paper"] = render_film(scene, out / "renders" / "paper")
        for obj in objects.values():
            object_material.show_painting(obj, True)

        step("shot")
        params = ops_paint.params_from_settings(scene.paint_relief).validate_shot()
        # The films are rendered anew each run, so the shot is painted anew, beside the earlier one until done.
        partial_shot = out / "shot.partial"
        shutil.rmtree(partial_shot, ignore_errors=True)
        core.paint_sequence_files([str(path) for path in films["original"]], partial_shot, params)
        shutil.rmtree(out / "shot", ignore_errors=True)
        partial_shot.replace(out / "shot")
        shot_frames = sorted((out / "shot").glob("painting_*.png"))

        step("figures")
        statistics = film_figures(core, films, shot_frames, out)
        reports = {folder: json.loads((out / "maps" / folder / "report.json").read_text())
                   for folder in painted_scene["paintings"]}
        seconds = dict(zip((name for name, _ in times), (b - a for (_, a), (_, b) in zip(times, times[1:] + [
            ("now", time.perf_counter())], strict=True)), strict=True))
        summary = {"scene": scene.name, "frames": [scene.frame_start, scene.frame_end],
                   "render_px": [int(scene.render.resolution_x * scene.render.resolution_percentage / 100),
                                 int(scene.render.resolution_y * scene.render.resolution_percentage / 100)],
                   "texture_size": args.texture_size, "samples": args.samples, "relief": args.relief,
                   "stroke_mm": painted_scene["stroke_mm"], "stroke_mm_from": painted_scene["stroke_mm_from"],
                   "stroke_width_agreement": width_agreement(reports, painted_scene["stroke_mm"]),
                   "objects": {name: dict(entry, strokes=reports[entry["folder"]].get("strokes"),
                                          islands=len(reports[entry["folder"]].get("islands", [])))
                               for name, entry in painted_scene["painted"].items()},
                   "refused": painted_scene["refused"], "paintings": painted_scene["paintings"],
                   "paint_seconds": painted_scene["seconds"], **statistics,
                   "seconds": {name: round(value, 2) for name, value in seconds.items()}}
        (out / "scene.json").write_text(json.dumps(summary, indent=2) + "\n")

        step("blend")
        scene.frame_set(shown_frame)
        bpy.ops.wm.save_as_mainfile(filepath=str(out / "scene.blend"), check_existing=False)
        partial.replace(out / "original.blend")
    except KeyboardInterrupt:
        partial.unlink(missing_ok=True)
        name = times[-1][0] if times else "scene"
        if created and name in ("scene", "paint") and not (out / "maps").exists():
            shutil.rmtree(out, ignore_errors=True)
        sys.stderr.write(f"Interrupted (Ctrl-C) in the {name} step: {out} keeps the textures painted so far, and "
                         f"running again goes on with them.\n")
        return 130
    except Exception as error:
        partial.unlink(missing_ok=True)
        if created and not (out / "maps").exists():
            shutil.rmtree(out, ignore_errors=True)
        if type(error).__name__ not in ("Failure", "InputError", "OutputError", "ParameterError", "Cancelled"):
            raise
        sys.stderr.write(f"{error}\n")
        return 1
    times.append(("end", time.perf_counter()))
    for (name, start), (_, stop) in zip(times, times[1:], strict=False):
        print(f"    {name:<8} {stop - start:7.1f} s")
    print(f"    {'total':<8} {time.perf_counter() - started:7.1f} s")
    means = summary["mean_warping_error"]
    print("Mean warping error from frame to frame: " + ", ".join(f"{name} {means[name]:.5f}" for name in FILMS)
          + "; relit / original {:.2f}".format(summary["over_original"]["relit"] or float("nan")))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
