"""Images that converge: the shown image (pass Converged) against raw and denoised, 1..1024 spp,
and the still-render stopping rule's estimate against the measured error.

For each dataset (256², paper preset, the benchmark view of ptvbench):
  * a reference of ``--ref-spp`` samples (seed 1000) and the reference's own error, from its two
    halves (each half's MSE against the truth is twice the whole's);
  * one accumulation (seed 1, Denoise on, one frame per Render) read at 1, 2, 4, ... 1024 spp:
    PSNR of Radiance (raw), Denoised and Converged against the reference (tone-mapped,
    docs/measuring.md); the check is Converged >= max(raw, denoised) - 0.3 dB at every spp and
    >= raw - 0.3 dB from 256 spp on;
  * still renders (the mapper's default ConvergeStillRenders, seed 2) at each ``--quality``:
    frames, seconds, the mapper's EstimatedQuality and the measured PSNR of what it shows
    (against the reference, less the reference's own error): the estimate must not be
    optimistic by more than 1 dB.

Writes ``results/convergence.csv`` (the sweep), ``results/convergence_stop.csv`` (the stops)
and ``results/convergence.png``. Run on an idle machine (the seconds are timings)::

    PYTHONPATH=build/python xvfb-run -a .venv/bin/python Testing/Benchmarks/convergence.py
"""
from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path
from typing import Dict, List

import numpy as np
from tqdm import tqdm

import ptvbench as pb

RESULTS = Path(__file__).resolve().parent / "results"


def tone_mse(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.mean((pb.tonemap(a).astype(np.float64) - pb.tonemap(b)) ** 2))


def psnr(mse: float) -> float:
    return float(-10.0 * np.log10(max(mse, 1e-20)))


def reference(dataset: str, size: int, spp: int) -> tuple:
    """(reference radiance, its own tone-mapped MSE)."""
    scene = pb.scene_for(dataset, (size, size))
    scene.mapper.SetSamplesPerFrame(16)
    frames = max(spp // 16, 2)
    half: Dict[str, np.ndarray] = {}

    def on_frame(k: int) -> None:
        if k == frames // 2:
            half["a"] = scene.grab("Radiance")
    scene.render(seed=1000, frames=frames, on_frame=on_frame)
    whole = scene.grab("Radiance")
    other = 2.0 * whole - half["a"]
    return whole, tone_mse(half["a"], other) / 4.0


def sweep(dataset: str, size: int, ref: np.ndarray, max_spp: int) -> List[dict]:
    scene = pb.scene_for(dataset, (size, size))
    scene.mapper.DenoiseOn()
    rows = []
    bar = tqdm(total=max_spp, desc=f"sweep {dataset}", unit="spp", leave=False)

    def on_frame(k: int) -> None:
        bar.update(1)
        if k & (k - 1) == 0:
            row = {"dataset": dataset, "spp": k}
            for key, name in (("raw", "Radiance"), ("denoised", "Denoised"),
                              ("converged", "Converged")):
                row[key] = psnr(tone_mse(scene.grab(name), ref))
            row["estimated"] = float(scene.mapper.GetEstimatedQuality())
            rows.append(row)
    scene.render(seed=1, frames=max_spp, on_frame=on_frame)
    bar.close()
    return rows


def stops(dataset: str, size: int, ref: np.ndarray, ref_mse: float,
          qualities: List[float]) -> List[dict]:
    rows = []
    for quality in qualities:
        scene = pb.scene_for(dataset, (size, size))
        m = scene.mapper
        m.DenoiseOn()
        m.ConvergeStillRendersOn()
        m.SetStillQuality(quality)
        m.SetStillTimeBudget(0.0)  # the quality alone stops it
        m.SetSeed(2)
        start = time.perf_counter()
        scene.window.Render()  # VTK's default desired update rate: a still render
        seconds = time.perf_counter() - start
        shown = scene.grab("Converged")
        mse = tone_mse(shown, ref)
        rows.append({"dataset": dataset, "quality": quality, "frames": m.GetStatistics().GetLastRenderFrames(),
                     "seconds": seconds, "estimated": m.GetEstimatedQuality(),
                     "measured": psnr(max(mse - ref_mse, 1e-20)), "vs_reference": psnr(mse),
                     "converged": bool(m.GetStillConverged())})
    return rows


def chart(rows: List[dict], path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    datasets = sorted({r["dataset"] for r in rows})
    fig, axes = plt.subplots(1, len(datasets), figsize=(5 * len(datasets), 4), squeeze=False)
    for ax, ds in zip(axes[0], datasets):
        sub = [r for r in rows if r["dataset"] == ds]
        spp = [r["spp"] for r in sub]
        for key, style in (("raw", "o-"), ("denoised", "s-"), ("converged", "^-"),
                           ("estimated", "x:")):
            ax.plot(spp, [r[key] for r in sub], style, label=key, markersize=4)
        ax.set_xscale("log", base=2)
        ax.set_xlabel("samples per pixel")
        ax.set_ylabel("PSNR (dB, tone-mapped)")
        ax.set_title(ds)
        ax.grid(True, alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def write_csv(rows: List[dict], path: Path) -> None:
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        for r in rows:
            writer.writerow({k: (f"{v:.3f}" if isinstance(v, float) else v) for k, v in r.items()})


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--datasets", nargs="+", default=["head", "stent", "concrete"])
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--max-spp", type=int, default=1024)
    parser.add_argument("--ref-spp", type=int, default=2048)
    parser.add_argument("--quality", type=float, nargs="+", default=[35.0, 40.0, 45.0])
    parser.add_argument("--out", type=Path, default=RESULTS)
    args = parser.parse_args()

    sweep_rows: List[dict] = []
    stop_rows: List[dict] = []
    failures = []
    for ds in args.datasets:
        ref, ref_mse = reference(ds, args.size, args.ref_spp)
        print(f"{ds}: reference {args.ref_spp} spp, its own error {psnr(ref_mse):.2f} dB")
        rows = sweep(ds, args.size, ref, args.max_spp)
        sweep_rows += rows
        print(f"{'spp':>5} {'raw':>7} {'denoised':>9} {'converged':>10} {'estimated':>10}")
        for r in rows:
            print(f"{r['spp']:5d} {r['raw']:7.2f} {r['denoised']:9.2f} {r['converged']:10.2f} "
                  f"{r['estimated']:10.2f}")
            if r["converged"] < max(r["raw"], r["denoised"]) - 0.3:
                failures.append(f"{ds} {r['spp']} spp: converged below max - 0.3 dB")
            if r["spp"] >= 256 and r["converged"] < r["raw"] - 0.3:
                failures.append(f"{ds} {r['spp']} spp: converged below raw - 0.3 dB")
        for r in stops(ds, args.size, ref, ref_mse, args.quality):
            stop_rows.append(r)
            print(f"  StillQuality {r['quality']:.0f}: {r['frames']} frames, {r['seconds']:.2f} s, "
                  f"estimated {r['estimated']:.2f} dB, measured {r['measured']:.2f} dB "
                  f"(vs reference {r['vs_reference']:.2f}), converged {r['converged']}")
            if r["measured"] < r["estimated"] - 1.0:
                failures.append(f"{ds} quality {r['quality']}: estimate optimistic by > 1 dB")
    args.out.mkdir(parents=True, exist_ok=True)
    write_csv(sweep_rows, args.out / "convergence.csv")
    write_csv(stop_rows, args.out / "convergence_stop.csv")
    chart(sweep_rows, args.out / "convergence.png")
    print("\n".join(failures) if failures else "all targets met")
    return 1 if failures else 0


if __name__ == "__main__":
    raise SystemExit(main())
