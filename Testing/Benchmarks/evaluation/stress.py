"""Section 5: the stress suite with a thumbnail gallery: translucent transfer function, strong
light, fireflies, thin structures, exposure x0.01/x100, odd image sizes, a mostly empty volume,
an unseen volume. Each case: one 1-spp frame denoised by ours, OIDN fast and two variants of
ours (fixed guide, no clamp) against a reference of another seed.

results.json: ``stress`` (one row per case, with the measured diagnosis and its gallery file).
"""
from __future__ import annotations

import argparse
import time
from typing import Any, Dict, List, Mapping, Sequence, Tuple

import numpy as np
import ptvbench as pb
from tqdm import tqdm

from .common import SEED_INPUT, STRESS_METHODS, Output, fmt, md_table, missing_keys, num
from .scenes import Bench


def cases(args: argparse.Namespace) -> List[Dict[str, Any]]:
    s = args.stress_size
    bw, bh = (int(v) for v in args.big_size.lower().split("x"))
    base = {"volume": "head", "preset": "paper", "size": [s, s], "azimuth": 30.0,
            "elevation": 10.0}
    r = args.stress_ref_spp
    return [
        {"name": "baseline", "spec": base, "ref_spp": r,
         "what": "head, two-band preset, for comparison"},
        {"name": "translucent", "spec": {**base, "preset": "translucent"}, "ref_spp": r,
         "what": "the head's bands at ≤5 % opacity: no opaque surface, deep scattering"},
        {"name": "strong light", "spec": {**base, "light": 20.0, "specular": [1.0, 80.0]},
         "ref_spp": r, "exposure": 0.05,
         "what": "key light ×20 (LightIntensity 20), specular 1 / power 80, radiance "
                 "×0.05 so the image is not clipped"},
        {"name": "fireflies", "spec": base, "ref_spp": r, "fireflies": [0.002, 100.0],
         "what": "synthetic unbiased fireflies: 0.2 % of the pixels ×100, the rest "
                 "×0.8 (the expectation is unchanged)"},
        {"name": "thin (stent)", "spec": {**base, "volume": "stent", "dolly": 0.7},
         "ref_spp": r, "what": "stent struts zoomed out to 1-2 pixels"},
        {"name": "exposure ×0.01", "spec": base, "ref_spp": r, "exposure": 0.01,
         "what": "radiance ×0.01 (input and reference; = light and environment ×0.01)"},
        {"name": "exposure ×100", "spec": base, "ref_spp": r, "exposure": 100.0,
         "what": "radiance ×100 (input and reference; = light and environment ×100)"},
        {"name": "8×8", "spec": {**base, "size": [8, 8]}, "ref_spp": r,
         "what": "tiny image (smaller than the coarsest grid cell)"},
        {"name": "1000×7", "spec": {**base, "size": [1000, 7]}, "ref_spp": r,
         "what": "extreme aspect ratio"},
        {"name": f"{bw}×{bh}", "spec": {**base, "size": [bw, bh]},
         "ref_spp": args.big_ref_spp,
         "what": f"large image; reference only {args.big_ref_spp} spp (time)"},
        {"name": "mostly empty", "spec": {**base, "volume": "head_padded"}, "ref_spp": r,
         "what": "head (2× downsampled) in a 3× larger air volume: 96 % empty voxels, "
                 "head small in the image"},
        {"name": "unseen volume", "spec": {**base, "volume": "procedural",
                                           "preset": "procedural", "elevation": 25.0},
         "ref_spp": r, "what": "procedural torus + blobs, 96³ float, new colours"},
    ]


# --- measure --------------------------------------------------------------------------------
def measure(bench: Bench, out: Output, results: Mapping[str, Any]) -> Dict[str, Any]:
    args = bench.args
    rows: List[Dict[str, Any]] = []
    (out.root / "gallery").mkdir(exist_ok=True)
    for case in tqdm(cases(args), desc="stress", unit="case"):
        spec, f = case["spec"], case.get("exposure", 1.0)
        p = bench.scenes.frame(spec, SEED_INPUT)
        ref = bench.reference(spec, case["ref_spp"])
        p["Radiance"] = p["Radiance"] * f
        if case.get("fireflies"):
            prob, gain = case["fireflies"]
            hit = np.random.default_rng(11).random(p["Radiance"].shape[:2]) < prob
            w = np.where(hit, gain, (1 - prob * gain) / (1 - prob)).astype(np.float32)
            p["Radiance"] = p["Radiance"] * w[..., None]
        reference = ref["ref"] * f
        images = {"noisy": p["Radiance"]}
        start = time.perf_counter()
        images["ours"] = bench.denoise(p)
        ours_ms = 1000 * (time.perf_counter() - start)
        images["OIDN fast"] = pb.oidn(p, "fast")
        fixed = pb.Ours(0, args.model, args.threads)
        fixed.den.UseNetworkOff()
        images["ours, fixed guide"] = fixed(p)
        noclamp = pb.Ours(0, args.model, args.threads)
        noclamp.den.SetClamp(0.0)
        images["ours, no clamp"] = noclamp(p)
        row: Dict[str, Any] = {"case": case["name"], "what": case["what"],
                               "size": "×".join(map(str, spec["size"])),
                               "ref_spp": case["ref_spp"],
                               "ref_check_psnr": pb.quality(ref["ref"], ref["half"])[0]}
        for k, img in images.items():
            q = pb.quality(reference, img)
            row[f"{k} psnr"], row[f"{k} ssim"] = q
            row[f"{k} finite"] = bool(np.isfinite(img).all())
        row["ours ms"] = ours_ms
        row["status"] = bench.ours[0].status()
        row["lit fraction"] = float(np.mean(p["Alpha"] > 0))
        lum = p["Radiance"].mean(axis=-1)[p["Alpha"][..., 0] > 0]
        row["peak/mean"] = float(lum.max() / max(lum.mean(), 1e-30)) if lum.size else 0.0
        row["failed"] = bool(not row["ours finite"] or row["ours psnr"] < row["noisy psnr"])
        row["analysis"] = analyse(row)
        rows.append(row)
        safe = "".join(c if c.isalnum() else "_" for c in case["name"])
        out.thumbs(f"stress_{safe}", [("noisy", images["noisy"]), ("ours", images["ours"]),
                                      ("OIDN fast", images["OIDN fast"]),
                                      (f"ref {case['ref_spp']} spp", reference)])
        row["gallery"] = f"gallery/stress_{safe}.png"
    return {"stress": rows}


