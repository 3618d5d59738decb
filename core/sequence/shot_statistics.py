"""The statistics of a shot's report.json, from its frames' entries: stroke counts, seconds per stage, mean PSNR
and, when the shot measures, its steadiness (warping errors and stillness)."""

from __future__ import annotations

from typing import Dict, List, Optional

import numpy as np


def restate_statistics(report: dict, frame_count: int, measures: bool) -> None:
    """Put the statistics of ``report``'s frames (``sequence_statistics``) into it, in place of any earlier run's;
    ``frame_count``: the frames of the run."""
    for key in STEADINESS_STATISTICS:
        report.pop(key, None)
    report.update(sequence_statistics(report["per_frame"], frame_count, measures))


def statistics_mean(values: List[Optional[float]]) -> float:
    """The mean of the ``values`` that have one (a None, as report.json's null reads back, or a NaN has none); NaN
    when none has."""
    numbers = np.array([np.nan if value is None else value for value in values], np.float64)
    return float(np.nanmean(numbers)) if (~np.isnan(numbers)).any() else float("nan")


STEADINESS_STATISTICS = ("warping_error", "stillness")
"""The keys of report.json that ``steadiness_statistics`` writes."""


def sequence_statistics(per_frame: List[dict], frame_count: int, measures: bool) -> dict:
    """The sequence's statistics from its frames' entries: stroke counts, seconds per stage and mean PSNR; with
    ``measures``, also the warping errors of the pairs measured (the height's normalised to [0, 1] over the frames
    painted: divided by their height range squared) and their ratios to the footage's, and the stillness of the
    painting against the footage's."""
    seconds: Dict[str, float] = {}
    for entry in per_frame:
        for name, value in entry["seconds"].items():
            seconds[name] = round(seconds.get(name, 0.0) + value, 4)
    statistics = {"complete": len(per_frame) >= frame_count,
                  "strokes": {"alive": [e["alive"] for e in per_frame], "born": [e["born"] for e in per_frame],
                              "died": [e["died"] for e in per_frame]},
                  "seconds": seconds, "psnr": statistics_mean([e["psnr"] for e in per_frame])}
    return dict(statistics, **steadiness_statistics(per_frame)) if measures else statistics


def steadiness_statistics(per_frame: List[dict]) -> dict:
    """The sequence's warping errors and stillness (``sequence_statistics``) over the pairs ``per_frame`` measured."""
    pairs = [entry for entry in per_frame if "warping_error" in entry]
    low = min(entry["height_range"][0] for entry in per_frame)
    high = max(entry["height_range"][1] for entry in per_frame)
    footage = statistics_mean([p["warping_error"]["footage"] for p in pairs])
    painting = statistics_mean([p["warping_error"]["painting"] for p in pairs])
    height = statistics_mean([p["warping_error"]["height_raw"] for p in pairs]) / max(high - low, 1e-12) ** 2
    still = [p for p in pairs if p["still_pixels"]]
    still_footage = statistics_mean([p["stillness"]["footage"] for p in still])
    still_painting = statistics_mean([p["stillness"]["painting"] for p in still])
    return {"warping_error": {"footage": footage, "painting": painting, "height": height,
                              "painting_ratio": painting / footage if footage else float("nan")},
            "stillness": {"footage": still_footage, "painting": still_painting,
                          "ratio": still_painting / still_footage if still_footage else float("nan")}}
