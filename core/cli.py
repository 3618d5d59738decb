"""Command line: ``python -m core analyze INPUT -o OUTDIR`` and friends.

Every failure caused by input or settings ends with one sentence on stderr
and a non-zero exit; outputs are written only after all work succeeded,
each through a temporary name.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import List, Optional

from .analysis.run import analyze
from .errors import Cancelled, PaintReliefError, ParameterError
from .figures.visualize import orientation_picture, partition_overlay
from .files import budget, quiet, reading, signals, writing
from .files.staging import output_folder
from .params import STYLE_NAMES, Params, SequenceSettings, canonical_style
from .progress import ConsoleProgress
from .results import Analysis
from .version import __version__

DEFAULTS = Params()


class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one sentence on stderr (no usage block) and exit status 2."""

    def error(self, message: str) -> None:
        message = message.strip().rstrip(".")
        self.exit(2, f"paint-relief: error: {message[:1].upper() + message[1:]}; see {self.prog} --help.\n")


def _sizes(text: str) -> tuple:
    try:
        sizes = tuple(int(s) for s in text.split(",") if s.strip())
    except ValueError:
        raise argparse.ArgumentTypeError(f"sizes must be whole numbers separated by commas, got {text[:40]!r}") from None
    repeated = sorted({s for s in sizes if sizes.count(s) > 1})
    if repeated:
        raise argparse.ArgumentTypeError(f"each stroke size may be given once, got {', '.join(map(str, repeated))} "
                                         f"more than once in {text[:40]!r}")
    return sizes


def _folder(text: str) -> str:
    """An output folder's path; an empty or blank one (an unset shell variable) is refused, never the current folder."""
    if not text.strip():
        raise argparse.ArgumentTypeError("the output folder is empty, which would write into the current folder; "
                                         "name the folder (is a shell variable unset?)")
    return text


def _int(text: str) -> int:
    """A whole number of at most 40 digits (larger values cannot be valid and are not parsed)."""
    digits = text.strip().lstrip("+-")
    if not digits.isdigit():
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text[:40]!r}")
    if len(digits) > 40:
        raise argparse.ArgumentTypeError(f"expected a whole number below 2^63, got one of {len(digits)} digits")
    return int(text)


def _float(text: str) -> float:
    """A finite number; NaN and infinities are refused."""
    try:
        value = float(text)
    except ValueError:
        value = float("nan") if text.strip().lower() not in ("nan", "inf", "-inf", "infinity") else None
    if value is None or value != value or value in (float("inf"), float("-inf")):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text[:40]!r}")
    return value


def _add_run_options(p: argparse.ArgumentParser) -> None:
    """Options every painting command shares: seed, pixel limit, quiet."""
    p.add_argument("--seed", type=_int, default=DEFAULTS.seed, metavar="N",
                   help="random seed, a whole number 0 <= N < 2^63 (default: %(default)s)")
    p.add_argument("--max-memory", default=None, metavar="SIZE",
                   help="refuse runs estimated to need more memory than this, e.g. 512M or 4G "
                        "(default: the memory available)")
    p.add_argument("--max-megapixels", type=_float, default=DEFAULTS.max_megapixels, metavar="N",
                   help="refuse inputs larger than this (default: %(default)s)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress line on stderr")


def _add_analysis_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("input", help="photograph to read (PNG, JPEG, TIFF, EXR, ...)")
    p.add_argument("-o", "--output", required=True, type=_folder, metavar="OUTDIR", help="folder for the outputs (created if missing)")
    _add_partition_options(p)
    p.add_argument("--mask", metavar="PATH", help="grayscale importance mask; white areas get smaller strokes (default: none)")
    p.add_argument("--mask-strength", type=_float, default=DEFAULTS.mask_strength, metavar="K",
                   help="k in E' = E (1 + k mask) (default: %(default)s)")
    _add_run_options(p)


def _add_partition_options(p: argparse.ArgumentParser) -> None:
    """The stroke sizes and how finely detailed areas are split."""
    p.add_argument("--sizes", type=_sizes, default=DEFAULTS.stroke_sizes, metavar="64,32,16,8,4",
                   help="standard stroke widths in px at 1 megapixel, scaled with the image (default: %(default)s)")
    p.add_argument("--detail", type=_float, default=DEFAULTS.detail, metavar="X",
                   help="0..1, how finely detailed areas are split; the stop energy is T_e = 16^(1 - X) times "
                        "the energy of a detailed area of the second-smallest stroke size (default: %(default)s)")


