"""Section 6: where the time goes: the stages of the denoiser (from the Table-1 timings), image
size, volume size and thread count.

results.json: ``timing`` (``stages``, ``image_size``, ``volume_size``, ``threads`` rows).
"""
from __future__ import annotations

import argparse
from typing import Any, Dict, List, Mapping, Sequence, Tuple

import numpy as np
import ptvbench as pb
from tqdm import tqdm

from .common import SEED_INPUT, Output, fmt, md_table, missing_keys, num
from .scenes import Bench


# --- measure --------------------------------------------------------------------------------
def measure(bench: Bench, out: Output, results: Mapping[str, Any]) -> Dict[str, Any]:
    """Image size, volume size and threads; the stages are those Table 1 measured."""
    a = bench.args
    stage_rows = []
    for ds, st in results.get("stages", {}).items():
        for m in ("ours every level", "ours"):
            stage_rows.append({"dataset": ds, "method": m, "trace": st["trace"],
                               **{k: st[m][k] for k in pb.STAGES},
                               "denoise_total": st[m]["ms"]})
    size_rows = []
    for s in tqdm(a.scaling_sizes, desc="timing: image size", unit="size"):
        spec = bench.view_spec("head", 0, s)
        t = bench.scenes.trace_ms(spec, a.repeats)
        p = bench.scenes.frame(spec, SEED_INPUT)
        o = pb.run_ours(p, 0, a.model, a.repeats, a.threads)
        f = pb.run_oidn(p, "fast", a.repeats)
        size_rows.append({"size": s, "pixels": s * s, "trace": t,
                          **{k: o[k] for k in pb.STAGES}, "denoise": o["ms"],
                          "oidn_fast": f["ms"]})
    vol_rows = []
    for f in tqdm(a.volume_shrink, desc="timing: volume size", unit="volume"):
        name = "head" if f == 1 else f"head_shrink{f}"
        spec = {**bench.view_spec("head", 0), "volume": name}
        dims = bench.scenes.volume(name).GetDimensions()
        vol_rows.append({"shrink": f, "dims": "×".join(map(str, dims)),
                         "voxels": int(np.prod(dims)),
                         "trace": bench.scenes.trace_ms(spec, a.repeats)})
    thread_rows = []
    spec = bench.view_spec("head", 0)
    p = bench.scenes.frame(spec, SEED_INPUT)
    for th in (1, 2):
        o = pb.run_ours(p, 0, a.model, a.repeats, th)
        thread_rows.append({"threads": th, "trace": bench.scenes.trace_ms(spec, a.repeats, th),
                            **{k: o[k] for k in pb.STAGES}, "denoise": o["ms"]})
    return {"timing": {"stages": stage_rows, "image_size": size_rows, "volume_size": vol_rows,
                       "threads": thread_rows}}


# --- render ---------------------------------------------------------------------------------
def missing(results: Mapping[str, Any]) -> List[str]:
    return missing_keys(results, ("timing.stages", "timing.image_size", "timing.volume_size",
                                  "timing.threads"))


def render(results: Mapping[str, Any], args: argparse.Namespace,
           out: Output) -> Tuple[List[str], Dict[str, Any]]:
    t = results["timing"]
    charts(args, t["stages"], t["image_size"], t["volume_size"], t["threads"], out)
    return markdown(args, t["stages"], t["image_size"], t["volume_size"], t["threads"]), {}


