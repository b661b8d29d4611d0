#!/usr/bin/env python3
"""Equal-time quality of the tracer: PSNR of N-spp images against trace time, per build.

For every dataset (its paper preset and the benchmark view of ptvbench.BenchScene) this renders
a reference of --ref-spp samples per pixel once (cached in --cache, seed 1000), then accumulates
N = 1, 2, 4, ... --max-spp frames with seed 1 and records, for each N, the PSNR of the
tone-mapped radiance against the reference and the summed trace time of the N frames (each
frame's own GetStatistics().GetLastTraceTime(), on --threads threads). Rows are appended to --csv under
--label, so running the script once with the build before a change and once with the build
after it (PYTHONPATH picks the build) puts both curves in one CSV; --plot draws every label's
curve per dataset (PSNR against milliseconds, log time axis). A faster estimator at equal
images moves the curve left; a lower-variance one moves it up.

Run on an idle machine; a curve's times come from one run, so compare labels measured one
after the other on the same machine.
"""
from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path
from typing import Dict, List

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ptvbench as pb  # noqa: E402

from tqdm import tqdm  # noqa: E402

FIELDS = ["label", "dataset", "size", "spp", "trace_ms", "psnr_db", "kernel"]


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--label", default="", help="name of this build's curve (measure mode)")
    parser.add_argument("--datasets", nargs="+", default=["head", "stent", "concrete"])
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--max-spp", type=int, default=64)
    parser.add_argument("--ref-spp", type=int, default=512)
    parser.add_argument("--threads", type=int, default=0, help="0: every core")
    parser.add_argument("--cache", type=Path, default=pb.ROOT / ".cache" / "bench" / "equal_time")
    parser.add_argument("--csv", type=Path,
                        default=pb.ROOT / "Testing/Benchmarks/results/tracer_equal_time.csv")
    parser.add_argument("--plot", type=Path, default=None,
                        help="draw the CSV's curves into this PNG (no measuring)")
    return parser.parse_args()


def reference(dataset: str, size: int, spp: int, cache: Path) -> np.ndarray:
    from pathtracedvolume.atomic import atomic_path

    target = cache / f"{dataset}_{size}_{spp}.npy"
    if target.exists():
        return np.load(target)
    scene = pb.scene_for(dataset, (size, size))
    bar = tqdm(total=spp, desc=f"reference {dataset}", unit="spp", leave=False)
    scene.render(seed=1000, frames=spp, on_frame=lambda k: bar.update(1))
    bar.close()
    image = scene.grab("Radiance")
    cache.mkdir(parents=True, exist_ok=True)
    with atomic_path(target, suffix=".tmp.npy") as tmp:
        np.save(tmp, image)
    return image


def measure(args: argparse.Namespace) -> List[Dict[str, object]]:
    from pathtracedvolume import vtkPathTracedVolumeMapper

    kernel = (vtkPathTracedVolumeMapper.GetCpuKernelTarget()
              if hasattr(vtkPathTracedVolumeMapper, "GetCpuKernelTarget") else "baseline")
    rows: List[Dict[str, object]] = []
    counts = [1 << i for i in range(args.max_spp.bit_length()) if (1 << i) <= args.max_spp]
    for dataset in tqdm(args.datasets, desc="datasets"):
        ref = reference(dataset, args.size, args.ref_spp, args.cache)
        scene = pb.scene_for(dataset, (args.size, args.size), threads=args.threads)
        scene.render(seed=7)  # warm-up: volume upload, tables, occupancy
        elapsed = 0.0
        psnr_at: Dict[int, float] = {}
        time_at: Dict[int, float] = {}

        def on_frame(k: int) -> None:
            nonlocal elapsed
            elapsed += float(scene.mapper.GetStatistics().GetLastTraceTime())
            if k in counts:
                psnr_at[k] = pb.quality(ref, scene.grab("Radiance"))[0]
                time_at[k] = elapsed

        scene.render(seed=1, frames=counts[-1], on_frame=on_frame)
        for n in counts:
            rows.append({"label": args.label, "dataset": dataset, "size": args.size, "spp": n,
                         "trace_ms": round(time_at[n], 2), "psnr_db": round(psnr_at[n], 3),
                         "kernel": kernel})
    return rows


def append_rows(path: Path, rows: List[Dict[str, object]]) -> None:
    from pathtracedvolume.atomic import write_text

    old = list(csv.DictReader(path.open())) if path.exists() else []
    labels = {r["label"] for r in rows}
    keep = [r for r in old if r["label"] not in labels]  # re-measuring a label replaces it
    lines = [",".join(FIELDS)]
    for r in keep + rows:
        lines.append(",".join(str(r[f]) for f in FIELDS))
    write_text(path, "\n".join(lines) + "\n")


def plot(csv_path: Path, png: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = list(csv.DictReader(csv_path.open()))
    datasets = list(dict.fromkeys(r["dataset"] for r in rows))
    labels = list(dict.fromkeys(r["label"] for r in rows))
    fig, axes = plt.subplots(1, len(datasets), figsize=(4.2 * len(datasets), 3.6), squeeze=False)
    for ax, dataset in zip(axes[0], datasets):
        for label in labels:
            pts = [(float(r["trace_ms"]), float(r["psnr_db"]), int(r["spp"])) for r in rows
                   if r["dataset"] == dataset and r["label"] == label]
            if not pts:
                continue
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", label=label)
            for t, q, n in pts[::2]:
                ax.annotate(f"{n}", (t, q), fontsize=7, xytext=(3, -9), textcoords="offset points")
        size = next(r["size"] for r in rows if r["dataset"] == dataset)
        ax.set_title(f"{dataset} {size}²")
        ax.set_xscale("log")
        ax.set_xlabel("trace time (ms, N frames)")
        ax.set_ylabel("PSNR vs reference (dB)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("Equal-time quality: N spp (labels) against trace time")
    fig.tight_layout()
    png.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(png, dpi=110)


def main() -> int:
    args = parse_args()
    if args.plot:
        plot(args.csv, args.plot)
        return 0
    if not args.label:
        sys.exit("--label is required when measuring (e.g. --label after)")
    rows = measure(args)
    append_rows(args.csv, rows)
    print(f"{'dataset':10s} {'spp':>4s} {'trace ms':>9s} {'PSNR dB':>8s}  ({args.label}, "
          f"{rows[0]['kernel']})")
    for r in rows:
        print(f"{r['dataset']:10s} {r['spp']:4d} {r['trace_ms']:9.1f} {r['psnr_db']:8.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