def _add_stroke_options(p: argparse.ArgumentParser) -> None:
    """How the paper's strokes are laid: layers, brush, relief, colour, renderer, paths, details, normal map."""
    p.add_argument("--layers", type=_int, default=DEFAULTS.layers, metavar="N",
                   help="layers of strokes, each one pass over all grids (default: %(default)s)")
    p.add_argument("--brush", default=DEFAULTS.brush, metavar="flat|round|filbert|PATH",
                   help="a shipped brush or a grayscale PNG brush map, wide side across (default: %(default)s)")
    p.add_argument("--height-mode", choices=("over", "accumulate"), default=DEFAULTS.height_mode,
                   help="'over': each stroke's height covers what is below (the paper); "
                        "'accumulate': paint piles up (default: %(default)s)")
    p.add_argument("--alpha", type=_float, default=DEFAULTS.bristle_alpha, metavar="A",
                   help="weight of each bristle's own colour in Eq. 5 (default: %(default)s)")
    p.add_argument("--renderer", default=DEFAULTS.renderer, metavar="bristles|lines",
                   help="huang11 strokes: bristles (the paper's brush) or lines (solid anti-aliased "
                        "lines, Fig. 8c ablation) (default: %(default)s)")
    p.add_argument("--path-rule", default=DEFAULTS.path_rule, choices=("natural", "literal"),
                   help="how strokes stop: natural (a minimum length, the colour and turn tests at control "
                        "points, an edge test at the brush's scale) or literal (the paper read literally: "
                        "every curve sample from the anchor, for ablation) (default: %(default)s)")
    p.add_argument("--no-details", dest="detail_pass", action="store_false",
                   help="skip the detail pass that dots small highlights with the smallest brush")
    p.add_argument("--normal-map", action="store_true",
                   help="also write the height map's tangent-space normals (for renderers that shade a flat plane)")


def _add_method_options(p: argparse.ArgumentParser) -> None:
    """The painter, and the Hertzmann 1998 baseline's style and layout."""
    p.add_argument("--method", default=DEFAULTS.method, metavar="huang11|hertzmann98",
                   help="huang11: the paper's painter; hertzmann98: the Hertzmann 1998 baseline "
                        "(default: %(default)s)")
    p.add_argument("--style", default=DEFAULTS.style, metavar="impressionist|expressionist|colorist_wash|pointillist",
                   help="Hertzmann 1998 style: the baseline's settings with --method hertzmann98, its "
                        "threshold and grid with --layout hertzmann98 (colorist-wash also accepted) "
                        "(default: %(default)s)")
    p.add_argument("--layout", default=DEFAULTS.layout, metavar="paper|hertzmann98",
                   help="huang11 stroke layout: paper (importance partition) or hertzmann98 "
                        "(layered grid ablation, Fig. 8b) (default: %(default)s)")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every subcommand."""
    parser = _Parser(prog="python -m core", description="Paint Relief's painter.")
    parser.add_argument("--version", action="version", version=f"paint-relief {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    analyze_p = sub.add_parser(
        "analyze", help="reference image, importance map, canvas partition and orientation field",
        description="Write reference.png, importance.exr/.png, partition.png, orientation.png and analysis.json.")
    _add_analysis_options(analyze_p)
    analyze_p.set_defaults(run=run_analyze)

    paint_p = sub.add_parser(
        "paint", help="paint a photograph stroke by stroke and write its relief maps",
        description="Write color.exr (scene-linear RGB), height.exr, opacity.exr, orientation.exr, "
                    "painting.png, lit_paper.png, strokes.json and report.json (and normal.exr with --normal-map).")
    _add_analysis_options(paint_p)
    _add_stroke_options(paint_p)
    _add_method_options(paint_p)
    paint_p.add_argument("--strokes-to-lay", action="store_true",
                         help="record in strokes.json what laying each stroke again needs (its brush, curve and "
                              "bristle colours), so `core lay` can lay the list, edited or not: about 7x its size")
    paint_p.add_argument("--timelapse", type=_timelapse_frames, default=0, metavar="N",
                         help="also write OUTDIR/timelapse/: N frames (1 to 1000) of the painting being painted, "
                              "stroke after stroke, as a painted shot's folder (Build Canvas animates it)")
    paint_p.set_defaults(run=run_paint)
    _add_sequence_parser(sub)
    _add_batch_parser(sub)
    _add_object_parser(sub)
    _add_light_parser(sub)
    _add_svg_parser(sub)
    _add_lay_parser(sub)
    _add_experiments_parser(sub)
    return parser


def params_from_args(args: argparse.Namespace) -> Params:
    """Params from parsed options (those the subcommand has), validated."""
    fields = {"stroke_sizes": tuple(args.sizes), "detail": args.detail, "seed": args.seed,
              "max_megapixels": args.max_megapixels}
    for option, name in (("mask_strength", "mask_strength"), ("layers", "layers"), ("brush", "brush"), ("height_mode", "height_mode"),
                         ("alpha", "bristle_alpha"), ("method", "method"), ("style", "style"),
                         ("layout", "layout"), ("renderer", "renderer"), ("path_rule", "path_rule"),
                         ("detail_pass", "detail_pass")):
        if hasattr(args, option):
            fields[name] = getattr(args, option)
    if isinstance(fields.get("style"), str) and canonical_style(fields["style"]) in STYLE_NAMES:
        fields["style"] = canonical_style(fields["style"])
    return Params(**fields).validate()


def max_memory(args: argparse.Namespace):
    """The --max-memory option in bytes, or None."""
    return None if args.max_memory is None else budget.parse_size(args.max_memory)


def run_analyze(args: argparse.Namespace, progress) -> None:
    """The ``analyze`` subcommand."""
    from .api import check_input, out_of_memory, pages_notice

    params = params_from_args(args)
    check_input(args.input, params, args.mask, max_memory(args))
    pages = reading.image_count(args.input)
    if pages > 1:
        _notice(progress, pages_notice(args.input, pages))
    try:
        with output_folder(args.output) as folder:
            folder.check_names(ANALYSIS_FILES)
            image = reading.read_image(args.input, params.max_megapixels, params.canvas_colour)
            mask = reading.read_gray(args.mask, params.max_megapixels, role="mask") if args.mask else None
            analysis = analyze(image, params, mask=mask, progress=progress)
            with folder.staged() as staging:
                write_analysis(staging, analysis, params, args.input, pages)
    except MemoryError:
        raise out_of_memory(args.input) from None


def _timelapse_frames(text: str) -> int:
    """--timelapse's value: a whole number of frames from 1 to ``files.timelapse.MAX_FRAMES``."""
    from .files.timelapse import MAX_FRAMES

    try:
        frames = int(text)
    except ValueError:
        frames = None
    if frames is None or not 1 <= frames <= MAX_FRAMES:
        raise argparse.ArgumentTypeError(f"the time-lapse takes a whole number of frames from 1 to {MAX_FRAMES}, "
                                         f"got {text!r}")
    return frames