def analyse(row: Mapping[str, Any]) -> str:
    """A measured diagnosis: which variant recovers where ours loses to the noisy input."""
    notes = []
    if not row["ours finite"]:
        notes.append("non-finite output from our denoiser")
    if not row["noisy finite"]:
        notes.append("the traced input itself holds non-finite values")
    gain = row["ours psnr"] - row["noisy psnr"]
    if gain < 0:
        alt = {k: row[f"{k} psnr"] - row["noisy psnr"]
               for k in ("ours, fixed guide", "ours, no clamp", "OIDN fast")}
        good = [f"{k} {v:+.2f} dB" for k, v in alt.items()]
        cause = []
        if alt["ours, no clamp"] > gain + 0.5:
            cause.append("the outlier clamp removes real energy (the clamp limits each "
                         "channel to 8× the mean; bright light is clipped)")
        if alt["ours, fixed guide"] > gain + 0.5:
            cause.append("the learned guide is worse than the fixed albedo/depth/normal "
                         "guide here (outside the training distribution)")
        if row["ref_check_psnr"] < row["noisy psnr"] + 6:
            cause.append("the reference is itself noisy (ref/2 vs ref "
                         f"{row['ref_check_psnr']:.1f} dB), which bounds any gain")
        if not cause:
            cause.append("over-blurring: the grid averages detail the reference keeps")
        notes.append(f"denoised loses {-gain:.2f} dB to the noisy input; variants vs noisy: "
                     f"{', '.join(good)}; likely cause: {'; '.join(cause)}")
    return "; ".join(notes) if notes else "ok"


# --- render ---------------------------------------------------------------------------------
def missing(results: Mapping[str, Any]) -> List[str]:
    return missing_keys(results, ("stress",))


def render(results: Mapping[str, Any], args: argparse.Namespace,
           out: Output) -> Tuple[List[str], Dict[str, Any]]:
    rows = results["stress"]
    chart(rows, out)
    return markdown(args, rows), {}


def chart(rows: Sequence[Mapping[str, Any]], out: Output) -> None:
    """stress.png/.csv: PSNR per case of noisy, ours, OIDN fast and the fixed guide."""
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(9, 4))
    keys = ("noisy", "ours", "OIDN fast", "ours, fixed guide")
    width = 0.8 / len(keys)
    for j, k in enumerate(keys):
        ax.bar(np.arange(len(rows)) + j * width, [num(r[f"{k} psnr"]) for r in rows], width,
               label=k)
    ax.set_xticks(np.arange(len(rows)) + 0.4 - width / 2)
    ax.set_xticklabels([r["case"] for r in rows], rotation=30, ha="right", fontsize=8)
    ax.set_ylabel("PSNR [dB]")
    ax.legend(fontsize=8, ncol=4)
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    out.save("stress", [{k: v for k, v in r.items()} for r in rows], fig)


def markdown(a: argparse.Namespace, rows: Sequence[Mapping[str, Any]]) -> List[str]:
    md = [
        "## 5. Stress suite", "",
        f"Head view 0 unless stated, {a.stress_size}² unless stated, one 1-spp frame "
        f"(seed {SEED_INPUT}) against a {a.stress_ref_spp}-spp reference of another seed "
        "(unless stated). Ours = the model's levels; the two variants (fixed guide = no "
        "network; no clamp = outlier clamp off) locate the cause where ours loses. "
        "'finite' = every output pixel finite (np.isfinite).", ""]
    md += md_table(
        ["case", "what", "size", "lit %", "peak / mean", "noisy PSNR", "ours PSNR",
         "OIDN fast", "fixed guide", "no clamp", "ours SSIM", "all finite", "verdict"],
        [[r["case"], r["what"], r["size"], fmt(100 * r["lit fraction"], 0),
          fmt(r["peak/mean"], 1), fmt(r["noisy psnr"]), fmt(r["ours psnr"]),
          fmt(r["OIDN fast psnr"]), fmt(r["ours, fixed guide psnr"]),
          fmt(r["ours, no clamp psnr"]), fmt(r["ours ssim"], 3),
          all(r[f"{k} finite"] for k in STRESS_METHODS),
          "**FAILED**" if r["failed"] else "ok"] for r in rows])
    failed = [r for r in rows if r["failed"] or r["analysis"] != "ok"]
    md += ["", "![stress](stress.png)", ""]
    if failed:
        md += ["Cases where the denoised image is worse than the noisy input or not "
               "finite (measured diagnosis):", ""]
        md += [f"* **{r['case']}**: {r['analysis']}" for r in failed]
    else:
        md += ["No case made the denoised image worse than the noisy input, and every "
               "output is finite."]
    md += ["", "Gallery (noisy | ours | OIDN fast | reference):", ""]
    md += [f"* {r['case']}: ![{r['case']}]({r['gallery']})" for r in rows]
    md += [""]
    return md
