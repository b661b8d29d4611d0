#!/usr/bin/env python3
"""Write the transfer-function presets in ``Data/TransferFunctions/``.

Each dataset gets one file ``<name>.json`` in ParaView's colour-map preset
format (a JSON list of objects with ``Name``, ``ColorSpace``, ``RGBPoints``
``[x, r, g, b, ...]`` and ``Points`` ``[x, opacity, midpoint, sharpness,
...]``); it can be imported in ParaView (Color Map Editor, "Choose preset",
"Import") or with ``paraview.simple.ImportPresets``.  Each file holds two
presets:

``"<Dataset> Two-Band (paper)"``
    The seed paper's Eq. 3: an outer band ``[t1, t2]`` coloured (1, 1, 0)
    with opacity 0.7 and an inner band ``[t3, t4]`` coloured (1, 1, 1) with
    opacity 1.0, transparent elsewhere.  Band edges are pairs of control
    points ``EDGE_FRACTION`` of the data range apart, so linear interpolation
    gives a box: the opacity is exactly the band value on ``[t1, t2]`` and
    exactly 0 further than one edge width outside it.
``"<Dataset> Smooth"``
    A VTK-style ramp with a warm, bone-like colour map.

The points of every preset span exactly the dataset's value range from
``Data/datasets.json``, so rescaling the preset to the data range in
ParaView leaves it unchanged.

The thresholds below were chosen from the histograms of the converted
volumes; ``--report`` prints the evidence (needs the fetched ``.vti``).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any, Sequence

REPO_ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO_ROOT / "Python"))

from pathtracedvolume import datasets as ds  # noqa: E402
from pathtracedvolume.atomic import write_text  # noqa: E402

OUTPUT_DIR = REPO_ROOT / "Data" / "TransferFunctions"
CREATOR = "PathTracedVolume scripts/make_transfer_functions.py"
EDGE_FRACTION = 1e-3
OUTER_COLOR = (1.0, 1.0, 0.0)
OUTER_OPACITY = 0.7
INNER_COLOR = (1.0, 1.0, 1.0)
INNER_OPACITY = 1.0

# Per dataset: title, band thresholds (t1, t2, t3, t4), the histogram
# justification, and the smooth preset's colour and opacity control points.
PRESETS: dict[str, dict[str, Any]] = {
    "head": {
        "title": "Head",
        "bands": (-500.0, 200.0, 400.0, 2986.0),
        "evidence": (
            "Head CT in HU, range [-1024, 2986]. Histogram in 100-HU bins: "
            "air below -900 HU holds 58.5% of the voxels. The soft-tissue "
            "peak (mode above -500 HU: 23 HU) puts 19.8% in [0, 100). Bins "
            "fall off to 1.1% in [100, 200) and 0.7% in [200, 300). Bone is "
            "then a flat plateau of about 0.6% per bin from 300 to 1300 HU, "
            "tailing off to 2986. A 3-class multi-Otsu (256 bins) gives -484 "
            "and 472 HU. "
            "Outer band = skin/soft tissue [-500, 200] HU (27.1% of the "
            "voxels). Inner band = bone [400, 2986] HU (5.6%). The gap "
            "(200, 400) holds 1.3%."),
        "smooth_rgb": [
            (-1024.0, 0.0, 0.0, 0.0),
            (-500.0, 0.55, 0.25, 0.15),
            (100.0, 0.88, 0.60, 0.45),
            (400.0, 0.90, 0.82, 0.56),
            (1500.0, 1.0, 1.0, 0.95),
            (2986.0, 1.0, 1.0, 1.0),
        ],
        "smooth_opacity": [
            (-1024.0, 0.0),
            (-600.0, 0.0),
            (-100.0, 0.04),
            (200.0, 0.08),
            (400.0, 0.3),
            (1200.0, 0.85),
            (2986.0, 0.9),
        ],
    },
    "stent": {
        "title": "Stent",
        "bands": (281.0, 469.0, 719.0, 2000.0),
        "evidence": (
            "Stent CT, range [0, 2000]. Values are quantised in steps of "
            "62.5 (0, 62, 125, 187, 250, 312, 375, 437, 500, ...), so the "
            "thresholds sit halfway between levels. Below 250 (background "
            "and soft tissue) lies 95.6% of the voxels. Inside the stented "
            "aorta the contrast-filled lumen reads 312-437, where 2.5% of "
            "the voxels lie. The stent struts are the brightest structure: "
            "they run from 500 up to the clip value 2000 (595 voxels sit "
            "exactly at 2000). Bone adds to the bright voxels only in the "
            "spine region (y >= 90): it holds 20% of the voxels at 750 or "
            "more and 6% of those at 1000 or more. A 4-class multi-Otsu "
            "(256 bins) gives 59, 254 and 684. Outer band = "
            "vessel/contrast range [281, 469] (levels 312-437, 2.5%). "
            "Inner band = metal stent [719, 2000] (levels 750 and up, "
            "0.31%)."),
        "smooth_rgb": [
            (0.0, 0.0, 0.0, 0.0),
            (281.0, 0.60, 0.10, 0.05),
            (469.0, 0.90, 0.35, 0.10),
            (719.0, 1.0, 0.75, 0.30),
            (2000.0, 1.0, 1.0, 0.90),
        ],
        "smooth_opacity": [
            (0.0, 0.0),
            (200.0, 0.0),
            (350.0, 0.05),
            (469.0, 0.15),
            (719.0, 0.6),
            (1200.0, 0.9),
            (2000.0, 1.0),
        ],
    },
    "concrete": {
        "title": "Concrete",
        "bands": (26000.0, 31700.0, 32300.0, 38064.0),
        "evidence": (
            "Concrete x-ray micro-CT, uint16, range [0, 38064]. Outside the "
            "cylindrical specimen (air, container wall) the 5th to 95th "
            "percentiles are 4669-25332, with a peak at 5000-6000. Below "
            "26000 lies 43.6% of all voxels. In the specimen core "
            "(radius < 38 voxels about the axis, 10 < z < 90) the "
            "histogram is one broad peak: 5th to 95th percentiles "
            "30270-33748, mode about 32200. A 3-class multi-Otsu of the "
            "core gives 25987 (pores and air against solid) and 31995 "
            "(cement matrix against aggregates). The brighter grains in the "
            "slices are the aggregates, the densest phase. Outer band = "
            "matrix/mortar [26000, 31700]: 26.7% of all voxels, 24% of the "
            "specimen core. Inner band = aggregates [32300, 38064]: 19.1% "
            "of all voxels, 50% of the specimen core. The gap of +-300 "
            "around the Otsu split (about 0.4 of the aggregate peak's SD "
            "of 810) leaves the mixed voxels transparent; it holds 24% of "
            "the specimen core."),
        "smooth_rgb": [
            (0.0, 0.0, 0.0, 0.0),
            (26000.0, 0.45, 0.20, 0.10),
            (31700.0, 0.85, 0.60, 0.35),
            (32300.0, 0.95, 0.85, 0.60),
            (38064.0, 1.0, 1.0, 1.0),
        ],
        "smooth_opacity": [
            (0.0, 0.0),
            (24000.0, 0.0),
            (28000.0, 0.05),
            (31700.0, 0.2),
            (32300.0, 0.5),
            (34000.0, 0.9),
            (38064.0, 1.0),
        ],
    },
}


def _round(value: float) -> float:
    """Round to 6 decimals so the JSON stays readable and stable."""
    rounded = round(float(value), 6)
    return 0.0 if rounded == 0 else rounded


def two_band_preset(title: str, value_range: Sequence[float],
                    bands: Sequence[float], evidence: str) -> dict[str, Any]:
    """Build the paper's two-band preset (Eq. 3) over *value_range*."""
    lo, hi = (float(v) for v in value_range)
    t1, t2, t3, t4 = (float(t) for t in bands)
    eps = EDGE_FRACTION * (hi - lo)
    if not (lo <= t1 < t2 and t2 + eps < t3 - eps and t3 < t4 <= hi):
        raise ValueError(f"{title}: bad thresholds {bands} for range "
                         f"{value_range}")
    opacity: list[tuple[float, float]] = []
    if t1 - eps > lo:
        opacity += [(lo, 0.0), (t1 - eps, 0.0)]
    opacity += [(t1, OUTER_OPACITY), (t2, OUTER_OPACITY), (t2 + eps, 0.0),
                (t3 - eps, 0.0), (t3, INNER_OPACITY), (t4, INNER_OPACITY)]
    if t4 + eps < hi:
        opacity += [(t4 + eps, 0.0), (hi, 0.0)]
    elif t4 < hi:
        opacity += [(hi, 0.0)]
    rgb = [(lo, *OUTER_COLOR), (t2 + eps, *OUTER_COLOR),
           (t3 - eps, *INNER_COLOR), (hi, *INNER_COLOR)]
    return {
        "Name": f"{title} Two-Band (paper)",
        "Creator": CREATOR,
        "Description": (
            f"Two-band transfer function (seed paper, Eq. 3). Outer band "
            f"[{t1:g}, {t2:g}]: colour (1, 1, 0), opacity {OUTER_OPACITY}. "
            f"Inner band [{t3:g}, {t4:g}]: colour (1, 1, 1), opacity "
            f"{INNER_OPACITY}. Opacity 0 elsewhere; each edge is a linear "
            f"step {eps:g} wide ({EDGE_FRACTION:g} of the data range "
            f"[{lo:g}, {hi:g}]), just outside the band. {evidence}"),
        "ColorSpace": "RGB",
        "NanColor": [1.0, 0.0, 0.0],
        "RGBPoints": [_round(v) for point in rgb for v in point],
        "Points": [_round(v) for x, y in opacity
                   for v in (x, y, 0.5, 0.0)],
    }