def run_paint(args: argparse.Namespace, progress) -> None:
    """The ``paint`` subcommand, with the C heap tuned for painting (this process is the painter's own)."""
    from .api import paint_file
    from .heap import reused_heap

    with reused_heap():
        paint_file(args.input, args.output, params_from_args(args), progress=progress, mask_path=args.mask,
                   max_memory=max_memory(args), normal_map=args.normal_map,
                   notice=lambda text: _notice(progress, text), strokes_to_lay=args.strokes_to_lay,
                   timelapse=args.timelapse)


def _add_files_parser(sub, name: str, summary: str, description: str, inputs: tuple,
                      output: tuple) -> argparse.ArgumentParser:
    """The parser of subcommand ``name`` that takes input files and an output folder: ``inputs`` = (dest,
    metavar, help) of its one or more inputs, ``output`` = (metavar, help) of its -o/--output folder."""
    p = sub.add_parser(name, help=summary, description=description)
    dest, metavar, inputs_help = inputs
    p.add_argument(dest, nargs="+", metavar=metavar, help=inputs_help)
    p.add_argument("-o", "--output", required=True, type=_folder, metavar=output[0], help=output[1])
    return p


def _add_shot_options(p: argparse.ArgumentParser) -> None:
    """The options of how a shot is painted (``SequenceSettings``), for `sequence` and `batch`."""
    p.add_argument("--fade-frames", type=_int, default=SequenceSettings.fade_frames, metavar="K",
                   help="frames a stroke of a shot takes to fade in when born and out when it dies "
                        "(default: %(default)s)")
    p.add_argument("--measures", action="store_true",
                   help="also measure each pair of a shot's frames' steadiness (warping errors, stillness) into its "
                        "report.json; it changes no painted byte")


def _add_sequence_parser(sub) -> None:
    p = _add_files_parser(
        sub, "sequence", "paint an image sequence with strokes that live across frames",
        "Paint a shot frame after frame, carrying the strokes by the motion (Blender's Vector pass "
        "when every frame has one, else optical flow). Writes painting_####.png, color_####.exr, "
        "height_####.exr, opacity_####.exr and orientation_####.exr per frame (normal_####.exr with "
        "--normal-map), strokes.lives and report.json. Every frame is committed whole; the same "
        "command run again resumes after the last complete frame.",
        ("input", "INPUT", "a folder of frames, a pattern with # for the frame number (render/frame_####.exr), or "
                           "frame files in order (PNG, JPEG, TIFF, EXR, Blender multilayer EXR)"),
        ("OUTDIR", "folder for the outputs (created if missing)"))
    p.add_argument("--frames", metavar="A-B", help="paint frames A to B only (A-, -B and A also work)")
    _add_shot_options(p)
    _add_partition_options(p)
    _add_stroke_options(p)
    _add_run_options(p)
    _add_farm_options(p)
    p.set_defaults(run=run_sequence)


