#!/usr/bin/env python3
"""Study: how much of its own mean an edge pixel keeps in the denoised image (the SampleRatio step).

The mapper's edge pixels hold EdgeSamples times the samples of a plain pixel
(``docs/edge-samples.md``), and its SampleRatio pass says so; vtkPTVDenoiser moves each such
pixel from its denoised value D towards its own mean M: D + w (M - D), w = (r - 1) /
(r - 1 + n), with the denoised value counting as n plain samples (ptv::kDenoisedSampleWorth).
This script picks n: for the report's Table-1 views (``compare.paper_view``, 256-spp
references) and each EdgeSamples count it denoises the mapper's frame without the SampleRatio
image (D), applies the step with each n of ``--worth`` in numpy on the pixels the pass marks,
and reports the PSNR after the tone map (``docs/measuring.md``); it also checks that the
shipped step (vtkPTVDenoiser with the pass) equals the numpy one for n = 4. Run it on an idle
machine.

    PYTHONPATH=build/python xvfb-run -a .venv/bin/python research/benchmarks/own_mean_weight.py
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any, Dict, List

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "Training"))
sys.path.insert(0, str(Path(__file__).resolve().parent))
SHIPPED_WORTH = 4.0  # ptv::kDenoisedSampleWorth


def parse_args() -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--sizes", nargs="+", type=int, default=[256, 512])
    p.add_argument("--counts", nargs="+", type=int, default=[3],
                   help="EdgeSamples values (default 3, the mapper's default)")
    p.add_argument("--worth", nargs="+", type=float, default=[1.5, 2, 3, 4, 6],
                   help="what the denoised value counts for, in plain samples")
    from ptv_training.compare import add_paper_view_arguments
    add_paper_view_arguments(p)
    return p.parse_args()


def main() -> int:
    a = parse_args()
    from evaluation.common import md_table
    from pathtracedvolume.atomic import write_text
    from pathtracedvolume.metrics import psnr
    from pathtracedvolume.scene import paper_preset
    from ptv_training import compare, exr_io
    from ptv_training.evaluate import cpp_denoise
    from ptv_training.scene import Scene
    from edge_samples import frame  # the frame the mapper denoises, with its edge samples

    names = list(exr_io.INPUT_PASSES) + ["Footprint"]
    rows: List[Dict[str, Any]] = []
    shipped_matches = True
    for size in a.sizes:
        for ds in compare.PAPER_DATASETS:
            scene = Scene(ds, (size, size))
            for cam, (azimuth, elevation) in enumerate(compare.PAPER_CAMERAS):
                ref = compare.paper_view(ds, size, cam, a.reference_spp, a.cache)["reference"]
                view = {"dataset": ds, "transfer_function": paper_preset(ds),
                        "azimuth": azimuth, "elevation": elevation}
                for count in a.counts:
                    frame(scene, view, compare.PAPER_SEEDS[0], count)
                    passes = {n: scene.get_pass(n) for n in names}
                    ratio = scene.get_pass("SampleRatio")
                    plain = cpp_denoise(a.model, passes, sorted(passes), threads=2)["output"]
                    with_ratio = dict(passes, SampleRatio=ratio)
                    shipped = cpp_denoise(a.model, with_ratio, sorted(with_ratio),
                                          threads=2)["output"]
                    r = ratio.reshape(plain.shape[:2])
                    own = passes["Radiance"].reshape(plain.shape)
                    row: Dict[str, Any] = {"size": size, "dataset": ds, "camera": cam,
                                           "count": count, "none": psnr(plain, ref)}
                    for worth in a.worth:
                        w = np.where(r > 1, (r - 1) / (np.maximum(r, 1) - 1 + worth), 0.0)
                        leaned = plain + w[..., None] * (own - plain)
                        row[f"n={worth:g}"] = psnr(leaned, ref)
                        if worth == SHIPPED_WORTH:
                            # The Footprint step after the lean may clear a pixel: compare there.
                            shipped_matches = shipped_matches and bool(np.allclose(
                                np.where(shipped == 0, 0, leaned), shipped, rtol=1e-4,
                                atol=1e-5))
                    rows.append(row)
                    print(row, flush=True)
    columns = ["none"] + [f"n={w:g}" for w in a.worth]
    summary = []
    for size in a.sizes:
        for count in a.counts:
            for ds in compare.PAPER_DATASETS + ("**mean**",):
                pick = [r for r in rows if r["size"] == size and r["count"] == count and
                        (ds == "**mean**" or r["dataset"] == ds)]
                summary.append([f"{size}²", ds, str(count)] +
                               [f"{np.mean([r[c] for r in pick]):.2f}" for c in columns])
    text = "\n".join([
        "# The edge pixels' own means in the denoised image", "",
        f"Command (idle machine): `{' '.join(sys.argv)}`", "",
        f"The Table-1 views (1-spp frames of seed 1 with EdgeSamples, {a.reference_spp}-spp "
        f"references); `{a.model.name}` through vtkPTVDenoiser without the SampleRatio image "
        "(D), then D + w (M - D) on the pixels the SampleRatio pass marks (ratio r, own mean M), "
        "w = (r - 1) / (r - 1 + n); PSNR (dB) after the tone map, mean of the two views. The "
        f"shipped step (n = {SHIPPED_WORTH:g}, vtkPTVDenoiser given the pass) equals this "
        f"one: {'yes' if shipped_matches else 'NO'}.", "",
        *md_table(["size", "dataset", "EdgeSamples"] + columns, summary), ""])
    if a.markdown:
        write_text(a.markdown, text)
    if a.json:
        write_text(a.json, json.dumps({"rows": rows, "shipped_matches": shipped_matches},
                                      indent=1) + "\n")
    print(text)
    return 0 if shipped_matches else 1


if __name__ == "__main__":
    sys.exit(main())