def smooth_preset(title: str, value_range: Sequence[float],
                  spec: dict[str, Any]) -> dict[str, Any]:
    """Build the smooth ramp preset."""
    lo, hi = (float(v) for v in value_range)
    rgb = spec["smooth_rgb"]
    opacity = spec["smooth_opacity"]
    for points in (rgb, opacity):
        if points[0][0] != lo or points[-1][0] != hi:
            raise ValueError(f"{title}: smooth preset must span [{lo}, {hi}]")
    return {
        "Name": f"{title} Smooth",
        "Creator": CREATOR,
        "Description": (
            "Smooth VTK-style ramp: warm, bone-like colours (black, dark "
            "red, flesh, tan, white) with opacity rising piecewise-linearly "
            f"over the two bands of the '{title} Two-Band (paper)' preset "
            f"(data range [{lo:g}, {hi:g}])."),
        "ColorSpace": "RGB",
        "NanColor": [1.0, 0.0, 0.0],
        "RGBPoints": [_round(v) for point in rgb for v in point],
        "Points": [_round(v) for x, y in opacity for v in (x, y, 0.5, 0.0)],
    }


def _dump(presets: list[dict[str, Any]]) -> str:
    """JSON text with one control point per line."""
    def number_list(values: list[float], width: int) -> str:
        rows = [", ".join(json.dumps(v) for v in values[i:i + width])
                for i in range(0, len(values), width)]
        return "[\n      " + ",\n      ".join(rows) + "\n    ]"

    blocks = []
    for preset in presets:
        fields = []
        for key, value in preset.items():
            if key in ("RGBPoints", "Points"):
                text = number_list(value, 4)
            else:
                text = json.dumps(value, ensure_ascii=False)
            fields.append(f'    "{key}": {text}')
        blocks.append("  {\n" + ",\n".join(fields) + "\n  }")
    return "[\n" + ",\n".join(blocks) + "\n]\n"