def _add_batch_parser(sub) -> None:
    """The ``batch`` subcommand's options."""
    p = _add_files_parser(
        sub, "batch", "paint unrelated stills and shots, each into a folder of its own",
        "Paint each INPUT into OUTROOT/<name>_001 (the first free counter, as the Blender panel names a "
        "painting's folder): a still as `paint` does, a shot (a folder of frames or a pattern with #) as "
        "`sequence` does, in this process one after another or on a Dask cluster, with the same bytes. "
        "Every input is checked before any painting. Run again, it goes on where it stopped: a folder holding "
        "an input's painting whole, from the same file with the same options, is kept; a shot left partly "
        "painted goes on in its folder; a folder a stopped run left unfinished is painted into; a changed "
        "input or option is painted into the next free folder. No folder holding another painting is written "
        "into.",
        ("input", "INPUT", "still images (PNG, JPEG, TIFF, EXR, ...) and shots: folders of frames or patterns "
                           "with # for the frame number"),
        ("OUTROOT", "folder under which each painting gets its own folder (created if missing)"))
    _add_shot_options(p)
    p.add_argument("--fresh", action="store_true",
                   help="paint every input anew into the next free folder, keeping nothing an earlier run painted")
    _add_partition_options(p)
    _add_stroke_options(p)
    _add_method_options(p)
    _add_run_options(p)
    _add_farm_options(p)
    p.set_defaults(run=run_batch)


def run_batch(args: argparse.Namespace, progress) -> None:
    """The ``batch`` subcommand: one line per still or shot on stdout, "INPUT -> FOLDER", once all are painted, then
    one notice on stderr (also under --quiet) of how many folders it kept, went on with and painted."""
    from .api import KEPT, PAINTED, WENT_ON, batch_counts, paint_batch
    from .heap import reused_heap

    with reused_heap():
        reports = paint_batch(args.input, args.output, params_from_args(args), args.normal_map, progress=progress,
                              max_memory=max_memory(args), farm=farm_from_args(args),
                              settings=SequenceSettings(args.fade_frames, args.normal_map, args.measures).validate(),
                              fresh=args.fresh, notice=lambda text: _notice(progress, text))
    if progress is not None:
        progress.close()
    for source, report in zip(args.input, reports, strict=True):
        print(f"{source} -> {report['output_dir']}", flush=True)
    counts = batch_counts(reports)
    _notice(progress, f"batch: kept {counts[KEPT]}, went on with {counts[WENT_ON]}, painted {counts[PAINTED]}.")


def _widths(text: str) -> tuple:
    """Stroke widths in millimetres: positive numbers separated by commas."""
    try:
        widths = tuple(float(s) for s in text.split(",") if s.strip())
    except ValueError:
        widths = ()
    if not widths or not all(0 < w < 1e6 for w in widths):
        raise argparse.ArgumentTypeError(f"widths must be positive millimetres separated by commas, got {text[:40]!r}")
    return widths


def _extensions(text: str) -> list:
    """``--extension``: rules beyond the UV square 0..1 separated by commas (``surface.atlas.EXTENSIONS``)."""
    from .surface.atlas import EXTENSIONS

    rules = [word.strip().upper() for word in text.split(",")]
    wrong = [rule for rule in rules if rule not in EXTENSIONS]
    if wrong:
        raise argparse.ArgumentTypeError(f"each extension must be one of {', '.join(EXTENSIONS)}, got {wrong[0]!r}")
    return rules


