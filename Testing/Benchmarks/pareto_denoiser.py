#!/usr/bin/env python3
"""Pareto chart of the denoiser: PSNR against denoise time, one point per GuideNet variant and grid
level count, with OIDN RT fast and balanced on the same passes as references.

For each dataset the benchmark frame's 1-spp passes and reference come from the cache shared with
benchmark_denoiser.py (<cache>/bench, rendered on first use). Every model given with --models
(default: the shipped model and every exported run of the "v2-cpu" study,
Training/results/v2-cpu.md, whose runs share the second data set and step budget)
runs through vtkPTVDenoiser (C++, ONNX Runtime, 2 threads) at each level count 1..L; times are
medians of --repeats after a warm-up, all in one run (docs/measuring.md). Writes
<out>/denoiser_pareto.{csv,json,png}: the chart has one panel per dataset and one for the mean
over datasets, x = ms (log), y = PSNR; the front (no point both faster and better) is drawn.
Run it on an idle machine.
"""
from __future__ import annotations

import argparse
import csv
import io
import json
import os
import sys
from pathlib import Path
from typing import Any, Dict, List, Tuple

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ptvbench as pb  # noqa: E402  (appends <repo>/Python after PYTHONPATH)
from ptvbench import ROOT, run_oidn, run_ours  # noqa: E402

from pathtracedvolume.atomic import atomic_path, write_text  # noqa: E402
from tqdm import tqdm  # noqa: E402

SHIPPED = pb.SHIPPED_MODEL
STUDY_RUNS = ROOT / ".cache" / "training" / "runs"
OIDN = ("OIDN RT fast", "OIDN RT balanced")


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--models", nargs="*", type=Path, default=None,
                        help="GuideNet .onnx files (default: shipped + "
                             "<runs>/study_v2-cpu_*/model.onnx + the shipped architecture's "
                             "study run, study_v2-features_paper10)")
    parser.add_argument("--runs", type=Path, default=STUDY_RUNS,
                        help=f"study runs searched by default (default {STUDY_RUNS})")
    parser.add_argument("--datasets", nargs="+", default=["head", "stent", "concrete"])
    parser.add_argument("--size", type=int, default=1024)
    parser.add_argument("--ref-spp", type=int, default=64)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--out", type=Path, default=ROOT / "Testing" / "Benchmarks" / "results")
    parser.add_argument("--replot", action="store_true",
                        help="redraw <out>/denoiser_pareto.png from its .json, measuring nothing")
    parser.add_argument("--cache", type=Path,
                        default=Path(os.environ.get("PTV_CACHE_DIR", ROOT / ".cache")) / "bench")
    return parser.parse_args()


def model_list(args: argparse.Namespace) -> List[Tuple[str, Path]]:
    """(name, path) of every model to chart."""
    paths = args.models
    if paths is None:
        # the v2-cpu study's runs, and the shipped architecture's run (v2-features' it shares)
        paths = [SHIPPED] + sorted(args.runs.glob("study_v2-features_paper10/model.onnx")) + \
            sorted(args.runs.glob("study_v2-cpu_*/model.onnx"))
    return [("shipped" if p.resolve() == SHIPPED.resolve()
             else "h16_k5_s2" if p.parent.name == "study_v2-features_paper10"
             else p.parent.name.removeprefix("study_v2-cpu_"), p)
            for p in paths]


def front(points: List[Tuple[float, float]]) -> List[Tuple[float, float]]:
    """Points no other point beats on both time (lower) and PSNR (higher), by time."""
    kept, best = [], -1e9
    for ms, psnr in sorted(points):
        if psnr > best:
            kept.append((ms, psnr))
            best = psnr
    return kept


