"""Sections 1 and 2: the paper's Table 1 per dataset, PSNR against time, the quality-matched
speed-up.

Per dataset, --views camera orbits: the 1..256-spp sweep, 1 spp denoised by vtkPTVDenoiser
(the model's default level count, "ours", and every level of the model) and by OIDN (fast and balanced, albedo + normal)
on the same 1-spp passes, against a --ref-spp reference of an independent seed; the time per
frame of every method, measured in the same run (view 0).

results.json: ``table1`` (the rows of the tables), ``table1_per_view``, ``psnr_time`` (every
swept count: the chart), ``speedup``, ``reference_check``, ``stages`` (read by the timing
section) and, rendered, ``headlines``.
"""
from __future__ import annotations

import argparse
import math
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple

import numpy as np
import ptvbench as pb
from tqdm import tqdm

from .common import VIEWS, Output, counts, fmt, md_table, missing_keys, num
from .scenes import Bench, set_edge_samples

# "ours": the model's default level count (ptv.default_levels); "ours every level": all of the
# model's levels (the slower, finer setting a user can ask for with NumberOfLevels).
EVERY = "ours every level"
METHODS = (EVERY, "ours", "OIDN fast", "OIDN balanced")
STYLES = {EVERY: ("s", "tab:blue"), "ours": ("D", "tab:green"),
          "OIDN fast": ("^", "tab:orange"), "OIDN balanced": ("v", "tab:red")}


# --- measure --------------------------------------------------------------------------------
def measure(bench: Bench, out: Output, results: Mapping[str, Any]) -> Dict[str, Any]:
    a = bench.args
    sweep_counts = counts(a)
    per_view: List[Dict[str, Any]] = []
    chart_rows: List[Dict[str, Any]] = []
    speedups: List[Dict[str, Any]] = []
    stages: Dict[str, Any] = {}
    reference_check: Dict[str, List[float]] = {}
    for ds in tqdm(a.datasets, desc="table 1", unit="dataset"):
        quality: Dict[str, List[Tuple[float, float]]] = {}
        ref_checks = []
        for v in range(a.views):
            d = bench.view_data(ds, v)
            passes = {n: d[f"{n}@frame"] for n in pb.PASSES}  # with EdgeSamples
            ref_checks.append(pb.quality(d["ref"], d["half"])[0])
            images = {f"{n} spp": d[f"Radiance@{n}"] for n in sweep_counts}
            images[EVERY] = bench.denoise(passes, pb.model_levels(a.model))
            images["ours"] = bench.denoise(passes, 0)
            images["OIDN fast"] = pb.oidn(passes, "fast")
            images["OIDN balanced"] = pb.oidn(passes, "balanced")
            for name, img in images.items():
                q = pb.quality(d["ref"], img)
                quality.setdefault(name, []).append(q)
                per_view.append({"dataset": ds, "view": v, "azimuth": VIEWS[v][0],
                                 "elevation": VIEWS[v][1], "method": name, "psnr": q[0],
                                 "ssim": q[1], "finite": bool(np.isfinite(img).all())})
            if v == 0:
                out.thumbs(f"table1_{ds}", [("1 spp", images["1 spp"]), ("ours", images["ours"]),
                                            ("OIDN fast", images["OIDN fast"]),
                                            (f"{max(a.sweep)} spp",
                                             images[f"{max(a.sweep)} spp"]),
                                            (f"reference {a.ref_spp} spp", d["ref"])],
                           box=(200, 200))
        # timings at view 0, all methods in the same rounds
        p0 = {n: bench.view_data(ds, 0)[f"{n}@frame"] for n in pb.PASSES}
        t_trace, t_ours, t_edges, den = timed_rounds(bench, ds, p0, table1_rounds(a))
        stages[ds] = {"trace": t_ours, "trace_plain": t_trace, "trace_edges": t_edges,
                      **{m: {k: den[m][k] for k in pb.STAGES + ("ms",)} for m in (EVERY, "ours")}}
        rows: Dict[str, Dict[str, Any]] = {}
        for name, qs in quality.items():
            spp = int(name.split()[0]) if name.endswith(" spp") else 1
            denoise_ms = den[name]["ms"] if name in den else 0.0
            trace_ms = (t_ours if name in (EVERY, "ours") else
                        t_edges if name in METHODS else spp * t_trace)
            rows[name] = {
                "dataset": ds, "method": name, "spp": spp,
                "psnr": float(np.mean([q[0] for q in qs])),
                "ssim": float(np.mean([q[1] for q in qs])),
                "trace_ms": trace_ms, "denoise_ms": denoise_ms,
                "frame_ms": trace_ms + denoise_ms, "views": len(qs),
                "in_table": name in METHODS or spp in a.sweep,
            }
        chart_rows += list(rows.values())
        sweep = [rows[f"{n} spp"] for n in sweep_counts]
        for m in METHODS:
            speedups.append({"dataset": ds, "method": m, **speedup(sweep, rows[m], t_trace)})
        reference_check[ds] = ref_checks
    return {"stages": stages, "reference_check": reference_check,
            "table1": [r for r in chart_rows if r["in_table"]], "speedup": speedups,
            "table1_per_view": per_view, "psnr_time": chart_rows,
            "edge_samples": bench.scenes.edge_samples}


