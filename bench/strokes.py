"""Brushwork figures of the bundled samples, the paper's method next to Hertzmann 1998.

For each bundled photograph, paints it with default settings by both methods
and prints the measures of ALGORITHM §5-6 (bench/brushwork_measures.py): median
stroke length over width (all strokes and the first layer), the share of the
painted area in dabs and in strokes at least 1.5 : 1, crack pixels, height
percentiles, the colour error in smooth areas, the small highlights kept,
PSNR against the photograph, the stroke ratio, the median length over width of
the layer strokes (the detail pass left out) and the detail pass's share of the
strokes, the speckle share (dots the photograph does not have), the gradient
correlation with the photograph and the width contrast (strokes in smooth areas
over strokes in detail). With --figure PATH it also
writes the brushwork picture (crops at 1:1 and 3x, painting and relief under a
raking light, for both methods) of the first sample.
Usage: python bench/strokes.py [--height-mode over|accumulate] [--figure docs/brushwork.png]
"""

from __future__ import annotations

import argparse

from brushwork_measures import (
    area_share_elongated,
    crack_share,
    detail_share,
    gradient_correlation,
    height_spread,
    highlights_kept,
    median_length_to_width_layers,
    smooth_colour_error,
    speckle_share,
    width_contrast,
)

from common import ROOT
from core import Params
from core.figures.brushwork import brushwork_sheet
from core.files import reading, writing
from core.measures.metrics import psnr
from core.measures.stroke_metrics import stroke_shape
from core.methods import paint

SAMPLES = ("coffee", "chelsea", "astronaut")
DIGITS = {"speckle": 4, "width contr": 2}  # decimals printed where not 3
FIGURE_BOX = {"coffee": (250, 110, 490, 350)}  # (x0, y0, x1, y1) px: the cup's rim, handle and spoon


def measures(painting, photo) -> dict:
    """Every brushwork figure of one painting of ``photo``."""
    shape = stroke_shape(painting.strokes)
    spread = height_spread(painting.height)
    count, kept = highlights_kept(painting.colour, photo)
    detail = painting.statistics.get("detail_strokes", 0)
    return {"strokes": len(painting.strokes), "L/w": shape["median_length_to_width"],
            "L/w first": shape["median_length_to_width_first_layer"], "dab area": shape["dab_area_share"],
            ">=1.5:1 area": area_share_elongated(painting.strokes), "cracks": crack_share(painting.height),
            "h p95/med": spread["height_p95_over_median"], "h max/med": spread["height_max_over_median"],
            "colour err": smooth_colour_error(painting.colour, photo), "highlights": kept,
            "PSNR": psnr(painting.colour, photo),
            "L/w layers": median_length_to_width_layers(painting.strokes, detail),
            "detail share": detail_share(painting.strokes, detail),
            "speckle": speckle_share(painting.colour, photo),
            "grad corr": gradient_correlation(painting.colour, photo),
            "width contr": width_contrast(painting.strokes, photo, detail)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--height-mode", default="over", choices=("over", "accumulate"))
    parser.add_argument("--figure", metavar="PATH", help="write the brushwork picture of the first sample here")
    args = parser.parse_args()
    columns = ("strokes", "ratio", "L/w", "L/w first", "dab area", ">=1.5:1 area", "cracks", "h p95/med",
               "h max/med", "colour err", "highlights", "PSNR", "L/w layers", "detail share", "speckle",
               "grad corr", "width contr")
    print(f"{'image':10} {'method':12} " + " ".join(f"{c:>12}" for c in columns))
    for name in SAMPLES:
        photo = reading.read_image(ROOT / "sample_scenes" / f"{name}.png")
        ours = paint(photo, Params(height_mode=args.height_mode))
        theirs = paint(photo, Params(method="hertzmann98", height_mode=args.height_mode))
        baseline = len(theirs.strokes)
        for label, painting in (("Huang 2011", ours), ("Hertzmann98", theirs)):
            row = measures(painting, photo)
            row["ratio"] = row["strokes"] / baseline
            print(f"{name:10} {label:12} " + " ".join(
                f"{row[c]:>12}" if isinstance(row[c], int) else f"{row[c]:>12.{DIGITS.get(c, 3)}f}"
                for c in columns))
        if args.figure and name in FIGURE_BOX:
            sheet = brushwork_sheet([("Huang 2011", ours.colour, ours.height),
                                     ("Hertzmann 1998", theirs.colour, theirs.height)], FIGURE_BOX[name])
            writing.write_png(args.figure, sheet)
            print(f"wrote {args.figure}")
            args.figure = None


if __name__ == "__main__":
    main()