def chart(rows: List[Dict[str, Any]], datasets: List[str], size: int, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = datasets + ["mean"]
    models = sorted({r["model"] for r in rows if r["method"] not in OIDN})
    colours = {m: plt.get_cmap("tab20")(i % 20) for i, m in enumerate(models)}
    fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels), 4.6), squeeze=False)
    for ax, panel in zip(axes[0], panels):
        sel = [r for r in rows if r["dataset"] == panel]
        ours = [r for r in sel if r["method"] not in OIDN]
        for model in models:
            pts = sorted(((r["ms"], r["psnr"], r["levels"]) for r in ours if r["model"] == model),
                         key=lambda t: t[2])  # joined in level order 1, 2, 3
            shipped = model == "shipped"
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", ms=7 if shipped else 4,
                    lw=2.5 if shipped else 1, color="k" if shipped else colours[model],
                    label=model, zorder=3 if shipped else 2)
            for ms, psnr, levels in pts:
                ax.annotate(str(levels), (ms, psnr), fontsize=6, xytext=(2, 2),
                            textcoords="offset points")
        for r in sel:
            if r["method"] in OIDN:
                ax.plot(r["ms"], r["psnr"], "k*" if "fast" in r["method"] else "kP", ms=9,
                        label=r["method"])
        fast = next((r for r in sel if r["method"] == "OIDN RT fast"), None)
        if fast:  # the targets: a tenth of OIDN fast's time, its PSNR - 0.5 dB
            ax.axvline(fast["ms"] / 10, color="k", ls=":", lw=0.8, label="OIDN fast / 10")
            ax.axhline(fast["psnr"] - 0.5, color="k", ls="--", lw=0.8,
                       label="OIDN fast - 0.5 dB")
        f = front([(r["ms"], r["psnr"]) for r in ours])
        ax.plot([p[0] for p in f], [p[1] for p in f], "-", color="grey", lw=3, alpha=0.3,
                label="front (ours)")
        ax.set_xscale("log")
        ax.set_xlabel("denoise ms (log)")
        ax.set_ylabel("PSNR dB")
        ax.set_title(f"{panel} {size}²")
        ax.grid(alpha=0.3)
    axes[0][-1].legend(fontsize=6, loc="lower right")
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=110)
    plt.close(fig)
    with atomic_path(path, suffix=".tmp.png") as tmp:
        Path(tmp).write_bytes(buffer.getvalue())


def main() -> int:
    args = parse_args()
    if args.replot:
        saved = json.loads((args.out / "denoiser_pareto.json").read_text())
        datasets = list(dict.fromkeys(r["dataset"] for r in saved["rows"] if r["dataset"] != "mean"))
        chart(saved["rows"], datasets, saved["size"], args.out / "denoiser_pareto.png")
        print(f"redrew {args.out / 'denoiser_pareto.png'}")
        return 0
    models = model_list(args)
    rows: List[Dict[str, Any]] = []
    for dataset in args.datasets:
        p = pb.bench_passes(dataset, args.size, args.ref_spp, args.cache)
        jobs = [(name, path, levels) for name, path in models
                for levels in range(1, pb.model_levels(path) + 1)]
        for name, path, levels in tqdm(jobs, desc=dataset, leave=False):
            m = run_ours(p, levels, str(path), args.repeats, alpha=False)  # colour, like OIDN
            if not m["status"].startswith("GuideNet"):
                raise RuntimeError(f"{path}: the denoiser fell back: {m['status']}")
            psnr, ssim = pb.quality(p["Reference"], m["image"])
            rows.append({"dataset": dataset, "method": f"{name} L{levels}", "model": name,
                         "levels": levels, "ms": m["ms"], "psnr": psnr, "ssim": ssim,
                         **{k: m[k] for k in ("features", "guidenet", "splat", "slice")}})
        for q in ("fast", "balanced"):
            m = run_oidn(p, q, args.repeats)
            psnr, ssim = pb.quality(p["Reference"], m["image"])
            rows.append({"dataset": dataset, "method": f"OIDN RT {q}", "model": "OIDN",
                         "levels": 0, "ms": m["ms"], "psnr": psnr, "ssim": ssim})
    for method in dict.fromkeys(r["method"] for r in rows):
        sel = [r for r in rows if r["method"] == method]
        mean = {k: sum(r[k] for r in sel) / len(sel) for k in ("ms", "psnr", "ssim")}
        rows.append({"dataset": "mean", "method": method, "model": sel[0]["model"],
                     "levels": sel[0]["levels"], **mean})
    args.out.mkdir(parents=True, exist_ok=True)
    fields = ["dataset", "method", "model", "levels", "ms", "psnr", "ssim",
              "features", "guidenet", "splat", "slice"]
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=fields, extrasaction="ignore")
    writer.writeheader()
    for r in rows:
        writer.writerow({k: (f"{v:.4f}" if isinstance(v, float) else v) for k, v in r.items()})
    write_text(args.out / "denoiser_pareto.csv", text.getvalue())
    write_text(args.out / "denoiser_pareto.json", json.dumps(
        {"size": args.size, "reference_spp": args.ref_spp, "repeats": args.repeats,
         "cores": os.cpu_count(), "models": {n: str(p) for n, p in models}, "rows": rows},
        indent=2))
    chart(rows, args.datasets, args.size, args.out / "denoiser_pareto.png")
    print(f"{os.cpu_count()} cores, {args.size}², median of {args.repeats}; "
          f"wrote {args.out / 'denoiser_pareto.csv'} and .png")
    print("| dataset | method | ms | PSNR | SSIM |")
    print("|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['dataset']} | {r['method']} | {r['ms']:.1f} | {r['psnr']:.2f} | "
              f"{r['ssim']:.4f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