def _add_object_parser(sub) -> None:
    """The ``object`` subcommand's options."""
    p = sub.add_parser(
        "object", help="paint a mesh's texture in its UV space, strokes of one size on the surface; or a model "
                       "file's meshes in Blender",
        usage="%(prog)s TEXTURE [TEXTURE ...] --mesh MESH.obj -o OUTDIR [options]\n"
              "       %(prog)s MODEL -o OUTDIR [--object NAME] [options]",
        description="Paint TEXTURE, the texture of the mesh MESH (a Wavefront OBJ file with texture coordinates, "
                    "positions in metres), island by island in its UV space: each UV island from its own texels, "
                    "strokes as wide in millimetres on every island. Writes the maps a still has, in UV space, and "
                    "report.json with each island's texel density and stroke widths. Several textures (one per "
                    "material) or UDIM tiles are painted as one atlas, with each one's maps written too. "
                    "Without --mesh, MODEL (a .glb, .gltf, .obj or .fbx file, or a .blend scene) is painted in "
                    "Blender by sample_scenes/paint_object.py: imported by Blender's own importer, the object "
                    "--object names painted (else every mesh object with a material), filmed on a turntable and "
                    "saved as OUTDIR/scene.blend beside OUTDIR/original.blend, the scene before painting. The "
                    "Blender is the one the environment variable PAINT_RELIEF_BLENDER names (a blender program or "
                    "a Python with the bpy module), else this Python when it has the bpy module, else blender on "
                    "the PATH.")
    p.add_argument("texture", metavar="TEXTURE", nargs="+",
                   help="the texture to paint (PNG, JPEG, TIFF, EXR, ...); several for a mesh of several materials, "
                        "the k-th for the OBJ's k-th material in the order its usemtl lines first name them; a "
                        "path holding <UDIM> is a tiled image, one file per UDIM tile (color.<UDIM>.png); without "
                        "--mesh, one MODEL file (.glb, .gltf, .obj, .fbx, .blend)")
    p.add_argument("--mesh", default=None, metavar="MESH.obj", help="the mesh whose UV map the texture follows")
    p.add_argument("-o", "--output", required=True, type=_folder, metavar="OUTDIR",
                   help="folder for the outputs (created if missing)")
    p.add_argument("--texture-size", type=_int, default=None, metavar="N",
                   help="paint an N x N texture, N x N for each texture or UDIM tile with several, which are "
                        "painted as one atlas of G x G of them (default: the sources' longest side)")
    p.add_argument("--stroke-mm", type=_widths, default=None, metavar="32,16,8",
                   help="stroke widths in millimetres on the surface (default: the still's widths for the texture "
                        "at its median texel's size)")
    p.add_argument("--detail", type=_float, default=DEFAULTS.detail, metavar="X",
                   help="0..1, how finely detailed areas are split (default: %(default)s)")
    p.add_argument("--extension", type=_extensions, default=None, metavar="REPEAT|MIRROR|CLIP|EXTEND",
                   help="what each texture shows beyond the UV square 0..1, as Blender's Image Texture node's "
                        "Extension: one rule for all, or one per texture separated by commas; faces there are "
                        "painted where the image repeats (REPEAT, MIRROR) or only inside 0..1 (CLIP, EXTEND) "
                        "(default: REPEAT)")
    p.add_argument("--apart-seams", dest="across_seams", action="store_false",
                   help="paint each UV island apart, its strokes stopping at its borders (default: strokes run on "
                        "across the UV seams where the surface does)")
    _add_stroke_options(p)
    _add_run_options(p)
    model = p.add_argument_group("a MODEL file, painted in Blender (with --texture-size and --seed; the options "
                                 "above apply to a TEXTURE and MESH)")
    model.add_argument("--object", default=None, metavar="NAME",
                       help="the mesh object to paint (default: every mesh object that has a material)")
    model.add_argument("--views", type=_int, default=None, metavar="V", help="turntable views (default 24)")
    model.add_argument("--samples", type=_int, default=None, metavar="S", help="Cycles samples (default 16)")
    model.add_argument("--resolution", type=_int, default=None, metavar="PX",
                       help="square render size of the turntable (default 384)")
    model.add_argument("--relief", default=None, choices=("DISPLACE", "CYCLES_ADAPTIVE", "NORMAL_MAP"),
                       help="how the paint's thickness shows on the object (default DISPLACE)")
    p.set_defaults(run=run_object, sizes=DEFAULTS.stroke_sizes)


def run_object(args: argparse.Namespace, progress) -> Optional[int]:
    """The ``object`` subcommand: a texture and its mesh painted here, or a model file painted in Blender (its
    exit status returned)."""
    from . import blender
    from .api import paint_object
    from .heap import reused_heap

    if args.mesh is None:
        model = args.texture[0]
        if len(args.texture) > 1 or not blender.is_model(model):
            raise ParameterError(f"{model} is no model file (.glb, .gltf, .obj, .fbx, .blend): give the mesh of "
                                 f"the texture{'s' if len(args.texture) > 1 else ''} with --mesh MESH.obj.")
        if progress is not None:
            progress.close()
        return blender.paint_model(model, args.output, args.object, args.texture_size, args.seed, args.views,
                                   args.samples, args.resolution, args.relief)

    with reused_heap():
        paint_object(args.texture[0] if len(args.texture) == 1 else args.texture, args.mesh, args.output, params_from_args(args), args.texture_size,
                     args.stroke_mm, progress=progress, max_memory=max_memory(args), normal_map=args.normal_map,
                     across_seams=args.across_seams, extensions=args.extension)


def _add_farm_options(p) -> None:
    group = p.add_mutually_exclusive_group()
    group.add_argument("--workers", type=_int, metavar="N",
                       help="paint on a local Dask cluster of N worker processes, one thread each (needs Dask: "
                            "pip install 'paint-relief[farm]')")
    group.add_argument("--scheduler", metavar="ADDRESS",
                       help="paint on the Dask cluster whose scheduler is at ADDRESS (tcp://host:8786); its workers "
                            "must see the input and output folders at the same paths")


