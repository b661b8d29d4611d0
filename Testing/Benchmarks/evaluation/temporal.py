"""Section 4: temporal stability. Per-pixel std over frames of different seeds (fixed view), the
mapper's own accumulation when the camera stops, temporal PSNR over a camera orbit, and "Camera
motion with temporal reuse", read from ``Testing/Benchmarks/results/temporal_reuse.json``
(``temporal_reuse.py``; not re-measured here: it runs for ~15 min).

results.json: ``temporal`` (``static``, ``orbit`` rows; ``orbit_tpsnr``: dataset -> method ->
tPSNR per frame pair; ``reuse``: None without temporal_reuse.json, else its ``source`` and the
fields of it that this section reads) and, rendered, ``flicker_verdicts`` and ``temporal_reuse``
(``source`` and ``verdicts``).
"""
from __future__ import annotations

import argparse
import json
import math
import statistics
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple

import numpy as np
import ptvbench as pb
from pathtracedvolume.metrics import flicker, tpsnr
from tqdm import tqdm

from .common import ROOT, Output, fmt, md_table, missing_keys, num
from .scenes import Bench

REUSE = "Testing/Benchmarks/results/temporal_reuse.json"
REUSE_FIELDS = {"rows": ("dataset", "case", "method", "tpsnr_mean", "psnr_mean", "never_below"),
                "cost": ("reproject_ms", "render_ms"),
                "static_flicker": ("dataset", "method", "ratio_to_oidn")}


# --- measure --------------------------------------------------------------------------------
def measure(bench: Bench, out: Output, results: Mapping[str, Any]) -> Dict[str, Any]:
    a = bench.args
    static_rows: List[Dict[str, Any]] = []
    for ds in tqdm(a.datasets, desc="temporal (static)", unit="dataset"):
        spec = bench.view_spec(ds, 0)
        ref = bench.view_data(ds, 0)["ref"]
        seqs: Dict[str, List[np.ndarray]] = {}
        for i in range(a.static_frames):
            p = bench.scenes.frame(spec, 2000 + i)
            seqs.setdefault("noisy 1 spp", []).append(p["Radiance"])
            seqs.setdefault("ours", []).append(bench.denoise(p))
            seqs.setdefault("OIDN fast", []).append(pb.oidn(p, "fast"))
        # the mapper's own behaviour when the camera stops: the k-th frame shows the denoised
        # mean of k spp (one seed)
        scene = bench.scenes.scene(spec)
        acc, acc_noisy = [], []

        def grab(k: int) -> None:
            p = scene.passes()
            acc_noisy.append(p["Radiance"])
            acc.append(bench.denoise(p))
        scene.render(3000, a.static_frames, grab)
        seqs["noisy accumulation"] = acc_noisy
        seqs["ours + accumulation"] = acc
        for m, frames in seqs.items():
            tm = [pb.tonemap(f) for f in frames]
            tp = tpsnr(tm)
            static_rows.append({
                "dataset": ds, "method": m, "frames": len(frames),
                "flicker_std": flicker(tm), "tpsnr_mean": float(np.mean(tp)),
                "psnr_mean": float(np.mean([pb.quality(ref, f)[0] for f in frames])),
                "finite": bool(all(np.isfinite(f).all() for f in frames))})
        by = {r["method"]: r for r in static_rows if r["dataset"] == ds}
        for r in static_rows:
            if r["dataset"] == ds:
                r["ratio_to_noisy"] = r["flicker_std"] / by["noisy 1 spp"]["flicker_std"]
                r["ratio_to_oidn"] = r["flicker_std"] / by["OIDN fast"]["flicker_std"]
    orbit_rows: List[Dict[str, Any]] = []
    series: Dict[str, Dict[str, List[float]]] = {}
    for ds in tqdm(a.orbit_datasets, desc="temporal (orbit)", unit="dataset"):
        seqs = {}
        for i in range(a.orbit_frames):
            spec = bench.view_spec(ds, 0)
            spec["azimuth"] += i * a.orbit_step
            p = bench.scenes.frame(spec, 4000 + i)
            seqs.setdefault("noisy 1 spp", []).append(p["Radiance"])
            seqs.setdefault("ours", []).append(bench.denoise(p))
            seqs.setdefault("OIDN fast", []).append(pb.oidn(p, "fast"))
            seqs.setdefault(f"converged ({a.orbit_ref_spp} spp)", []).append(
                bench.reference(spec, a.orbit_ref_spp, 6000 + i)["ref"])
        conv = [pb.tonemap(f) for f in seqs[f"converged ({a.orbit_ref_spp} spp)"]]
        for m, frames in seqs.items():
            tm = [pb.tonemap(f) for f in frames]
            tp = tpsnr(tm)
            series.setdefault(ds, {})[m] = tp
            orbit_rows.append({
                "dataset": ds, "method": m, "frames": len(frames),
                "tpsnr_mean": float(np.mean(tp)), "tpsnr_min": float(np.min(tp)),
                "psnr_vs_converged": float(np.mean([
                    10 * math.log10(1 / max(float(np.mean((x - c) ** 2)), 1e-10))
                    for x, c in zip(tm, conv)]))})
    return {"temporal": {"static": static_rows, "orbit": orbit_rows, "orbit_tpsnr": series,
                         "reuse": measure_reuse()}}


