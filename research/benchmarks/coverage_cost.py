#!/usr/bin/env python3
"""Benchmark: what the Coverage or Footprint pass costs the trace (CoverageMarch, FootprintRays).

With CoverageMarch (on by itself when the denoiser's model reads the "coverage" channel, as the
shipped one does) every camera ray's march is carried on past its event until its transmittance
is below 0.01, for the ray's opacity (``Rendering/Kernels/ptvIntegrator.h``, step 4c). On an
opaque surface that is a few samples; in a fog the rest of the ray.

For every dataset and view (the report's Table-1 views), with its paper preset and with that
preset's opacity scaled by ``--translucent`` (a fog-like transfer function), the median trace
time of a fresh 1-spp frame with CoverageMarch off and on, in ``--rounds`` interleaved rounds,
and their ratio (the median of the per-round ratios). It also checks that every other pass is
bit-identical with the pass on. Run it on an idle machine.

With ``--pass Footprint`` the same for FootprintRays (on by itself whenever the frame is
denoised): camera rays that meet no opacity are followed by four fixed rays through their pixel
(step 4d), so its cost grows with the share of pixels whose ray misses.
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
from pathlib import Path
from typing import Dict, List

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ptvbench as pb  # noqa: E402
from evaluation.common import md_table  # noqa: E402
from expected_coverage import VIEWS, scale_opacity  # noqa: E402

from pathtracedvolume.atomic import write_text  # noqa: E402
from tqdm import tqdm  # noqa: E402


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--datasets", nargs="+", default=["head", "stent", "concrete"])
    parser.add_argument("--sizes", nargs="+", type=int, default=[512])
    parser.add_argument("--translucent", type=float, default=0.1,
                        help="opacity scale of the fog-like variant (default 0.1; 0: none)")
    parser.add_argument("--rounds", type=int, default=9, help="timing rounds (default 9)")
    parser.add_argument("--pass", dest="name", choices=["Coverage", "Footprint"],
                        default="Coverage", help="the pass whose switch is timed (Coverage)")
    parser.add_argument("--json", type=Path, default=None)
    parser.add_argument("--markdown", type=Path, default=None)
    return parser.parse_args()


def switch(scene: pb.BenchScene, name: str, on: bool) -> None:
    """CoverageMarch or FootprintRays of the scene's mapper (its expert options)."""
    option = {"Coverage": "CoverageMarch", "Footprint": "FootprintRays"}[name]
    getattr(scene.mapper.GetExpertOptions(), f"Set{option}")(on)


def trace_ms(scene: pb.BenchScene, name: str, on: bool, seed: int) -> float:
    """Trace milliseconds of a fresh 1-spp frame (the second of two: tables are warm)."""
    switch(scene, name, on)
    scene.render(seed=seed, frames=2)
    return float(scene.mapper.GetLastTraceTime())


def measure(scene: pb.BenchScene, name: str, rounds: int) -> Dict[str, float]:
    if name == "Coverage":
        # the march alone; the Footprint pass as in a frame
        scene.mapper.GetExpertOptions().FootprintRaysOff()
    off: List[float] = []
    on: List[float] = []
    for r in range(rounds):
        off.append(trace_ms(scene, name, False, 100 + r))
        on.append(trace_ms(scene, name, True, 100 + r))
    passes = {}
    for state in (False, True):
        switch(scene, name, state)
        scene.render(seed=1, frames=1)
        passes[state] = scene.passes()
    switch(scene, name, False)
    same = all(np.array_equal(passes[False][other], passes[True][other])
               for other in pb.PASSES if other != name)
    row = {"off_ms": statistics.median(off), "on_ms": statistics.median(on),
           "ratio": statistics.median(b / a for a, b in zip(off, on)),
           "other_passes_identical": bool(same)}
    if name == "Coverage":
        c = passes[True]["Coverage"][..., 0]
        covered = c > 0.001
        row["covered"] = float(covered.mean())
        row["translucent_share"] = float(((c < 0.99) & covered).sum() / max(covered.sum(), 1))
    else:
        depth = passes[True]["Depth"][..., 0]
        row["missed"] = float((depth >= depth.max()).mean())  # the four rays follow these
        row["empty"] = float((passes[True]["Footprint"][..., 0] == 0).mean())
    return row


def main() -> int:
    args = parse_args()
    rows: List[Dict[str, object]] = []
    variants = [("preset", 1.0)] + ([(f"opacity x{args.translucent:g}", args.translucent)]
                                    if args.translucent > 0 else [])
    for size in args.sizes:
        for dataset in tqdm(args.datasets, desc=f"{size}²"):
            for name, scale in variants:
                scene = pb.scene_for(dataset, (size, size))
                scene.mapper.SetDenoise(False)
                if scale != 1.0:
                    scale_opacity(scene, scale)
                for azimuth, elevation in VIEWS:
                    scene.orbit(azimuth, elevation)
                    rows.append({"size": size, "dataset": dataset, "tf": name,
                                 "view": f"{azimuth:g}/{elevation:g}",
                                 **measure(scene, args.name, args.rounds)})
                    print(rows[-1], flush=True)
    coverage = args.name == "Coverage"
    header = (f"Trace time of a fresh 1-spp frame with Compute{args.name} off and on (median of "
              f"{args.rounds} interleaved rounds; ratio: median of the per-round ratios), Denoise "
              f"off; the report's Table-1 views, paper presets and their opacity scaled by "
              f"{args.translucent:g}; " + (
                  "'translucent share': covered pixels (Coverage > 0.001) whose Coverage is "
                  "below 0.99." if coverage else
                  "'missed': pixels whose camera ray met no opacity (the four rays follow "
                  "them); 'empty': pixels whose Footprint is 0."))
    extra = ["translucent share"] if coverage else ["missed", "empty"]
    table = md_table(
        ["size", "dataset", "transfer function", "view", "off ms", "on ms", "on / off",
         *extra, "other passes identical"],
        [[f"{r['size']}²", r["dataset"], r["tf"], r["view"], f"{r['off_ms']:.1f}",
          f"{r['on_ms']:.1f}", f"{r['ratio']:.3f}",
          *([f"{r['translucent_share']:.2f}"] if coverage else
            [f"{r['missed']:.2f}", f"{r['empty']:.2f}"]),
          "yes" if r["other_passes_identical"] else "NO"] for r in rows])
    text = (f"# The {args.name} pass: trace cost\n\nCommand (idle machine): "
            f"`{' '.join(sys.argv)}`\n\n")
    text += header + "\n\n" + "\n".join(table) + "\n"
    if args.markdown:
        write_text(args.markdown, text)
    if args.json:
        write_text(args.json, json.dumps({"rows": rows}, indent=1) + "\n")
    print(text)
    return 0 if all(r["other_passes_identical"] for r in rows) else 1


if __name__ == "__main__":
    raise SystemExit(main())