def charts(a: argparse.Namespace, stage_rows: Sequence[Mapping[str, Any]],
           size_rows: Sequence[Mapping[str, Any]], vol_rows: Sequence[Mapping[str, Any]],
           thread_rows: Sequence[Mapping[str, Any]], out: Output) -> None:
    """timing_stages (stacked bars) and timing_scaling (image size, volume size, threads)."""
    import matplotlib.pyplot as plt
    if stage_rows:
        fig, ax = plt.subplots(figsize=(7, 3.6))
        labels = [f"{r['dataset']}\n{r['method'].replace('ours ', '')}" for r in stage_rows]
        bottom = np.zeros(len(stage_rows))
        for k in ("trace",) + pb.STAGES:
            vals = np.array([num(r[k]) for r in stage_rows])
            ax.bar(labels, vals, bottom=bottom, label=k)
            bottom += vals
        ax.set_ylabel("ms (median)")
        ax.set_title(f"1 spp + denoise, {a.size}²")
        ax.legend(fontsize=8)
        fig.tight_layout()
        out.save("timing_stages", list(stage_rows), fig)
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.6))
    ax = axes[0]
    px = [r["pixels"] for r in size_rows]
    for k in ("trace", "denoise", "oidn_fast") + pb.STAGES:
        ax.plot(px, [num(r[k]) for r in size_rows], "-o", ms=3, label=k,
                lw=2 if k in ("trace", "denoise", "oidn_fast") else 0.8)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("pixels")
    ax.set_ylabel("ms")
    ax.set_title("image size (head)")
    ax.legend(fontsize=7)
    ax = axes[1]
    ax.plot([r["voxels"] for r in vol_rows], [num(r["trace"]) for r in vol_rows], "-o")
    ax.set_xscale("log")
    ax.set_xlabel("voxels")
    ax.set_ylabel("trace ms")
    ax.set_title(f"volume size ({a.size}²)")
    ax = axes[2]
    x = np.arange(2)
    ax.bar(x - 0.2, [num(r["trace"]) for r in thread_rows], 0.4, label="trace")
    ax.bar(x + 0.2, [num(r["denoise"]) for r in thread_rows], 0.4, label="denoise")
    ax.set_xticks(x)
    ax.set_xticklabels(["1 thread", "2 threads"])
    ax.set_ylabel("ms")
    ax.set_title(f"threads ({a.size}²)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    out.save("timing_scaling", {"image_size": list(size_rows), "volume_size": list(vol_rows),
                                "threads": list(thread_rows)}, fig)
    out.csv("timing_image_size", size_rows)
    out.csv("timing_volume_size", vol_rows)
    out.csv("timing_threads", thread_rows)


def markdown(a: argparse.Namespace, stage_rows: Sequence[Mapping[str, Any]],
             size_rows: Sequence[Mapping[str, Any]], vol_rows: Sequence[Mapping[str, Any]],
             thread_rows: Sequence[Mapping[str, Any]]) -> List[str]:
    md = ["## 6. Where the time goes", "",
          f"Median of {a.repeats} after a warm-up, milliseconds. Trace = the mapper's "
          "`GetStatistics().GetLastTraceTime()` of a fresh 1-spp frame; features, GuideNet, splat "
          "(incl. demodulation and clamp) and slice = `vtkPTVDenoiser::GetLast*Time()`; "
          "denoise = the whole `Execute()` call.", ""]
    if stage_rows:
        md += [f"**Per stage** ({a.size}², view 0):", ""]
        md += md_table(["dataset", "levels", "trace", "features", "GuideNet", "splat",
                        "slice", "denoise total", "denoise ÷ trace"],
                       [[r["dataset"], "model's" if r["method"] == "ours"
                         else r["method"].replace("ours ", ""), fmt(r["trace"], 1)]
                        + [fmt(r[k], 1) for k in pb.STAGES]
                        + [fmt(r["denoise_total"], 1),
                           fmt(num(r["denoise_total"]) / num(r["trace"]), 2)]
                        for r in stage_rows])
        md += ["", "![stages](timing_stages.png)", ""]
    md += ["**Image size** (head, view 0; denoise with the model's levels):", ""]
    md += md_table(["size", "trace", "features", "GuideNet", "splat", "slice", "denoise",
                    "OIDN fast", "ns / pixel (trace + denoise)"],
                   [[f"{r['size']}²", fmt(r["trace"], 1)]
                    + [fmt(r[k], 1) for k in pb.STAGES]
                    + [fmt(r["denoise"], 1), fmt(r["oidn_fast"], 1),
                       fmt(1e6 * (num(r["trace"]) + num(r["denoise"])) / r["pixels"], 0)]
                    for r in size_rows])
    md += ["", "**Volume size** (head downsampled by vtkImageShrink3D with averaging, "
           f"{a.size}²; the denoiser does not see the volume):", ""]
    md += md_table(["shrink", "voxels", "dims", "trace ms"],
                   [[r["shrink"], r["voxels"], r["dims"], fmt(r["trace"], 1)]
                    for r in vol_rows])
    md += ["", f"**Threads** (head, {a.size}²; `NumberOfThreads` of mapper and denoiser):", ""]
    md += md_table(["threads", "trace", "features", "GuideNet", "splat", "slice",
                    "denoise"],
                   [[r["threads"], fmt(r["trace"], 1)] + [fmt(r[k], 1) for k in pb.STAGES]
                    + [fmt(r["denoise"], 1)] for r in thread_rows])
    if len(thread_rows) == 2:
        t1, t2 = thread_rows
        md += ["", f"2 threads vs 1: trace {num(t1['trace']) / num(t2['trace']):.2f}×, denoise "
               f"{num(t1['denoise']) / num(t2['denoise']):.2f}× (on a 2-core machine shared "
               "with other work, see the load average in the header: a second thread only "
               "helps when a core is free; `results/tracer.md` has the tracer's 1- vs 2-thread "
               "times from a quieter run)."]
    md += ["", "![scaling](timing_scaling.png)", ""]
    return md
