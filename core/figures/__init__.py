"""Figures: pictures for people, 8-bit sRGB arrays in [0, 1].

Labelled contact sheets (``sheet``, with ``text`` and its bitmap font),
line charts (``chart``), animated GIFs (``gif``), the analysis pictures
(``visualize``: partition overlay, orientation) and raking-light close-ups
of strokes (``brushwork``).
"""

from .brushwork import brushwork_sheet
from .chart import line_chart
from .gif import write_gif
from .sheet import contact_sheet, label_strip
from .text import draw_text
from .visualize import orientation_picture, partition_overlay

__all__ = ["brushwork_sheet", "contact_sheet", "draw_text", "label_strip", "line_chart", "orientation_picture",
           "partition_overlay", "write_gif"]