def table1_rounds(args: argparse.Namespace) -> int:
    """Timed rounds of Table 1: 9 x --repeats (45 by default, about 5 s per dataset at 256^2),
    so that a slow spell of the host, which lasts seconds on this VM, cannot fill half of them
    (docs/measuring.md)."""
    return 9 * args.repeats


def timed_rounds(bench: Bench, ds: str, passes: Mapping[str, np.ndarray], rounds: int
                 ) -> Tuple[float, float, float, Dict[str, Dict[str, Any]]]:
    """The 1-spp trace (a fresh frame, the tracer's own time) and every denoiser on view 0's
    passes in the same rounds (pb.interleaved: a slow spell of the shared machine slows them
    alike), one warm-up round, then ``rounds``: (median trace ms of a plain frame (the N-spp
    sweep's), the same with what the mapper traces when it denoises -- the Coverage pass where
    our model reads it, the Footprint pass (traced for every denoised frame), EdgeSamples --,
    the same with EdgeSamples alone (OIDN's frames: the same samples, without the passes only
    our denoiser reads), per denoiser the row of pb.run_ours / pb.run_oidn with medians over
    the rounds). Every denoiser runs right after a trace of its own kind, as in a frame: the
    trace leaves the caches to the volume, and a denoiser timed after another denoiser would
    find its own buffers warm."""
    import statistics

    a = bench.args
    scene = bench.scenes.scene(bench.view_spec(ds, 0))
    seeds = iter(range(500000, 500000 + 8 * (rounds + 1)))
    reads = "coverage" in pb.model_props(a.model)["ptv.input_channels"].split(",")
    traced: Dict[bool, List[float]] = {False: [], True: []}
    plain: List[float] = []

    def trace(ours_frame: bool, edges: bool = True, into: Optional[List[float]] = None
              ) -> None:
        scene.mapper.GetExpertOptions().SetCoverageMarch(ours_frame and reads)
        scene.mapper.GetExpertOptions().SetFootprintRays(ours_frame)
        set_edge_samples(scene, bench.scenes.edge_samples if edges else 1)
        (traced[ours_frame] if into is None else into).append(scene.render(next(seeds), 1)[0])

    ours = {m: pb.Ours(lv, a.model, a.threads)
            for m, lv in ((EVERY, pb.model_levels(a.model)), ("ours", 0))}
    for o in ours.values():
        o.set_passes(passes)
    denoisers = {f"OIDN {q}": (lambda q=q: pb.oidn(passes, q)) for q in ("fast", "balanced")}
    denoisers.update({m: (lambda o=o: o.execute(copy=False)) for m, o in ours.items()})
    calls: Dict[str, Any] = {}
    for m, call in denoisers.items():
        calls[f"trace before {m}"] = lambda c=m in ours: trace(c)
        calls[m] = call
    calls["trace plain"] = lambda: trace(False, edges=False, into=plain)
    runs = pb.interleaved(calls, rounds, {m: o.stages for m, o in ours.items()})
    den: Dict[str, Dict[str, Any]] = {}
    for m, run in runs.items():
        if m.startswith("trace"):
            continue
        row: Dict[str, Any] = {"ms": statistics.median(run["times"]),
                               "image": np.array(run["result"])}
        if m in ours:
            row.update({k: statistics.median(e[k] for e in run["extra"]) for k in pb.STAGES})
            row.update(status=ours[m].status(), kernels=ours[m].kernel_target())
        den[m] = row
    per_round = {c: sum(1 for m in denoisers if (m in ours) == c) for c in traced}
    edged, marched = (statistics.median(traced[c][per_round[c]:])  # without the warm-up round's
                      if per_round[c] else float("nan") for c in (False, True))
    scene.mapper.GetExpertOptions().SetCoverageMarch(True)  # as the scene was
    scene.mapper.GetExpertOptions().SetFootprintRays(True)
    set_edge_samples(scene, 1)
    return statistics.median(plain[1:]), marched, edged, den