def measure_reuse() -> Optional[Dict[str, Any]]:
    """The fields of results/temporal_reuse.json that the section shows; None without it."""
    path = ROOT / REUSE
    if not path.exists():
        return None
    data = json.loads(path.read_text())
    keep = {"source": REUSE, "command": data["command"], "args": data["args"]}
    for key, fields in REUSE_FIELDS.items():
        keep[key] = [{k: r[k] for k in fields if k in r} for r in data[key]]
    return keep


# --- render ---------------------------------------------------------------------------------
def missing(results: Mapping[str, Any]) -> List[str]:
    return missing_keys(results, ("temporal.static", "temporal.orbit", "temporal.orbit_tpsnr",
                                  "temporal.reuse"))


def render(results: Mapping[str, Any], args: argparse.Namespace,
           out: Output) -> Tuple[List[str], Dict[str, Any]]:
    static_rows = results["temporal"]["static"]
    orbit_rows = results["temporal"]["orbit"]
    charts(args, static_rows, results["temporal"]["orbit_tpsnr"], out)
    md, flicker_verdicts = markdown(args, static_rows, orbit_rows)
    reuse_md, reuse = render_reuse(results["temporal"]["reuse"])
    return md + reuse_md, {"flicker_verdicts": flicker_verdicts, "temporal_reuse": reuse}


def charts(args: argparse.Namespace, static_rows: Sequence[Mapping[str, Any]],
           series: Mapping[str, Mapping[str, Sequence[float]]], out: Output) -> None:
    """temporal_static (flicker per dataset and method) and temporal_orbit (tPSNR per pair)."""
    import matplotlib.pyplot as plt
    methods = list(dict.fromkeys(r["method"] for r in static_rows))
    fig, ax = plt.subplots(figsize=(7, 3.8))
    width = 0.8 / max(len(methods), 1)
    for j, m in enumerate(methods):
        vals = [num(next(r["flicker_std"] for r in static_rows
                         if r["dataset"] == ds and r["method"] == m)) for ds in args.datasets]
        ax.bar(np.arange(len(vals)) + j * width, vals, width, label=m)
    ax.set_xticks(np.arange(len(args.datasets)) + 0.4 - width / 2)
    ax.set_xticklabels(args.datasets)
    ax.set_ylabel("mean per-pixel std (tone-mapped)")
    ax.set_title(f"fixed view, {args.static_frames} frames")
    ax.legend(fontsize=8)
    fig.tight_layout()
    out.save("temporal_static", list(static_rows), fig)
    fig, ax = plt.subplots(figsize=(7, 3.8))
    rows = []
    for ds, per in series.items():
        for m, tp in per.items():
            ax.plot(np.arange(1, len(tp) + 1), [num(v) for v in tp], label=f"{ds}: {m}")
            rows += [{"dataset": ds, "method": m, "pair": i + 1, "tpsnr": v}
                     for i, v in enumerate(tp)]
    ax.set_xlabel(f"frame pair (camera moves {args.orbit_step}° per frame)")
    ax.set_ylabel("temporal PSNR [dB]")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    out.save("temporal_orbit", rows, fig)


def markdown(a: argparse.Namespace, static_rows: Sequence[Mapping[str, Any]],
             orbit_rows: Sequence[Mapping[str, Any]]) -> Tuple[List[str], List[str]]:
    """The fixed-view and orbit parts (Markdown lines) and the flicker verdicts."""
    md = [
        "## 4. Temporal stability", "",
        f"**Fixed view** (view 0, {a.size}²): {a.static_frames} independent 1-spp frames "
        "(seeds differ), each shown noisy, denoised by ours (the model's levels) and by OIDN "
        "fast; plus the mapper's own behaviour when the camera stops: the k-th frame shows "
        "the (denoised) mean of k spp of one seed. Flicker = per-pixel standard deviation "
        "over the frames of the tone-mapped images, averaged over the image; tPSNR = PSNR "
        "between consecutive frames (higher = steadier); PSNR against the reference.", ""]
    md += md_table(
        ["dataset", "method", "flicker (std)", "÷ noisy", "÷ OIDN", "tPSNR [dB]",
         "PSNR [dB]", "finite"],
        [[r["dataset"], r["method"], fmt(r["flicker_std"], 4), fmt(r["ratio_to_noisy"], 3),
          fmt(r["ratio_to_oidn"], 3), fmt(r["tpsnr_mean"]), fmt(r["psnr_mean"]),
          r["finite"]] for r in static_rows])
    verdicts = []
    for ds in a.datasets:
        by = {r["method"]: r for r in static_rows if r["dataset"] == ds}
        o = by["ours"]
        noisy, oidn = num(o["ratio_to_noisy"]), num(o["ratio_to_oidn"])
        verdicts.append(
            f"* {ds}: ours / noisy = {noisy:.3f} (target ≤ 0.25: "
            f"{'met' if noisy <= 0.25 else 'NOT met'}), ours / OIDN = "
            f"{oidn:.3f} ({'below' if oidn < 1 else 'NOT below'}"
            f" OIDN); with accumulation {num(by['ours + accumulation']['ratio_to_noisy']):.3f} "
            "of the noisy flicker.")
    md += ["", "![flicker](temporal_static.png)", ""] + verdicts + [""]
    md += [
        f"**Camera orbit** ({', '.join(a.orbit_datasets)}): {a.orbit_frames} frames, "
        f"{a.orbit_step}° of azimuth per frame, one fresh 1-spp frame per view (a new seed "
        "each), denoised per frame with no temporal filtering. The converged row "
        f"({a.orbit_ref_spp} spp per view) is what the camera motion alone costs in tPSNR.",
        ""]
    md += md_table(["dataset", "method", "mean tPSNR [dB]", "min tPSNR [dB]",
                    "PSNR vs converged [dB]"],
                   [[r["dataset"], r["method"], fmt(r["tpsnr_mean"]),
                     fmt(r["tpsnr_min"]), fmt(r["psnr_vs_converged"])]
                    for r in orbit_rows])
    md += ["", "![orbit tPSNR](temporal_orbit.png)", ""]
    return md, verdicts


