#!/usr/bin/env python3
"""Benchmark: our denoiser (1 and 3 grid levels) against Intel Open Image Denoise on the same 1-spp inputs.

For each dataset and size: the 1-spp passes and a high-spp reference of one view are rendered
with vtkPathTracedVolumeMapper (Denoise off) and cached in <cache>/bench; then, in the same run,
vtkPTVDenoiser (the shipped model, 1 and 3 levels) and pyoidn's RT filter (quality fast and
balanced, HDR colour + albedo + normal) denoise the same radiance. Times are medians of
--repeats runs after a warm-up; ours is split into features, GuideNet, splat (incl.
demodulation) and slice. PSNR/SSIM (scikit-image, data_range 1) against the reference, all images
tone-mapped clip(max(0,x)^(1/2.2),0,1).
"""
from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ptvbench as pb  # noqa: E402  (appends <repo>/Python after PYTHONPATH)
from ptvbench import ROOT, run_oidn, run_ours  # noqa: E402

from pathtracedvolume.atomic import atomic_path, write_text  # noqa: E402
from tqdm import tqdm  # noqa: E402


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--datasets", nargs="+", default=["head"])
    parser.add_argument("--sizes", nargs="+", type=int, default=[512, 1024])
    parser.add_argument("--ref-spp", type=int, default=512,
                        help="reference samples per pixel (default 512)")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--model", default="", help="GuideNet .onnx (default: shipped)")
    parser.add_argument("--json", type=Path, default=None)
    parser.add_argument("--cache", type=Path,
                        default=Path(os.environ.get("PTV_CACHE_DIR", ROOT / ".cache")) / "bench")
    return parser.parse_args()


def render(dataset: str, size: int, ref_spp: int, cache: Path) -> dict[str, np.ndarray]:
    """1-spp passes plus "Reference" (ref_spp) and "Reference/2" (ref_spp/2), cached."""
    target = cache / f"{dataset}_{size}_{ref_spp}.npz"
    if target.exists():
        return dict(np.load(target))
    scene = pb.scene_for(dataset, (size, size))
    scene.render(seed=1)
    out: dict[str, np.ndarray] = scene.passes()
    bar = tqdm(total=ref_spp, desc=f"reference {dataset} {size}²", unit="spp", leave=False)

    def on_frame(k: int) -> None:
        bar.update(1)
        if k == ref_spp // 2:
            out["Reference/2"] = scene.grab("Radiance")
    scene.render(seed=1000, frames=ref_spp, on_frame=on_frame)
    bar.close()
    out["Reference"] = scene.grab("Radiance")
    with atomic_path(target, suffix=".tmp.npz") as tmp:
        np.savez(tmp, **out)
    return out


def main() -> int:
    args = parse_args()
    rows = []
    for dataset in args.datasets:
        for size in args.sizes:
            p = render(dataset, size, args.ref_spp, args.cache)
            check = pb.quality(p["Reference"], p["Reference/2"])[0]
            methods = {"noisy 1 spp": {"ms": 0.0, "image": p["Radiance"]}}
            for levels in (1, 3):
                methods[f"ours {levels} level{'s' if levels > 1 else ''}"] = run_ours(
                    p, levels, args.model, args.repeats)
            for q in ("fast", "balanced"):
                methods[f"OIDN RT {q}"] = run_oidn(p, q, args.repeats)
            for name, m in methods.items():
                psnr, ssim = pb.quality(p["Reference"], m["image"])
                rows.append({"dataset": dataset, "size": size, "method": name,
                             "ms": m["ms"], "psnr": psnr, "ssim": ssim,
                             **{k: m[k] for k in ("features", "guidenet", "splat", "slice",
                                                  "status") if k in m},
                             "reference_spp": args.ref_spp,
                             "reference_half_vs_full_psnr": check})
    print(f"\n{os.cpu_count()} cores; median of {args.repeats} after a warm-up; reference "
          f"{args.ref_spp} spp; model: {rows[1].get('status', '?')}")
    print("| dataset | size | method | ms | features | GuideNet | splat | slice | PSNR | SSIM |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        st = [f"{r[k]:.1f}" if k in r else "" for k in ("features", "guidenet", "splat", "slice")]
        print(f"| {r['dataset']} | {r['size']}² | {r['method']} | {r['ms']:.1f} | "
              f"{' | '.join(st)} | {r['psnr']:.2f} | {r['ssim']:.4f} |")
    for dataset in args.datasets:
        for size in args.sizes:
            sel = {r["method"]: r for r in rows if r["dataset"] == dataset and r["size"] == size}
            ours, oidn = sel["ours 3 levels"], sel["OIDN RT fast"]
            print(f"{dataset} {size}²: OIDN fast / ours (3 levels) time = "
                  f"{oidn['ms'] / ours['ms']:.1f}x, PSNR gap ours - OIDN fast = "
                  f"{ours['psnr'] - oidn['psnr']:+.2f} dB; reference check "
                  f"(ref/2 vs ref) {ours['reference_half_vs_full_psnr']:.1f} dB")
    if args.json:
        write_text(args.json, json.dumps(rows, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
