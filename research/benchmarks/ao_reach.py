#!/usr/bin/env python3
"""Ablation: how far environment rays look for occluders (AmbientOcclusionReach), quality
against time.

For every dataset (its paper preset, ptvbench's benchmark view) and each reach r in --reaches
(a fraction of the volume's diagonal; 1 = to the volume's exit, today's default):

- time: the median trace time of a 1-spp frame, measured in interleaved rounds (every reach once
  per round, so a slow spell of the machine slows all of them alike);
- bias: PSNR of a --bias-spp image at reach r against the --ref-spp reference at reach 1 (another
  seed): how far local occlusion moves the converged image (inf = none);
- equal time: PSNR against that reference of the image reach r accumulates in the time reach 1
  takes for --budget-spp frames (its frame count scaled by the time ratio, rounded down), which
  weighs the bias against the samples the saved time buys.

A default below 1 is worth it only where the equal-time PSNR rises on every dataset and the bias
stays invisible (docs/measuring.md's tone mapping; > 40 dB). Run it on an idle machine.
"""
from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path
from typing import Dict, List

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ptvbench as pb  # noqa: E402
from evaluation.common import md_table  # noqa: E402

from tqdm import tqdm  # noqa: E402


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--datasets", nargs="+", default=["head", "stent", "concrete"])
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--reaches", type=float, nargs="+", default=[1.0, 0.5, 0.25, 0.1, 0.05])
    parser.add_argument("--rounds", type=int, default=7, help="timing rounds (default 7)")
    parser.add_argument("--ref-spp", type=int, default=1024)
    parser.add_argument("--bias-spp", type=int, default=512)
    parser.add_argument("--budget-spp", type=int, default=16,
                        help="equal-time budget: this many frames at reach 1")
    parser.add_argument("--json", type=Path, default=None)
    parser.add_argument("--markdown", type=Path, default=None)
    return parser.parse_args()


def accumulate(scene: pb.BenchScene, reach: float, seed: int, frames: int) -> np.ndarray:
    scene.mapper.GetExpertOptions().SetAmbientOcclusionReach(reach)
    scene.render(seed=seed, frames=frames)
    return scene.grab("Radiance")


def main() -> int:
    args = parse_args()
    rows: List[Dict[str, object]] = []
    for dataset in tqdm(args.datasets, desc="datasets"):
        scene = pb.scene_for(dataset, (args.size, args.size))
        ref = accumulate(scene, 1.0, 1000, args.ref_spp)
        times: Dict[float, List[float]] = {r: [] for r in args.reaches}
        for _ in range(args.rounds):
            for reach in args.reaches:
                accumulate(scene, reach, 7, 1)
                scene.render(seed=8, frames=2)  # the second frame's trace: tables are warm
                times[reach].append(float(scene.mapper.GetLastTraceTime()))
        t1 = statistics.median(times[1.0]) if 1.0 in times else None
        for reach in args.reaches:
            t = statistics.median(times[reach])
            bias = pb.quality(ref, accumulate(scene, reach, 1, args.bias_spp))[0]
            frames = max(1, int(args.budget_spp * (t1 / t))) if t1 else args.budget_spp
            equal = pb.quality(ref, accumulate(scene, reach, 1, frames))[0]
            rows.append({"dataset": dataset, "reach": reach, "trace_ms": round(t, 2),
                         "speedup": round(t1 / t, 3) if t1 else None,
                         "bias_psnr": round(bias, 2), "equal_time_spp": frames,
                         "equal_time_psnr": round(equal, 2)})
            print(rows[-1], flush=True)
    header = (f"{args.size}², paper presets, benchmark views; time: median 1-spp trace of "
              f"{args.rounds} interleaved rounds; bias: {args.bias_spp} spp at reach r vs "
              f"{args.ref_spp} spp at reach 1 (another seed); equal time: the frames reach r "
              f"traces in the time of {args.budget_spp} at reach 1")
    lines = [header, ""] + md_table(
        ["dataset", "reach", "trace ms", "speed-up", "bias PSNR (dB)", "equal-time spp",
         "equal-time PSNR (dB)"],
        [[r["dataset"], f"{r['reach']:g}", f"{r['trace_ms']:.1f}", f"{r['speedup']:.2f}",
          f"{r['bias_psnr']:.2f}", r["equal_time_spp"], f"{r['equal_time_psnr']:.2f}"]
         for r in rows])
    pb.save_results(rows, "\n".join(lines), args.json, args.markdown,
                    "Ambient-occlusion reach: quality against time", "ao_reach.py")
    return 0


if __name__ == "__main__":
    sys.exit(main())
