"""Section "Quality against samples": what the mapper shows as frames accumulate.

Per dataset (view 0 of Table 1, the paper preset) and image size (``--samples-sizes``), one
accumulation of the mapper with its defaults (Denoise on, one frame per render, seed 1), read
after 1, 2, 4, ... ``--samples-frames`` frames: PSNR of the raw Radiance mean, the Denoised pass
(the denoiser on the accumulation), the Converged pass (what the mapper shows), and OIDN RT fast
and balanced on the same accumulated Radiance, Albedo and Normal, against the section's
reference (``--ref-spp`` of an independent seed, as Table 1). Then the frames each image needs
to reach 30, 35 and 40 dB (the first power of two at or above it; ">N" when not reached) and
the check of issue #58: shown >= max(raw, OIDN fast) - 0.2 dB at every count.
"""
from __future__ import annotations

import argparse
import contextlib
from pathlib import Path
from typing import Any, Dict, Iterator, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from .common import Output, fmt, md_table

IMAGES = ("raw", "Denoised", "shown", "OIDN fast", "OIDN balanced")
TARGETS_DB = (30.0, 35.0, 40.0)
MARGIN_DB = 0.2  # issue #58: shown >= max(raw, OIDN fast) - 0.2 dB


def _psnr(image: np.ndarray, reference: np.ndarray) -> float:
    from pathtracedvolume.metrics import tonemap
    mse = float(np.mean((tonemap(image).astype(np.float64) - tonemap(reference)) ** 2))
    return -10.0 * np.log10(max(mse, 1e-20))


def _counts(frames: int) -> List[int]:
    out, k = [], 1
    while k <= frames:
        out.append(k)
        k *= 2
    return out


@contextlib.contextmanager
def denoising(mapper: Any, model: str = "") -> Iterator[None]:
    """The mapper denoises with ``model`` (``--model``; "": the shipped one) inside the block;
    after it, it denoises no more and has its default model again (the other sections' scenes
    denoise the passes themselves)."""
    mapper.SetDenoiserModelFile(str(Path(model).resolve()) if model else "")
    mapper.DenoiseOn()
    try:
        yield
    finally:
        mapper.DenoiseOff()
        mapper.SetDenoiserModelFile("")


def measure(bench: Any, out: Output, results: Mapping[str, Any]) -> Dict[str, Any]:
    import ptvbench as pb
    from tqdm import tqdm

    args = bench.args
    rows: List[Dict[str, Any]] = []
    counts = _counts(args.samples_frames)
    for size in args.samples_sizes:
        for dataset in args.datasets:
            spec = bench.view_spec(dataset, 0, size)
            ref = bench.reference(spec, args.ref_spp)["ref"]
            scene = bench.scenes.scene(spec)
            with denoising(scene.mapper, args.model):
                bar = tqdm(total=max(counts), desc=f"samples {dataset} {size}²", unit="frame",
                           leave=False, disable=None)

                def on_frame(k: int) -> None:
                    bar.update(1)
                    if k not in counts:
                        return
                    passes = {name: scene.grab(name) for name in ("Radiance", "Albedo",
                                                                  "Normal")}
                    images = {"raw": passes["Radiance"], "Denoised": scene.grab("Denoised"),
                              "shown": scene.grab("Converged"),
                              "OIDN fast": pb.oidn(passes, "fast"),
                              "OIDN balanced": pb.oidn(passes, "balanced")}
                    row = {"dataset": dataset, "size": size, "frames": k}
                    row.update({name: _psnr(img, ref) for name, img in images.items()})
                    rows.append(row)

                scene.render(seed=SEED, frames=max(counts), on_frame=on_frame)
                bar.close()
    return {"samples": rows}


SEED = 1


def frames_to(rows: Sequence[Mapping[str, Any]], image: str, target: float) -> Optional[int]:
    """The first frame count at which ``image`` reaches ``target`` dB (None: never)."""
    for row in sorted(rows, key=lambda r: r["frames"]):
        if row[image] >= target:
            return int(row["frames"])
    return None


