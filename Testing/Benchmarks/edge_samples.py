#!/usr/bin/env python3
"""Benchmark: what EdgeSamples buys the denoised frame and what it costs the trace.

With one sample a pixel on the volume's silhouette or on thin structure shows all of its colour
or none, and the denoiser cannot average the two (``docs/edge-samples.md``). The mapper's
EdgeSamples (traced when the frame is denoised; ComputeEdgeSamples here, since this script
denoises the passes itself) gives the pixels whose 3x3 neighbourhood holds both a camera ray of
opacity >= 0.5 and one below 0.05 more samples per frame.

For the report's Table-1 views (``Training/ptv_training/compare.py``'s: paper presets, cameras
30/10 and 150/-20 degrees, 1-spp input of seed 1, ``--reference-spp`` references of another seed,
cached in ``--cache``) and each EdgeSamples count: the share of edge pixels, PSNR of the shipped
model through vtkPTVDenoiser (its automatic level count; the Footprint pass as the mapper gives
it) and of OIDN RT fast on the same passes, after the tone map of ``docs/measuring.md``; and the
trace time of a fresh 1-spp frame with the Coverage and Footprint passes (what the mapper
traces when it denoises), median of ``--rounds`` interleaved rounds, with its ratio to
EdgeSamples 1 (the median of the per-round ratios). It checks that the frame outside the edge
pixels is bit-identical to the frame without edge samples. Run it on an idle machine.

    PYTHONPATH=build/python xvfb-run -a .venv/bin/python Testing/Benchmarks/edge_samples.py
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
from pathlib import Path
from typing import Any, Dict, List

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "Training"))
sys.path.insert(0, str(Path(__file__).resolve().parent))


def parse_args() -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--sizes", nargs="+", type=int, default=[256, 512],
                   help="image sizes (default 256 512)")
    p.add_argument("--counts", nargs="+", type=int, default=[1, 2, 4, 8],
                   help="EdgeSamples values (default 1 2 4 8; 1 = none, the baseline)")
    p.add_argument("--rounds", type=int, default=9, help="timing rounds (default 9)")
    from ptv_training.compare import add_paper_view_arguments
    add_paper_view_arguments(p)
    return p.parse_args()


def frame(scene: Any, view: Dict[str, Any], seed: int, count: int) -> Any:
    """A fresh 1-spp frame of ``view`` with EdgeSamples ``count``; returns the mapper."""
    mapper = scene.set_view(view, seed=seed, max_frames=1, footprint=True)
    mapper.GetExpertOptions().SetEdgeSamples(count)
    mapper.GetExpertOptions().SetComputeEdgeSamples(count > 1)
    scene.render(1)
    return mapper


def main() -> int:
    a = parse_args()
    from evaluation.common import md_table
    from pathtracedvolume.atomic import write_text
    from pathtracedvolume.metrics import psnr
    from pathtracedvolume.edges import edge_mask
    from pathtracedvolume.scene import paper_preset
    from ptv_training import compare, exr_io
    from ptv_training.evaluate import cpp_denoise
    from ptv_training.scene import Scene

    names = list(exr_io.INPUT_PASSES) + ["Footprint"]
    rows: List[Dict[str, Any]] = []
    identical = True
    for size in a.sizes:
        for ds in compare.PAPER_DATASETS:
            scene = Scene(ds, (size, size))
            for cam, (azimuth, elevation) in enumerate(compare.PAPER_CAMERAS):
                cached = compare.paper_view(ds, size, cam, a.reference_spp, a.cache)
                ref = cached["reference"]
                view = {"dataset": ds, "transfer_function": paper_preset(ds),
                        "azimuth": azimuth, "elevation": elevation}
                base: Dict[str, np.ndarray] = {}
                for count in a.counts:
                    mapper = frame(scene, view, compare.PAPER_SEEDS[0], count)
                    passes = {n: scene.get_pass(n) for n in names}
                    if count == 1:
                        base = passes
                        if not all(np.array_equal(passes[n].reshape(cached["inputs"][n].shape),
                                                  cached["inputs"][n]) for n in names):
                            raise RuntimeError(f"{ds} {size} {cam}: the cached view is not "
                                               "this tracer's: delete it from --cache")
                    elif base:
                        changed = np.zeros(passes["Radiance"].shape[:2], bool)
                        for n in names:
                            changed |= np.any((passes[n] != base[n]).reshape(
                                changed.shape + (-1,)), -1)
                        mask = edge_mask(base["Coverage"][..., 0])
                        identical = identical and not bool(np.any(changed & ~mask)) and bool(
                            abs(mask.mean() - mapper.GetStatistics().GetLastEdgeFraction()) < 1e-9)
                    ours = cpp_denoise(a.model, passes, sorted(passes), threads=2)["output"]
                    rows.append({"size": size, "dataset": ds, "camera": cam, "count": count,
                                 "edges": float(mapper.GetStatistics().GetLastEdgeFraction()),
                                 "ours": psnr(ours, ref),
                                 "oidn_fast": psnr(compare.oidn_fast(passes), ref)})
                # timing: interleaved rounds of fresh frames (the second of two: tables warm)
                times: Dict[int, List[float]] = {c: [] for c in a.counts}
                for r in range(a.rounds):
                    for count in a.counts:
                        mapper = scene.set_view(view, seed=100 + r, max_frames=2, footprint=True)
                        mapper.GetExpertOptions().SetEdgeSamples(count)
                        mapper.GetExpertOptions().SetComputeEdgeSamples(count > 1)
                        scene.render(2)
                        times[count].append(float(mapper.GetStatistics().GetLastTraceTime()))
                for row in rows[-len(a.counts):]:
                    c = row["count"]
                    row["trace_ms"] = statistics.median(times[c])
                    row["ratio"] = statistics.median(
                        t / t1 for t, t1 in zip(times[c], times[a.counts[0]]))
                    print(row, flush=True)
    table = [[f"{r['size']}²", r["dataset"], str(r["camera"]), str(r["count"]),
              f"{100 * r['edges']:.1f} %", f"{r['ours']:.2f}", f"{r['oidn_fast']:.2f}",
              f"{r['trace_ms']:.1f}", f"{r['ratio']:.2f}"] for r in rows]
    summary = []
    for size in a.sizes:
        for count in a.counts:
            sel = [r for r in rows if r["size"] == size and r["count"] == count]
            for ds in compare.PAPER_DATASETS + ("**mean**",):
                pick = sel if ds == "**mean**" else [r for r in sel if r["dataset"] == ds]
                summary.append([f"{size}²", ds, str(count),
                                f"{np.mean([r['ours'] for r in pick]):.2f}",
                                f"{np.mean([r['oidn_fast'] for r in pick]):.2f}",
                                f"{np.mean([r['ratio'] for r in pick]):.2f}"])
    text = "\n".join([
        "# EdgeSamples: denoised quality and trace cost", "",
        f"Command (idle machine): `{' '.join(sys.argv)}`", "",
        f"The Table-1 views (`compare.paper_view`: 1-spp passes of seed 1, {a.reference_spp}-spp "
        f"references of another seed) traced with EdgeSamples 1 (none) to {max(a.counts)}; "
        f"`{a.model.name}` through vtkPTVDenoiser (automatic level count: 3 at 256², 1 at "
        "512²; the Footprint pass as the mapper gives it) and OIDN RT fast on the same passes; "
        "PSNR (dB) after the tone map. 'edges': pixels that got the extra samples. Trace: a "
        "fresh 1-spp frame with the Coverage and Footprint passes (what the mapper traces when "
        f"it denoises), median of {a.rounds} interleaved rounds; ratio to EdgeSamples 1: median "
        "of the per-round ratios. Outside the edge pixels every frame is bit-identical to the "
        f"frame without edge samples: {'yes' if identical else 'NO'}.", "",
        "Per dataset (mean of the two views):", "",
        *md_table(["size", "dataset", "EdgeSamples", "ours", "OIDN fast", "trace ÷ none"],
                  summary), "",
        "Per view:", "",
        *md_table(["size", "dataset", "camera", "EdgeSamples", "edges", "ours", "OIDN fast",
                   "trace ms", "trace ÷ none"], table), ""])
    if a.markdown:
        write_text(a.markdown, text)
    if a.json:
        write_text(a.json, json.dumps({"rows": rows, "identical": identical}, indent=1) + "\n")
    print(text)
    return 0 if identical else 1


if __name__ == "__main__":
    sys.exit(main())
