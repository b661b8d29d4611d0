#!/usr/bin/env python3
"""Ablation: where transmittance rays start Russian roulette, variance against time.

Shadow and environment rays multiply their transmittance T by (1 - a) per absorbing sample and,
once T drops below a threshold, survive each further absorbing sample with probability 1/2
(T doubled) or end with T = 0. Any threshold is unbiased; a higher one ends rays sooner (less
time) and adds variance. What matters is the efficiency 1 / (variance x time): the time to reach
a given noise level. For every dataset (its paper preset, ptvbench's benchmark view) and each
threshold in --thresholds (set through PTV_ROULETTE_THRESHOLD):
- time: the median trace time of a 1-spp frame in --rounds interleaved rounds (every threshold
  once per round, so a slow spell of the machine slows all of them alike);
- variance: the per-pixel variance of --frames independent 1-spp radiance frames (linear, every
  channel), averaged over the image;
- efficiency: 1 / (variance x time), relative to the first threshold.
The default (kRouletteThreshold in Rendering/Kernels/ptvShading.h) is worth changing only where
the efficiency rises on every dataset. Run it on an idle machine.
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

VARIABLE = "PTV_ROULETTE_THRESHOLD"


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--datasets", nargs="+", default=["head", "stent", "concrete"])
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--thresholds", type=float, nargs="+",
                        default=[0.05, 0.1, 0.15, 0.25, 0.4])
    parser.add_argument("--rounds", type=int, default=7, help="timing rounds (default 7)")
    parser.add_argument("--frames", type=int, default=32,
                        help="independent 1-spp frames per variance (default 32)")
    parser.add_argument("--json", type=Path, default=None)
    parser.add_argument("--markdown", type=Path, default=None)
    return parser.parse_args()


def use_threshold(threshold: float) -> None:
    os.environ[VARIABLE] = repr(threshold)


def frame_time(scene: pb.BenchScene, seed: int) -> float:
    """Trace milliseconds of a fresh 1-spp frame (the second of two: tables are warm)."""
    scene.render(seed=seed, frames=2)
    return float(scene.mapper.GetLastTraceTime())


def variance(scene: pb.BenchScene, frames: int) -> float:
    """Mean over pixels and channels of the variance of independent 1-spp radiance frames."""
    stack = []
    for k in range(frames):
        scene.render(seed=100 + k, frames=1)
        stack.append(scene.grab("Radiance").astype(np.float64))
    return float(np.stack(stack).var(axis=0, ddof=1).mean())


def main() -> int:
    args = parse_args()
    rows: List[Dict[str, object]] = []
    try:
        for dataset in tqdm(args.datasets, desc="datasets"):
            scene = pb.scene_for(dataset, (args.size, args.size))
            times: Dict[float, List[float]] = {t: [] for t in args.thresholds}
            for r in range(args.rounds):
                for threshold in args.thresholds:
                    use_threshold(threshold)
                    times[threshold].append(frame_time(scene, 8 + r))
            first = None
            for threshold in args.thresholds:
                use_threshold(threshold)
                t = statistics.median(times[threshold])
                v = variance(scene, args.frames)
                efficiency = 1.0 / (v * t)
                first = first or efficiency
                rows.append({"dataset": dataset, "threshold": threshold, "trace_ms": round(t, 2),
                             "variance": v, "efficiency": round(efficiency / first, 4)})
                print(rows[-1], flush=True)
    finally:
        os.environ.pop(VARIABLE, None)
    base = {r["dataset"]: r for r in rows if r["threshold"] == args.thresholds[0]}
    header = (f"{args.size}², paper presets, benchmark views; time: median 1-spp trace of "
              f"{args.rounds} interleaved rounds; variance: mean per-pixel variance of "
              f"{args.frames} independent 1-spp radiance frames; efficiency 1 / (variance x "
              f"time), relative to threshold {args.thresholds[0]:g}")
    lines = [header, ""] + md_table(
        ["dataset", "threshold", "trace ms", "time ratio", "variance ratio", "efficiency"],
        [[r["dataset"], f"{r['threshold']:g}", f"{r['trace_ms']:.1f}",
          f"{r['trace_ms'] / base[r['dataset']]['trace_ms']:.3f}",
          f"{r['variance'] / base[r['dataset']]['variance']:.3f}", f"{r['efficiency']:.3f}"]
         for r in rows])
    pb.save_results(rows, "\n".join(lines), args.json, args.markdown,
                    "Russian roulette threshold: variance against time", "roulette.py")
    return 0


if __name__ == "__main__":
    sys.exit(main())