def verdict(rows: Sequence[Mapping[str, Any]]) -> Tuple[bool, List[str]]:
    """(every count passes, the failing counts described)."""
    misses = []
    for row in rows:
        floor = max(row["raw"], row["OIDN fast"]) - MARGIN_DB
        if row["shown"] < floor:
            misses.append(f"{row['dataset']} {row['size']}² {row['frames']} frames: shown "
                          f"{row['shown']:.2f} < {floor + MARGIN_DB:.2f} - {MARGIN_DB}")
    return not misses, misses


def render(results: Mapping[str, Any], args: argparse.Namespace,
           out: Output) -> Tuple[List[str], Dict[str, Any]]:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = results["samples"]
    lines = ["## Quality against samples", "",
             "The mapper's own accumulation (defaults, Denoise on, one frame per render): PSNR "
             "in dB of the raw mean, the Denoised pass, what is shown (Converged), and OIDN RT "
             "fast and balanced on the same accumulated Radiance, Albedo and Normal, after N "
             "frames. Issue #58's check: shown >= max(raw, OIDN fast) - 0.2 dB at every N.", ""]
    groups = sorted({(r["size"], r["dataset"]) for r in rows},
                    key=lambda g: (g[0], args.datasets.index(g[1])
                                   if g[1] in args.datasets else 0))
    counts = sorted({r["frames"] for r in rows})
    table = []
    for size, dataset in groups:
        mine = {r["frames"]: r for r in rows if r["size"] == size and r["dataset"] == dataset}
        for image in IMAGES:
            table.append([f"{dataset} {size}²", image] + [fmt(mine[k][image]) if k in mine
                                                          else "" for k in counts])
    lines += md_table(["view", "image"] + [str(k) for k in counts], table) + [""]

    reach = []
    for size, dataset in groups:
        mine = [r for r in rows if r["size"] == size and r["dataset"] == dataset]
        cells = []
        for target in TARGETS_DB:
            shown = frames_to(mine, "shown", target)
            raw = frames_to(mine, "raw", target)
            oidn = frames_to(mine, "OIDN fast", target)
            ratio = (f"{raw / shown:.1f}x" if shown and raw else
                     (f">{max(counts) / shown:.1f}x" if shown else "-"))
            cells.append(f"{shown or '>' + str(max(counts))} / {raw or '>' + str(max(counts))}"
                         f" / {oidn or '>' + str(max(counts))} ({ratio})")
        reach.append([f"{dataset} {size}²"] + cells)
    lines += ["Frames to reach 30 / 35 / 40 dB: shown / raw mean / OIDN fast (raw ÷ shown):", ""]
    lines += md_table(["view"] + [f"{t:.0f} dB" for t in TARGETS_DB], reach) + [""]

    ok, misses = verdict(rows)
    lines += [f"Check (shown >= max(raw, OIDN fast) - {MARGIN_DB} dB at every count): "
              + ("**met**." if ok else f"**missed** at {len(misses)} of {len(rows)} counts:"),
              ""]
    lines += [f"- {m}" for m in misses] + ([""] if misses else [])

    fig, axes = plt.subplots(len({g[0] for g in groups}), len(args.datasets),
                             figsize=(4.2 * len(args.datasets), 3.4 * len({g[0] for g in groups})),
                             squeeze=False)
    sizes = sorted({g[0] for g in groups})
    for (size, dataset) in groups:
        ax = axes[sizes.index(size)][args.datasets.index(dataset)
                                     if dataset in args.datasets else 0]
        mine = sorted((r for r in rows if r["size"] == size and r["dataset"] == dataset),
                      key=lambda r: r["frames"])
        for image, style in zip(IMAGES, ("k--", "C1-", "C0-o", "C2-", "C3:")):
            ax.plot([r["frames"] for r in mine], [r[image] for r in mine], style, label=image,
                    markersize=3)
        ax.set_xscale("log", base=2)
        ax.set_title(f"{dataset} {size}²")
        ax.set_xlabel("frames (1 spp each)")
        ax.set_ylabel("PSNR (dB)")
        ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    out.save("quality_vs_samples", rows, fig)
    plt.close(fig)
    lines += ["![quality against samples](quality_vs_samples.png)", ""]
    return lines, {"samples_check": {"met": ok, "misses": misses}}


def missing(results: Mapping[str, Any]) -> List[str]:
    return [] if "samples" in results else ["samples"]