def report(name: str, bands: Sequence[float]) -> None:
    """Print band fractions and multi-Otsu thresholds of a fetched volume."""
    import numpy as np

    array = ds.read_vti(ds.dataset_path(name)).array
    t1, t2, t3, t4 = bands
    total = array.size
    fractions = {
        f"< {t1:g}": np.count_nonzero(array < t1),
        f"outer [{t1:g}, {t2:g}]": np.count_nonzero((array >= t1)
                                                    & (array <= t2)),
        f"gap ({t2:g}, {t3:g})": np.count_nonzero((array > t2)
                                                  & (array < t3)),
        f"inner [{t3:g}, {t4:g}]": np.count_nonzero((array >= t3)
                                                    & (array <= t4)),
    }
    print(f"{name}: range [{array.min()}, {array.max()}]")
    for label, count in fractions.items():
        print(f"  {label:28s} {100.0 * count / total:6.2f}%")
    try:
        from skimage.filters import threshold_multiotsu
    except ImportError:
        return
    values = array.astype(np.float64)
    print("  multi-Otsu (3 classes, 256 bins):",
          np.round(threshold_multiotsu(values, 3, nbins=256), 1))


def main(argv: list[str] | None = None) -> int:
    """Entry point."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--output", type=Path, default=OUTPUT_DIR,
                        help=f"output folder (default: {OUTPUT_DIR})")
    parser.add_argument("--report", action="store_true",
                        help="print histogram evidence from the fetched .vti "
                             "files instead of writing presets")
    args = parser.parse_args(argv)
    manifest = ds.load_manifest()
    for name, spec in PRESETS.items():
        if args.report:
            report(name, spec["bands"])
            continue
        value_range = ds.dataset_entry(name, manifest)["volume"]["value_range"]
        presets = [two_band_preset(spec["title"], value_range, spec["bands"],
                                   spec["evidence"]),
                   smooth_preset(spec["title"], value_range, spec)]
        path = args.output / f"{name}.json"
        write_text(path, _dump(presets))  # atomically: a reader never sees half a preset file
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
