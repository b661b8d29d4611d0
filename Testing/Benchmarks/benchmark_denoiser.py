#!/usr/bin/env python3
"""Benchmark: our denoiser against Intel Open Image Denoise on the same 1-spp inputs.

For each dataset and size: the 1-spp passes and a high-spp reference of one view are rendered
with vtkPathTracedVolumeMapper (Denoise off) and cached in <cache>/bench; then, in the same run,
vtkPTVDenoiser (the model, every grid level count; with 2 threads, and with 1 thread and with the
portable kernels at the model's level count) and pyoidn's RT filter (quality fast and balanced,
HDR colour + albedo + normal) denoise the same radiance. Times are medians of --repeats runs after
a warm-up; ours is split into features, GuideNet (incl. the guide upsampling), splat (incl.
demodulation) and slice, and given in ns per pixel. PSNR/SSIM (scikit-image, data_range 1)
against the reference, all images tone-mapped clip(max(0,x)^(1/2.2),0,1) (docs/measuring.md).
Run it on an idle machine: nothing else (no build, training or second benchmark) on the cores.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path
from typing import Any, Dict, List

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ptvbench as pb  # noqa: E402  (appends <repo>/Python after PYTHONPATH)
from ptvbench import ROOT, run_oidn, run_ours  # noqa: E402

from pathtracedvolume.atomic import write_text  # noqa: E402

STAGES = ("features", "guidenet", "splat", "slice")


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--datasets", nargs="+", default=["head", "stent", "concrete"])
    parser.add_argument("--sizes", nargs="+", type=int, default=[512, 1024])
    parser.add_argument("--ref-spp", type=int, default=64,
                        help="reference samples per pixel (default 64)")
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--model", default="", help="GuideNet .onnx (default: shipped)")
    parser.add_argument("--json", type=Path, default=None, help="write every row as JSON")
    parser.add_argument("--cache", type=Path,
                        default=Path(os.environ.get("PTV_CACHE_DIR", ROOT / ".cache")) / "bench")
    return parser.parse_args()


def measure(p: pb.Passes, args: argparse.Namespace, levels: int) -> Dict[str, Dict[str, Any]]:
    """Every method on one frame's passes, in one run; ``levels``: the model's level count."""
    full = run_ours(p, 0, args.model, args.repeats)
    methods: Dict[str, Dict[str, Any]] = {"noisy 1 spp": {"ms": 0.0, "image": p["Radiance"]}}
    for count in range(1, levels):
        methods[f"ours {count} level{'s' if count > 1 else ''}"] = run_ours(
            p, count, args.model, args.repeats)
    methods[f"ours {levels} levels"] = full
    methods[f"ours {levels} levels, 1 thread"] = run_ours(p, 0, args.model, args.repeats, 1)
    methods[f"ours {levels} levels, portable kernels"] = run_ours(
        p, 0, args.model, args.repeats, portable=True)
    for q in ("fast", "balanced"):
        methods[f"OIDN RT {q}"] = run_oidn(p, q, args.repeats)
    return methods


def main() -> int:
    args = parse_args()
    rows: List[Dict[str, Any]] = []
    summary = []
    levels = pb.model_levels(args.model)
    for dataset in args.datasets:
        for size in args.sizes:
            p = pb.bench_passes(dataset, size, args.ref_spp, args.cache)
            check = pb.quality(p["Reference"], p["Reference/2"])[0]
            methods = measure(p, args, levels)
            for name, m in methods.items():
                psnr, ssim = pb.quality(p["Reference"], m["image"])
                rows.append({"dataset": dataset, "size": size, "method": name,
                             "ms": m["ms"], "ns_per_pixel": 1e6 * m["ms"] / (size * size),
                             "psnr": psnr, "ssim": ssim,
                             **{k: m[k] for k in (*STAGES, "status", "kernels") if k in m},
                             "reference_spp": args.ref_spp,
                             "reference_half_vs_full_psnr": check})
            sel = {r["method"]: r for r in rows if r["dataset"] == dataset and r["size"] == size}
            ours, oidn = sel[f"ours {levels} levels"], sel["OIDN RT fast"]
            one = sel[f"ours {levels} levels, 1 thread"]
            summary.append(
                f"{dataset} {size}²: OIDN fast / ours = {oidn['ms'] / ours['ms']:.1f}x "
                f"(target >= 10x); PSNR ours - OIDN fast = {ours['psnr'] - oidn['psnr']:+.2f} dB "
                f"(target >= -0.5); 1 -> 2 threads {one['ms'] / ours['ms']:.2f}x; reference "
                f"check (ref/2 vs ref) {check:.1f} dB")
    first = next(r for r in rows if "status" in r)
    print(f"\n{os.cpu_count()} cores; median of {args.repeats} after a warm-up; reference "
          f"{args.ref_spp} spp; model: {first['status']}; grid kernels: {first['kernels']}")
    print("| dataset | size | method | ms | ns/pixel | features | GuideNet | splat | slice "
          "| PSNR | SSIM |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        st = [f"{r[k]:.1f}" if k in r else "" for k in STAGES]
        print(f"| {r['dataset']} | {r['size']}² | {r['method']} | {r['ms']:.1f} | "
              f"{r['ns_per_pixel']:.0f} | {' | '.join(st)} | {r['psnr']:.2f} | "
              f"{r['ssim']:.4f} |")
    print("\n".join(summary))
    if args.json:
        write_text(args.json, json.dumps(rows, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