def speedup(sweep: Sequence[Mapping[str, Any]], method: Mapping[str, Any],
            t_trace: float) -> Dict[str, Any]:
    """Smallest swept spp whose PSNR reaches the method's, its time / the method's time; also
    the log2-interpolated equal-quality spp."""
    target = method["psnr"]
    hit = next((r for r in sweep if r["psnr"] >= target), None)
    out: Dict[str, Any] = {"psnr": target, "frame_ms": method["frame_ms"]}
    if hit is None:
        top = sweep[-1]
        out.update(matched_spp=None, lower_bound=True, matched_ms=top["frame_ms"],
                   speedup=top["frame_ms"] / method["frame_ms"], interp_spp=None,
                   interp_speedup=None)
        return out
    out.update(matched_spp=hit["spp"], lower_bound=False, matched_ms=hit["frame_ms"],
               speedup=hit["frame_ms"] / method["frame_ms"])
    i = sweep.index(hit)
    if i == 0:
        n_eq = 1.0
    else:
        lo = sweep[i - 1]
        f = (target - lo["psnr"]) / max(hit["psnr"] - lo["psnr"], 1e-9)
        n_eq = 2 ** (math.log2(lo["spp"]) + f * (math.log2(hit["spp"]) - math.log2(lo["spp"])))
    out.update(interp_spp=n_eq, interp_speedup=n_eq * t_trace / method["frame_ms"])
    return out


# --- render ---------------------------------------------------------------------------------
def missing(results: Mapping[str, Any]) -> List[str]:
    return missing_keys(results, ("table1", "table1_per_view", "psnr_time", "speedup",
                                  "reference_check"))


def render(results: Mapping[str, Any], args: argparse.Namespace,
           out: Output) -> Tuple[List[str], Dict[str, Any]]:
    summary, speedups = results["table1"], results["speedup"]
    sweep_counts = counts(args)
    for ds in args.datasets:
        rows = {r["method"]: r for r in results["psnr_time"] if r["dataset"] == ds}
        chart(args, ds, [rows[f"{n} spp"] for n in sweep_counts],
              {m: rows[m] for m in METHODS},
              next(s for s in speedups if s["dataset"] == ds and s["method"] == "ours"), out)
    out.save("table1", list(summary))
    out.save("table1_per_view", list(results["table1_per_view"]))
    out.save("speedup", list(speedups))
    out.save("psnr_time", list(results["psnr_time"]))
    lines, headlines = markdown(args, summary, speedups, results["reference_check"],
                                results.get("edge_samples", 1))
    return lines, {"headlines": headlines}


def chart(args: argparse.Namespace, ds: str, sweep: Sequence[Mapping[str, Any]],
          methods: Mapping[str, Mapping[str, Any]], mark: Mapping[str, Any],
          out: Output) -> None:
    """psnr_time_<ds>.png/.csv: PSNR against time per frame, the sweep as a line, each denoiser
    as a marker, the speed-up of ours as a dashed line."""
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.6))
    ax.plot([num(r["frame_ms"]) for r in sweep], [num(r["psnr"]) for r in sweep], "-o",
            color="0.4", ms=3, label="path tracing, N spp")
    for r in sweep:
        if r["spp"] in args.sweep:
            ax.annotate(f"{r['spp']}", (num(r["frame_ms"]), num(r["psnr"])), fontsize=7,
                        textcoords="offset points", xytext=(-4, 6))
    for m, r in methods.items():
        mk, c = STYLES[m]
        ax.plot([num(r["frame_ms"])], [num(r["psnr"])], mk, color=c, ms=8, label=f"1 spp + {m}")
    if mark.get("matched_ms"):
        ax.plot([mark["frame_ms"], mark["matched_ms"]], [num(mark["psnr"])] * 2, "--",
                color="tab:green", lw=1)
        tag = ">" if mark["lower_bound"] else ""
        ax.annotate(f"{tag}{num(mark['speedup']):.1f}× (quality-matched)",
                    (math.sqrt(mark["frame_ms"] * mark["matched_ms"]), num(mark["psnr"])),
                    textcoords="offset points", xytext=(0, -12), ha="center", fontsize=8,
                    color="tab:green")
    ax.set_xscale("log")
    ax.set_xlabel("time per frame [ms] (log; N spp = N × measured 1-spp trace)")
    ax.set_ylabel("PSNR [dB] (mean over views)")
    ax.set_title(f"{ds}, {args.size}², {args.views} view(s), reference {args.ref_spp} spp")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    rows = [dict(r) for r in sweep] + [dict(r) for r in methods.values()]
    out.save(f"psnr_time_{ds}", rows, fig)