def farm_from_args(args: argparse.Namespace):
    """The ``core.farm.cluster.Farm`` that --workers or --scheduler name, or None to paint in this process."""
    if args.workers is None and args.scheduler is None:
        return None
    from .farm.cluster import Farm

    farm = Farm(args.workers, args.scheduler)
    farm.validate()
    return farm


def run_sequence(args: argparse.Namespace, progress) -> None:
    """The ``sequence`` subcommand: the parameters checked for a shot (``Params.validate_shot``), the frames found and
    checked from their names and headers, before any painting."""
    from .api import paint_sequence_files
    from .heap import reused_heap

    params = params_from_args(args).validate_shot()
    settings = SequenceSettings(args.fade_frames, args.normal_map, args.measures).validate()
    with reused_heap():
        paint_sequence_files(args.input, args.output, params, settings, args.frames, progress=progress,
                             max_memory=max_memory(args), farm=farm_from_args(args),
                             notice=lambda text: _notice(progress, text))


def _notice(console, text: str) -> None:
    """One line of notice on stderr (also under --quiet: it says which image is painted), after any progress line."""
    if console is not None:
        console.close()
    print(f"paint-relief: {text}", file=sys.stderr, flush=True)


ANALYSIS_FILES = ("reference.png", "importance.exr", "importance.png", "partition.png", "orientation.png",
                  "analysis.json")
"""Every file ``write_analysis`` writes."""


def write_analysis(out: Path, analysis: Analysis, params: Params, source: str, pages: int = 1) -> None:
    """Write the analysis pictures, maps and figures (ANALYSIS_FILES) into folder ``out``; analysis.json records
    the input, its image analysed ("input_page", 0) and how many it holds ("input_pages", ``pages``)."""
    t0 = time.perf_counter()
    attributes = {"paint_relief:version": __version__, "paint_relief:seed": str(params.seed),
                  "paint_relief:params": json.dumps(params.to_dict(), sort_keys=True)}
    writing.write_png(out / "reference.png", analysis.reference)
    writing.write_exr(out / "importance.exr", analysis.importance, channels=("Y",), attributes=attributes)
    writing.write_png(out / "importance.png", analysis.importance)
    writing.write_png(out / "partition.png",
                 partition_overlay(analysis.reference, analysis.grids, analysis.grid_sizes, analysis.sizes))
    writing.write_png(out / "orientation.png", orientation_picture(analysis.orientation, analysis.reference, params.seed))
    summary = analysis.summary()
    summary["seconds"]["pictures"] = round(time.perf_counter() - t0, 4)
    summary.update({"input": str(source), "input_page": 0, "input_pages": int(pages), "version": __version__,
                    "seed": params.seed, "params": params.to_dict()})
    writing.write_json(out / "analysis.json", summary)


def _add_light_parser(sub) -> None:
    """The ``light`` subcommand's options."""
    import math

    from . import lighting

    p = sub.add_parser(
        "light", help="light a painted folder in 2-D: the paper's Eq. 6-7, a fixed light, or bump shading",
        description="Read OUTDIR/color.exr, height.exr (and orientation.exr for 'paper') written by "
                    "`python -m core paint` and write OUTDIR/lit_<model>.png (8-bit sRGB). Angles are "
                    "degrees; the azimuth points from the canvas towards the light, from +x (right) "
                    "towards +y (down the image): 0 = right, 90 = bottom, 180 = left, 270 = top.")
    p.add_argument("outdir", type=_folder, metavar="OUTDIR", help="a folder written by `python -m core paint`")
    p.add_argument("--model", required=True, metavar="paper|directional|bump",
                   help="paper: Eq. 6-7, the light turns with the strokes; directional: Eq. 6-7 with one "
                        "fixed light; bump: Blinn-Phong bump shading, one directional light (required)")
    p.add_argument("--azimuth", default=f"{math.degrees(lighting.DEFAULT_AZIMUTH):g}", metavar="DEG",
                   help="light direction for directional and bump, degrees (default: %(default)s, upper left)")
    p.add_argument("--elevation", default=f"{math.degrees(lighting.DEFAULT_ELEVATION):g}", metavar="DEG",
                   help="light height above the canvas for bump, degrees in (0, 90] (default: %(default)s)")
    p.add_argument("--strength", default=None, metavar="A",
                   help=f"paper and directional: a of Eq. 7 (default: {lighting.PAPER_STRENGTH:g}); "
                        f"bump: relief, pixel widths per height unit (default: {lighting.DEFAULT_RELIEF:g})")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress line on stderr")
    p.set_defaults(run=run_light)


def _number(text: str, option: str) -> float:
    """``text`` as a finite float; ParameterError naming ``option`` otherwise."""
    import math

    try:
        value = float(text)
    except (TypeError, ValueError):
        value = math.nan
    if not math.isfinite(value):
        raise ParameterError(f"The option {option} must be a number, got {text!r}.")
    return value