def render_reuse(data: Optional[Mapping[str, Any]]
                 ) -> Tuple[List[str], Optional[Dict[str, Any]]]:
    """"Camera motion with temporal reuse" (the mapper's TemporalReprojection) and the
    ``temporal_reuse`` entry of results.json."""
    md = ["### Camera motion with temporal reuse", ""]
    if data is None:
        return md + [f"Not available: `{REUSE}` does not exist.", ""], None
    source = data["source"]
    rows, m = data["rows"], data["args"]["default_history"]
    md += [
        f"From `{source}` (`{data['command']}`; its tables and chart: "
        "`results/temporal_reuse.md`): what the mapper shows while the camera moves, "
        f"{data['args']['size']}², {data['args']['frames']} views "
        f"{data['args']['step']}° apart, with TemporalReprojection on (MaximumHistory {m}) "
        "and off.", ""]
    ours_reuse = f"ours + reprojection (M={m})"
    table = [[r["dataset"], r["case"], r["method"], fmt(r["tpsnr_mean"]),
              "n/a" if r["method"].startswith("converged") else fmt(r["psnr_mean"]),
              fmt(r.get("never_below"))]
             for r in rows if r["method"] in (ours_reuse, "ours per frame, new seed (report)",
                                              "OIDN fast per frame")
             or r["method"].startswith("converged")]
    md += md_table(["dataset", "case", "method", "mean tPSNR [dB]",
                    "PSNR vs converged [dB]", "worst frame vs no history [dB]"], table)
    verdicts = []
    for ds in dict.fromkeys(r["dataset"] for r in rows if r["case"] == "orbit"):
        by = {r["method"]: r for r in rows if r["dataset"] == ds and r["case"] == "orbit"}
        ours, today = by[ours_reuse], by["ours per frame, new seed (report)"]
        conv = next(r for k, r in by.items() if k.startswith("converged"))
        oidn = by["OIDN fast per frame"]
        steady_conv = ours["tpsnr_mean"] >= conv["tpsnr_mean"]
        steady_oidn = ours["tpsnr_mean"] >= oidn["tpsnr_mean"]
        verdicts.append(
            f"* {ds} orbit: tPSNR {ours['tpsnr_mean']:.2f} dB vs converged "
            f"{conv['tpsnr_mean']:.2f} ({'met' if steady_conv else 'NOT met'})"
            f" and OIDN fast {oidn['tpsnr_mean']:.2f} "
            f"({'met' if steady_oidn else 'NOT met'}); PSNR "
            f"{ours['psnr_mean']:.2f} dB vs {today['psnr_mean']:.2f} per frame "
            f"({ours['psnr_mean'] - today['psnr_mean']:+.2f} dB; target +2: "
            f"{'met' if ours['psnr_mean'] - today['psnr_mean'] >= 2 else 'NOT met'}).")
    shares = [c["reproject_ms"] / c["render_ms"] for c in data["cost"]]
    if shares:
        typical, worst = statistics.median(shares), max(shares)
        verdicts.append(
            f"* reprojection cost: {100 * typical:.1f} % of the render (median of "
            f"{len(shares)} runs; target ≤ 5 %: {'met' if typical <= 0.05 else 'NOT met'}), "
            f"at most {100 * worst:.1f} % in one run.")
    flick = [r for r in data["static_flicker"] if r["method"].startswith("mapper")]
    verdicts += [f"* {r['dataset']} still view: flicker {r['ratio_to_oidn']:.3f} of OIDN "
                 "fast's (the mapper accumulates while the camera rests)." for r in flick]
    md += [""] + verdicts + [""]
    return md, {"source": source, "verdicts": verdicts}
