#!/usr/bin/env python3
"""Ablation: the step of shadow and environment rays, quality against time.

Transmittance rays (towards the light, and the environment-occlusion ray) march jittered
samples at ShadowStepScale camera steps with the opacity corrected for that step. A longer step
costs less and moves the converged image where the medium varies faster than the step (thin
bands, edges): the jittered product of per-step opacities is then a coarser quadrature of the
transmittance. For every dataset (its paper preset, ptvbench's benchmark view) and each scale
in --scales (set through PTV_SHADOW_STEP_SCALE):

- time: the median trace time of a 1-spp frame at --time-size² in --rounds interleaved rounds (every scale once
  per round, so a slow spell of the machine slows all of them alike), as a ratio to --default;
- bias: PSNR of a --bias-spp image at that scale against the --ref-spp reference at scale 1
  (one camera step, another seed): how far the coarser quadrature moves the converged image
  (the scale-1 row is the noise floor of the comparison);
- equal time: PSNR against that reference of the image the scale accumulates in the time the
  default takes for --budget-spp frames (frame count scaled by the time ratio, rounded down),
  which weighs the bias against the samples the saved time buys.

A longer default step is worth it only where the equal-time PSNR does not fall on any dataset
and the bias stays invisible (> 40 dB, docs/measuring.md). Run it on an idle machine.
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

from tqdm import tqdm  # noqa: E402

VARIABLE = "PTV_SHADOW_STEP_SCALE"


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--datasets", nargs="+", default=["head", "stent", "concrete"])
    parser.add_argument("--size", type=int, default=256, help="image size for the quality")
    parser.add_argument("--time-size", type=int, default=512, help="image size for the time")
    parser.add_argument("--scales", type=float, nargs="+", default=[1.0, 2.0, 3.0, 4.0])
    parser.add_argument("--default", type=float, default=2.0,
                        help="the scale the others are timed against (today's default)")
    parser.add_argument("--rounds", type=int, default=9, help="timing rounds (default 9)")
    parser.add_argument("--ref-spp", type=int, default=1024)
    parser.add_argument("--bias-spp", type=int, default=512)
    parser.add_argument("--budget-spp", type=int, default=16,
                        help="equal-time budget: this many frames at the default scale")
    parser.add_argument("--json", type=Path, default=None)
    parser.add_argument("--markdown", type=Path, default=None)
    return parser.parse_args()


def accumulate(scene: pb.BenchScene, scale: float, seed: int, frames: int) -> np.ndarray:
    os.environ[VARIABLE] = repr(scale)
    scene.render(seed=seed, frames=frames)
    return scene.grab("Radiance")


def main() -> int:
    args = parse_args()
    if args.default not in args.scales:
        args.scales.insert(0, args.default)
    rows: List[Dict[str, object]] = []
    try:
        for dataset in tqdm(args.datasets, desc="datasets"):
            timing = pb.scene_for(dataset, (args.time_size, args.time_size))
            times: Dict[float, List[float]] = {s: [] for s in args.scales}
            for _ in range(args.rounds):
                for scale in args.scales:
                    accumulate(timing, scale, 7, 1)  # the step tables for this scale
                    timing.render(seed=8, frames=2)  # the second frame's trace: tables warm
                    times[scale].append(float(timing.mapper.GetLastTraceTime()))
            del timing
            scene = pb.scene_for(dataset, (args.size, args.size))
            ref = accumulate(scene, 1.0, 1000, args.ref_spp)
            ratios = {s: pb.paired_ratio(times[s], times[args.default]) for s in args.scales}
            for scale in args.scales:
                bias = pb.quality(ref, accumulate(scene, scale, 1, args.bias_spp))[0]
                frames = max(1, int(args.budget_spp / ratios[scale]))
                equal = pb.quality(ref, accumulate(scene, scale, 1, frames))[0]
                rows.append({"dataset": dataset, "scale": scale,
                             "trace_ms": round(statistics.median(times[scale]), 2),
                             "time_ratio": round(ratios[scale], 3),
                             "bias_psnr": round(bias, 2), "equal_time_spp": frames,
                             "equal_time_psnr": round(equal, 2)})
                print(rows[-1], flush=True)
    finally:
        os.environ.pop(VARIABLE, None)
    header = (f"{args.size}², paper presets, benchmark views; time: median 1-spp trace at "
              f"{args.time_size}² of {args.rounds} interleaved rounds, ratio to scale {args.default:g} (median of the "
              f"rounds' ratios); bias: {args.bias_spp} spp at the scale vs {args.ref_spp} spp "
              f"at scale 1 (another seed); equal time: the frames the scale traces in the time "
              f"of {args.budget_spp} at scale {args.default:g}")
    lines = [header, ""] + md_table(
        ["dataset", "shadow step (camera steps)", "trace ms", "time ratio", "bias PSNR (dB)",
         "equal-time spp", "equal-time PSNR (dB)"],
        [[r["dataset"], f"{r['scale']:g}", f"{r['trace_ms']:.1f}", f"{r['time_ratio']:.3f}",
          f"{r['bias_psnr']:.2f}", r["equal_time_spp"], f"{r['equal_time_psnr']:.2f}"]
         for r in rows])
    pb.save_results(rows, "\n".join(lines), args.json, args.markdown,
                    "Shadow and environment step: quality against time", "shadow_step.py")
    return 0


if __name__ == "__main__":
    sys.exit(main())