def run_light(args: argparse.Namespace, progress) -> None:
    """The ``light`` subcommand: OUTDIR's maps -> OUTDIR/lit_<model>.png."""
    import math

    from . import lighting
    from .colour import linear_to_srgb
    from .errors import InputError
    from .files.staging import settle

    model = lighting.check_model(args.model)
    azimuth = math.radians(_number(args.azimuth, "--azimuth"))
    elevation = math.radians(_number(args.elevation, "--elevation"))
    strength = None if args.strength is None else _number(args.strength, "--strength")
    if model == "bump" and not 0.0 < elevation <= math.pi / 2:
        raise ParameterError(f"The option --elevation must be above 0 and at most 90 degrees, got {args.elevation}.")
    if strength is not None and strength < 0:
        raise ParameterError(f"The option --strength must not be negative, got {args.strength}.")
    folder = Path(args.outdir)
    if not folder.is_dir():
        raise InputError(f"The folder {folder} does not exist: run `python -m core paint` into it first.")
    settle(folder)  # a commit a killed run left midway is completed first, so the maps read are of one painting
    names = ("color.exr", "height.exr") + (("orientation.exr",) if model == "paper" else ())
    for name in names:
        if not (folder / name).is_file():
            raise InputError(f"{folder / name} is missing: run `python -m core paint` into that folder first.")
    maps = {}
    for name, channels in zip(names, (3, 1, 1), strict=False):
        data, _, _ = reading.read_exr(folder / name)
        if data.shape[2] != channels:
            raise InputError(f"{folder / name} has {data.shape[2]} channels, expected {channels}.")
        if "color.exr" in maps and data.shape[:2] != maps["color.exr"].shape[:2]:
            raise InputError(f"{folder / name} is {data.shape[1]} x {data.shape[0]} pixels, "
                             f"not the size of {folder / 'color.exr'}.")
        maps[name] = data
    if progress is not None:
        progress(0.0, f"Lighting ({model})")
    image = lighting.light(model, linear_to_srgb(maps["color.exr"]), maps["height.exr"][:, :, 0],
                           maps["orientation.exr"][:, :, 0] if model == "paper" else None,
                           azimuth=azimuth, elevation=elevation, strength=strength)
    writing.write_png(folder / f"lit_{model}.png", image)
    if progress is not None:
        progress(1.0, f"Wrote {folder / f'lit_{model}.png'}")


def _add_svg_parser(sub) -> None:
    """The ``svg`` subcommand's options."""
    p = sub.add_parser(
        "svg", help="write a painting's strokes as an SVG picture",
        description="Read PAINTED_DIR/strokes.json (written by `python -m core paint`) and write FILE.svg: one "
                    "path per stroke in painting order, its brush width in the painting's pixels, its colour "
                    "(the mean of its bristles' colours, or its anchor colour when the list holds none) and "
                    "opacity, round caps and joins, the painting's size as the viewBox.")
    p.add_argument("painted", metavar="PAINTED_DIR", help="a folder written by `python -m core paint`")
    p.add_argument("-o", "--output", required=True, metavar="FILE.svg", help="the SVG file to write")
    p.add_argument("-q", "--quiet", action="store_true", help="no line on stderr")
    p.set_defaults(run=run_svg)


def _status_one(run):
    """``run`` with its input and output errors ending in exit status 1."""
    def wrapped(args: argparse.Namespace, progress):
        try:
            return run(args, progress)
        except PaintReliefError as exc:
            if not isinstance(exc, Cancelled):
                exc.status = 1
            raise
    return wrapped


@_status_one
def run_svg(args: argparse.Namespace, progress) -> None:
    """The ``svg`` subcommand: PAINTED_DIR/strokes.json -> FILE.svg; exit status 1 on a bad folder or file."""
    from .files.svg import write_svg

    count = write_svg(args.painted, args.output)
    if progress is not None:
        progress(1.0, f"Wrote {count} strokes to {args.output}")


def _add_lay_parser(sub) -> None:
    """The ``lay`` subcommand's options."""
    p = sub.add_parser(
        "lay", help="lay a stroke list (strokes.json, edited or not) into a painting's maps",
        description="Lay the strokes of STROKES.json (written by `python -m core paint --strokes-to-lay`) on a blank "
                    "canvas with the painting's parameters it records, against the photograph INPUT it was "
                    "painted from (its orientation field and the report's PSNR), and write the files `paint` "
                    "writes into OUTDIR. The painting's own strokes.json gives the painting's bytes.")
    p.add_argument("strokes", metavar="STROKES.json",
                   help="a stroke list written by `python -m core paint --strokes-to-lay`")
    p.add_argument("--reference", required=True, metavar="INPUT",
                   help="the photograph the strokes were painted from, of the size they were painted at")
    p.add_argument("-o", "--output", required=True, type=_folder, metavar="OUTDIR",
                   help="folder for the outputs (created if missing)")
    p.add_argument("--normal-map", action="store_true", help="also write normal.exr")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress line on stderr")
    p.set_defaults(run=run_lay)


