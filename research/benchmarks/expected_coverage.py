#!/usr/bin/env python3
"""Ablation: a camera ray's opacity as its Alpha (expected coverage) against the coin flip.

Today a camera ray either has an event (Alpha 1, Radiance the event's) or not (Alpha 0, Radiance
0), with the probability of its opacity c. The mapper's ExpectedCoverage (here through
PTV_EXPECTED_COVERAGE=1, which turns it on in every mapper; ``Rendering/Kernels/ptvIntegrator.h``,
step 4b) marches every camera ray to its end instead,
stores c itself as Alpha and c times the radiance of an event drawn in proportion to each
sample's share of c: the same expectations without the coin flip, for the march behind the
event. It removes the variance of that flip, which is large where c is far from 0 and 1
(translucent media, the fringe of a band) and nothing on opaque surfaces.

For every dataset and view (the report's Table-1 views), with its paper preset and with that
preset's opacity scaled by ``--translucent`` (a fog-like transfer function), both modes:
- time: the median trace time of a 1-spp frame in ``--rounds`` interleaved rounds;
- raw PSNR at 1, 2, 4 and 8 spp against a reference of ``--ref-spp`` (the default mode, another
  seed), and its mean squared error, linear, over the image;
- efficiency: 1 / (MSE x time) at 1 spp, relative to the default mode;
- the 1-spp frame denoised by the shipped model (vtkPTVDenoiser, DenoiseAlpha, as the mapper
  runs it).
Run it on an idle machine.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
from pathlib import Path
from typing import Dict, List

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ptvbench as pb  # noqa: E402
from evaluation.common import md_table  # noqa: E402

from pathtracedvolume.metrics import psnr  # noqa: E402
from tqdm import tqdm  # noqa: E402

VARIABLE = "PTV_EXPECTED_COVERAGE"
VIEWS = ((30.0, 10.0), (150.0, -20.0))
MODES = ("0", "1")


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--datasets", nargs="+", default=["head", "stent", "concrete"])
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--ref-spp", type=int, default=256)
    parser.add_argument("--translucent", type=float, default=0.1,
                        help="opacity scale of the fog-like variant (default 0.1; 0: none)")
    parser.add_argument("--rounds", type=int, default=7, help="timing rounds (default 7)")
    parser.add_argument("--json", type=Path, default=None)
    parser.add_argument("--markdown", type=Path, default=None)
    return parser.parse_args()


def scale_opacity(scene: pb.BenchScene, scale: float) -> None:
    """Multiply every opacity point of the scene's transfer function by ``scale``."""
    fn = scene.prop.GetScalarOpacity()
    nodes = []
    for i in range(fn.GetSize()):
        node = [0.0] * 4
        fn.GetNodeValue(i, node)
        nodes.append(node)
    fn.RemoveAllPoints()
    for x, y, mid, sharp in nodes:
        fn.AddPoint(x, min(1.0, y * scale), mid, sharp)


def frame_time(scene: pb.BenchScene, seed: int) -> float:
    """Trace milliseconds of a fresh 1-spp frame (the second of two: tables are warm)."""
    scene.render(seed=seed, frames=2)
    return float(scene.mapper.GetLastTraceTime())


def measure(scene: pb.BenchScene, ours: pb.Ours, rounds: int, ref_spp: int
            ) -> Dict[str, Dict[str, float]]:
    os.environ.pop(VARIABLE, None)
    scene.render(seed=9000, frames=ref_spp)
    ref = scene.grab("Radiance")
    times: Dict[str, List[float]] = {m: [] for m in MODES}
    for r in range(rounds):
        for mode in MODES:
            os.environ[VARIABLE] = mode
            times[mode].append(frame_time(scene, 100 + r))
    out: Dict[str, Dict[str, float]] = {}
    for mode in MODES:
        os.environ[VARIABLE] = mode
        row: Dict[str, float] = {"trace_ms": statistics.median(times[mode])}
        scene.render(seed=1, frames=1)
        passes = scene.passes()
        row["mse"] = float(np.mean((passes["Radiance"] - ref) ** 2))
        row["raw_1"] = psnr(passes["Radiance"], ref)
        row["ours"] = psnr(ours(passes), ref)
        for n in (2, 4, 8):
            scene.render(seed=1, frames=n)
            row[f"raw_{n}"] = psnr(scene.grab("Radiance"), ref)
        out[mode] = row
    return out


def main() -> int:
    args = parse_args()
    rows: List[Dict[str, object]] = []
    variants = [("preset", 1.0)] + ([(f"opacity x{args.translucent:g}", args.translucent)]
                                    if args.translucent > 0 else [])
    ours = pb.Ours(0, "", alpha=True)
    try:
        for dataset in tqdm(args.datasets, desc="datasets"):
            for name, scale in variants:
                scene = pb.scene_for(dataset, (args.size, args.size))
                if scale != 1.0:
                    scale_opacity(scene, scale)
                for azimuth, elevation in VIEWS:
                    scene.orbit(azimuth, elevation)
                    result = measure(scene, ours, args.rounds, args.ref_spp)
                    base = result["0"]
                    for mode, r in result.items():
                        efficiency = (base["mse"] * base["trace_ms"]) / (r["mse"] * r["trace_ms"])
                        rows.append({"dataset": dataset, "tf": name,
                                     "view": f"{azimuth:g}/{elevation:g}",
                                     "expected_coverage": mode == "1", **r,
                                     "efficiency": efficiency})
                        print(rows[-1], flush=True)
    finally:
        os.environ.pop(VARIABLE, None)
    header = (f"`PTV_EXPECTED_COVERAGE` off (the tracer's default) and on; {args.size}², the "
              f"report's Table-1 views, paper presets and their opacity scaled by "
              f"{args.translucent:g}; time: median 1-spp trace of {args.rounds} interleaved "
              f"rounds; PSNR (tone-mapped) against {args.ref_spp} spp of another seed traced "
              "with the default; efficiency 1 / (MSE x time) at 1 spp, linear radiance, relative "
              "to the default; ours: the shipped model on the 1-spp passes (DenoiseAlpha).")
    lines = [header, ""] + md_table(
        ["dataset", "transfer function", "view", "expected coverage", "trace ms", "1 spp",
         "2 spp", "4 spp", "8 spp", "1 spp + ours", "efficiency"],
        [[r["dataset"], r["tf"], r["view"], "on" if r["expected_coverage"] else "off",
          f"{r['trace_ms']:.1f}", f"{r['raw_1']:.2f}", f"{r['raw_2']:.2f}",
          f"{r['raw_4']:.2f}", f"{r['raw_8']:.2f}", f"{r['ours']:.2f}",
          f"{r['efficiency']:.2f}"] for r in rows])
    pb.save_results(rows, "\n".join(lines), args.json, args.markdown,
                    "Expected coverage on camera rays: variance against time",
                    "expected_coverage.py")
    return 0


if __name__ == "__main__":
    sys.exit(main())