def markdown(a: argparse.Namespace, summary: Sequence[Mapping[str, Any]],
             speedups: Sequence[Mapping[str, Any]],
             checks: Mapping[str, Sequence[float]],
             edge_samples: int) -> Tuple[List[str], List[str]]:
    """Sections 1 and 2 (Markdown lines) and the headlines of the summary."""
    md = ["## 1. Paper Table 1: quality and time per dataset", "",
          f"{a.size}² pixels, {a.views} view(s) per dataset (camera azimuth/elevation "
          f"{', '.join(f'{VIEWS[v][0]:.0f}°/{VIEWS[v][1]:.0f}°' for v in range(a.views))}),"
          f" PSNR/SSIM = mean over the views against a {a.ref_spp}-spp reference of an "
          f"independent seed. Time per frame: N spp = N × the median 1-spp trace time; "
          f"denoisers = the trace of the frame the mapper denoises (1 spp, and "
          f"EdgeSamples {edge_samples} on the volume's edge pixels: "
          f"docs/edge-samples.md; ours also with the Coverage pass, which the mapper traces "
          f"when the model reads it, and the Footprint pass, which it traces when it denoises; "
          f"OIDN gets the same samples without those two passes) + the median denoise time "
          f"(ours: vtkPTVDenoiser with the shipped model; OIDN: pyoidn RT filter, HDR colour + "
          f"albedo + normal), all on the same passes of that frame, view 0; every denoiser "
          f"right after a trace of its frame (a fresh frame, as in a frame loop), all of them "
          f"once per round, median of {table1_rounds(a)} rounds after a warm-up round. The "
          f"'1 spp' row is the plain frame (the sweep's first).",
          ""]
    md += ["Reference convergence: PSNR of the first half (ref/2 spp) against the full "
           "reference, per view: " + "; ".join(
               f"{ds} {', '.join(f'{num(c):.1f}' for c in v)} dB" for ds, v in checks.items())
           + ". The reference's own noise bounds the PSNR a method can show to about "
           "this figure + 3 dB.", ""]
    for ds in a.datasets:
        rows = [r for r in summary if r["dataset"] == ds]
        md += [f"### {ds}", ""]
        md += md_table(["method", "PSNR [dB]", "SSIM", "ms / frame", "of which denoise"],
                       [[r["method"] if r["method"].endswith("spp") else
                         f"1 spp + {r['method']}", fmt(r["psnr"]), fmt(r["ssim"], 4),
                         fmt(r["frame_ms"], 1), fmt(r["denoise_ms"], 1)] for r in rows])
        md += ["", f"![PSNR against time, {ds}](psnr_time_{ds}.png)", "",
               f"![{ds}: 1 spp, ours, OIDN fast, {max(a.sweep)} spp, reference]"
               f"(gallery/table1_{ds}.png)", ""]
    md += ["## 2. PSNR against time: the quality-matched speed-up", "",
           "The charts above (one per dataset) put every method at its time per frame; "
           "the dashed line marks the speed-up of ours (the model's levels). Target: ≥ 10×; the "
           "paper reports about 6×.", "",
           "Time of the smallest spp count (from the sweep and intermediate counts "
           f"{', '.join(map(str, counts(a)))}) whose PSNR reaches the denoised PSNR, "
           "divided by the time of 1 spp + denoising; the interpolated column takes the "
           "equal-quality spp by linear interpolation of PSNR in log2(spp). A '>' marks "
           "a lower bound (no swept count reached the denoised PSNR).", ""]
    md += md_table(["dataset", "method", "PSNR [dB]", "matched spp", "speed-up",
                    "interp. spp", "interp. speed-up"],
                   [[s["dataset"], s["method"], fmt(s["psnr"]),
                     f">{max(counts(a))}" if s["lower_bound"] else s["matched_spp"],
                     (">" if s["lower_bound"] else "") + fmt(s["speedup"], 1) + "×",
                     fmt(s["interp_spp"], 1),
                     fmt(s["interp_speedup"], 1) + ("×" if s["interp_speedup"] else "")]
                    for s in speedups])
    md += [""]
    lines = []
    for ds in a.datasets:
        r = {x["method"]: x for x in summary if x["dataset"] == ds}
        o, f = r["ours"], r["OIDN fast"]
        at = {n: fmt(r[f"{n} spp"]["psnr"]) if f"{n} spp" in r else "n/a" for n in (8, 16)}
        lines.append(
            f"* {ds}: 1 spp + ours {num(o['psnr']):.2f} dB vs 8 spp {at[8]} dB and "
            f"16 spp {at[16]} dB (1 spp {num(r['1 spp']['psnr']):.2f} dB); OIDN fast "
            f"takes {f['denoise_ms'] / o['denoise_ms']:.1f}× our denoise time, PSNR ours − "
            f"OIDN fast = {num(o['psnr']) - num(f['psnr']):+.2f} dB (balanced: "
            f"{num(o['psnr']) - num(r['OIDN balanced']['psnr']):+.2f} dB).")
    md += ["Headlines:", ""] + lines + [""]
    return md, lines