@_status_one
def run_lay(args: argparse.Namespace, progress) -> None:
    """The ``lay`` subcommand; exit status 1 on a bad stroke list or reference, nothing written."""
    from .api import lay_file
    from .heap import reused_heap

    with reused_heap():
        lay_file(args.strokes, args.reference, args.output, progress=progress, normal_map=args.normal_map)


def _add_experiments_parser(sub) -> None:
    """The ``experiments`` subcommand's options."""
    p = _add_files_parser(
        sub, "experiments", "compare the paper's method with Hertzmann 1998 and the two ablations",
        "Paint every IMAGE with the paper's method, Hertzmann 1998 (Impressionist), the "
        "Hertzmann-layout ablation and the solid-lines ablation; write table.md, table.csv "
        "(strokes, seconds, PSNR, SSIM, edge fidelity, stroke ratio) and <image>_sheet.png.",
        ("images", "IMAGE", "photographs to paint"), ("OUTDIR", "folder for the tables and sheets"))
    p.add_argument("--detail", type=_float, default=DEFAULTS.detail, metavar="X",
                   help="detail of the paper's method (default: %(default)s)")
    _add_run_options(p)
    p.set_defaults(run=run_experiments_command)


def run_experiments_command(args: argparse.Namespace, progress) -> None:
    """The ``experiments`` subcommand."""
    from .evaluation.experiments import run_experiments

    params = Params(detail=args.detail, seed=args.seed, max_megapixels=args.max_megapixels).validate()
    seen = set()
    for image in args.images:
        if Path(image).resolve() in seen:
            raise ParameterError(f"The image {image} is given twice: the table has one row per image, "
                                 f"so give each image once.")
        seen.add(Path(image).resolve())
    run_experiments([Path(p) for p in args.images], Path(args.output), params, progress=progress,
                    max_memory=max_memory(args))


def main(argv: Optional[List[str]] = None) -> int:
    """Entry point; returns the process exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    console = None if args.quiet else ConsoleProgress()
    restore = signals.install()
    quiet.enable()
    try:
        status = args.run(args, console)
    except signals.Interrupted as exc:
        return _fail(console, _interrupted_message(exc, args), exc.status)
    except Cancelled as exc:
        return _fail(console, str(exc), 130)
    except KeyboardInterrupt:
        return _fail(console, f"Interrupted; {_folder_phrase(args)} was left as it was.", 130)
    except MemoryError:
        return _fail(console, "error: The machine ran out of memory; nothing was written.", 2)
    except PaintReliefError as exc:
        return _fail(console, f"error: {exc}", getattr(exc, "status", 2))
    finally:
        quiet.enable(False)
        restore()
    if console is not None:
        console.close()
    return status if isinstance(status, int) else 0


def _folder_phrase(args: argparse.Namespace) -> str:
    """'the output folder X' (or 'the folder X' for light) for messages."""
    folder = getattr(args, "output", None) or getattr(args, "outdir", None)
    return f"the output folder {folder}" if folder else "the output folder"


def _interrupted_message(exc: "signals.Interrupted", args: argparse.Namespace) -> str:
    """A true sentence about what a signal left behind."""
    from .api import is_shot

    if args.command == "sequence":
        return (f"Stopped by {exc.name}; every frame in {args.output} is complete, and the same command goes on "
                f"after the last of them.")
    if args.command == "batch" and any(is_shot(source) for source in args.input):
        return (f"Stopped by {exc.name}; the stills and frames painted stay in {args.output}, each complete, and "
                f"{_goes_on(args)}.")
    if args.command == "batch":
        return (f"Stopped by {exc.name}; the stills painted stay in {args.output}, each folder complete, and "
                f"{_goes_on(args)}.")
    if exc.committed:
        return f"Stopped by {exc.name} after every output was written to {exc.committed}."
    return f"Stopped by {exc.name}; {_folder_phrase(args)} was left as it was."


def _goes_on(args: argparse.Namespace) -> str:
    """What goes on with a batch stopped midway: the same command, or without --fresh when it had it."""
    if args.fresh:
        return "the same command without --fresh goes on where it stopped"
    return "the same command goes on where it stopped"


def _fail(console, message: str, status: int) -> int:
    """End the progress line, print one line to stderr, return ``status``."""
    if console is not None:
        console.close()
    print(f"paint-relief: {message}", file=sys.stderr)
    return status
