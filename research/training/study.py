"""CLI: the training studies in one command each — ablations, leave-one-out, U-Net, CPU cost.

Every experiment is one ``train.py`` run with the same data, seed, step budget and optimizer, so
only the named factor differs; runs go in ``<runs>/<study>_<name>`` and are reused when their
``best.pt`` exists (a rerun only trains what is missing). The tables report validation PSNR at
1 spp per dataset (tone-mapped, against the 1024-spp reference, the held-out views of
``split_views``), read from each run's best checkpoint, plus the network's size and cost.

    python Training/ptv_training/study.py ablation --steps 800
    python Training/ptv_training/study.py loo --steps 800
    python Training/ptv_training/study.py unet --steps 800
    python Training/ptv_training/study.py cpu --steps 800
    python Training/ptv_training/study.py v2-features --steps 1500 --jobs 2
    python Training/ptv_training/study.py v2-loo --steps 1500 --jobs 2
    python Training/ptv_training/study.py v2-cpu --steps 600 --jobs 2
    python Training/ptv_training/study.py v3-loo --steps 600 --jobs 2

``ablation``, ``loo``, ``unet`` and ``cpu`` ran on the first data set (``.cache/training/v1``:
head, stent and concrete with jittered presets, 128², 1024-spp references; L1 loss), which is
their default data. The ``v2-*`` studies run on the second (``.cache/training/v2``: every dataset
of ``Data/datasets.json``, random transfer functions, 256², 64-spp Noise2Noise targets; relative
MSE), always with the shipped architecture (hidden 16, 5 x 5, stride 2, 8 outputs, PAPER_10, 3
levels): ``v2-features`` asks which auxiliary features and which loss pay, ``v2-loo`` trains once
without each volume and tests on its held-out views. ``v2-cpu`` is ``cpu`` again on the second data
set: the shipped network against a 3 x 3 second conv, 3 x 3 throughout and 1/4 resolution.
``v3-loo`` is ``v2-loo`` with the architecture shipped since that study (hidden 32, 3 x 3
throughout, stride 2, 8 outputs, PAPER_10, 3 levels), on the same data. ``v4-loo`` is the
recipe shipped since the coverage study: ``v3-loo`` with the ``coverage`` channel, level dropout
and the jittered presets (``generate.py --tf presets``, ``.cache/training/presets``) as extra
data, whose views of the left-out volume are left out as well.

``unet`` is the paper's Table 2: the U-Net baseline (``unet.py``) against the bilateral-grid
denoiser, PSNR as above plus the C++ denoise time (``vtkPTVDenoiser``, the same ONNX Runtime
path; median of ``--repeats`` runs at 128² and at 512², 2 threads).

``cpu`` trains cheaper GuideNets for ONNX Runtime on the CPU (the shipped flags: PAPER_10, 3
levels, no demodulation): fewer hidden channels, 3 x 3 kernels, the network at 1/2 or 1/4
resolution (``--stride``) and outputs padded to 8 channels (``--out-channels``);
``paper_h20_L3`` is today's architecture (the ablation's run, shared). MACs are per
full-resolution pixel. Each run's model is exported to ``<run>/model.onnx`` for the C++ timing
of ``Testing/Benchmarks/pareto_denoiser.py`` (PSNR against ms at 1024²).

Results: ``Training/results/<study>.md`` and ``.json`` (written atomically).
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence

if __package__ in (None, ""):  # run as a file: python Training/ptv_training/study.py
    sys.path.append(str(Path(__file__).resolve().parents[1]))
    import ptv_training  # noqa: F401
    __package__ = "ptv_training"

from pathtracedvolume.atomic import write_text  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parents[2]
TRAIN = REPO_ROOT / "Training" / "ptv_training" / "train.py"
DEFAULT_RUNS = REPO_ROOT / ".cache" / "training" / "runs"
DEFAULT_RESULTS = REPO_ROOT / "Training" / "results"
DATASETS = ("concrete", "head", "stent")  # the first data set's (v1) datasets
DATA_V1 = REPO_ROOT / ".cache" / "training" / "v1"
DATA_V2 = REPO_ROOT / ".cache" / "training" / "v2"
KEEP_WITHIN_DB = 0.2  # keep the cheapest configuration within this of the best


@dataclass
class Experiment:
    name: str
    what: str
    args: List[str] = field(default_factory=list)


BASE = ["--channels", "VOLUME_FEATURES", "--hidden", "8", "--kernel", "5", "--no-demodulate"]
# The shipped configuration, chosen by the ablation (cheapest within 0.2 dB of the best).
SHIP = ["--channels", "PAPER_10", "--hidden", "20", "--kernel", "5", "--no-demodulate"]
# Runs shared between studies (trained once): (study, experiment) -> run folder; study "" is
# every study on the first data set.
SHARED = {("", "vol_h8_L3"): "study_vol_h8_L3",
          ("", "paper_h20_L3"): "study_ablation_paper_h20_L3",
          # v2-loo's in-domain run is v2-features' paper10, and so is v2-cpu's first architecture
          ("v2-loo", "all"): "study_v2-features_paper10",
          ("v2-cpu", "h16_k5_s2"): "study_v2-features_paper10"}


def cpu_candidate(hidden: int, kernel: int, stride: int, out_channels: int,
                  levels: int = 3) -> Experiment:
    """A ``cpu`` study run: the shipped flags with this GuideNet size, stride, padding and
    number of grid levels (the finest ``levels`` of 4:4, 8:8, 16:16)."""
    steps = ",".join(f"{s}:{s}" for s in (4, 8, 16)[:levels])
    suffix = "" if levels == 3 else f"_L{levels}"
    return Experiment(
        f"h{hidden}_k{kernel}_s{stride}{suffix}",
        f"hidden {hidden}, {kernel}x{kernel}, stride {stride}, {out_channels} outputs, "
        f"{levels} levels",
        ["--channels", "PAPER_10", "--hidden", str(hidden), "--kernel", str(kernel),
         "--stride", str(stride), "--out-channels", str(out_channels), "--no-demodulate",
         "--levels", steps])


# (hidden, kernel, stride, out_channels[, levels]). Today's architecture (20, 5, 1, 5) is the
# ablation's paper_h20_L3 run (same data, seed, steps and flags), shared rather than trained
# again. The 2-level runs follow the first chart at 1024², where 2 of the 3 levels measured
# better than 3 for every network (pareto_denoiser.py).
CPU_CANDIDATES = ((16, 3, 1, 8), (16, 3, 2, 8), (16, 5, 2, 8), (16, 3, 4, 8), (8, 3, 2, 8),
                  (8, 5, 2, 8), (16, 3, 2, 8, 2), (16, 5, 2, 8, 2), (8, 3, 2, 8, 2))

STUDIES: Dict[str, List[Experiment]] = {
    "ablation": [
        Experiment("vol_h8_L3", "volume features, hidden 8, 3 levels (candidate)", BASE),
        Experiment("color_h8_L3", "colour only (3 ch), hidden 8, 3 levels",
                   ["--channels", "COLOR_ONLY", "--hidden", "8", "--no-demodulate"]),
        Experiment("vol_h8_L1", "volume features, hidden 8, 1 level (4:4)",
                   BASE + ["--levels", "4:4"]),
        Experiment("paper_h20_L3", "the original GuideNet: 10 ch -> 20 -> 5, 5x5", SHIP),
        Experiment("vol_h20_L3", "volume features, hidden 20, 3 levels",
                   ["--channels", "VOLUME_FEATURES", "--hidden", "20", "--no-demodulate"]),
        Experiment("vol_h4_L3", "volume features, hidden 4, 3 levels",
                   ["--channels", "VOLUME_FEATURES", "--hidden", "4", "--no-demodulate"]),
        Experiment("vol_h0_L3", "volume features, a single 5x5 conv, 3 levels",
                   ["--channels", "VOLUME_FEATURES", "--hidden", "0", "--no-demodulate"]),
        Experiment("vol_h8_L3_demod", "as the candidate, with albedo demodulation",
                   ["--channels", "VOLUME_FEATURES", "--hidden", "8"]),
    ],
    "loo": [Experiment("paper_h20_L3", "all three datasets (in-domain, shipped config)", SHIP)] + [
        Experiment(f"no_{d}", f"trained without {d}", SHIP + ["--exclude", d])
        for d in DATASETS],
    "unet": [Experiment("paper_h20_L3", "bilateral grid + GuideNet (ours, shipped config)", SHIP),
             Experiment("unet_w16", "U-Net autoencoder (Hofmann et al. 2020 style), width 16",
                        ["--arch", "unet", "--width", "16", "--channels", "VOLUME_FEATURES"])],
    "cpu": [Experiment("paper_h20_L3", "today's GuideNet: hidden 20, 5x5, stride 1, 5 outputs",
                       SHIP)] + [cpu_candidate(*c) for c in CPU_CANDIDATES],
}


# The shipped architecture since the cpu study; v2 runs use the relative-MSE loss (train.py).
V2_SHIP = ["--channels", "PAPER_10", "--hidden", "16", "--kernel", "5", "--stride", "2",
           "--out-channels", "8", "--no-demodulate"]


def v2_cpu_candidate(hidden: int, kernel: int, kernel2: int, stride: int) -> Experiment:
    """A ``v2-cpu`` study run: the shipped flags (PAPER_10, 8 outputs, 3 levels) with this hidden
    width, first and second kernel and stride."""
    kernels = f"k{kernel}" if kernel2 == kernel else f"k{kernel}k{kernel2}"
    flags = with_flag(with_flag(with_flag(V2_SHIP, "--hidden", hidden), "--kernel", kernel),
                      "--stride", stride)
    if kernel2 != kernel:
        flags += ["--kernel2", str(kernel2)]
    return Experiment(f"h{hidden}_{kernels}_s{stride}",
                      f"hidden {hidden}, {kernel}x{kernel} then {kernel2}x{kernel2}, "
                      f"stride {stride}", flags)


def with_flag(flags: List[str], name: str, value: Any) -> List[str]:
    out = list(flags)
    out[out.index(name) + 1] = str(value)
    return out


def with_channels(flags: List[str], channels: str) -> List[str]:
    return with_flag(flags, "--channels", channels)


STUDIES["v2-features"] = [
    Experiment("paper10", "colour, albedo, normal, depth (PAPER_10, shipped)", V2_SHIP),
    Experiment("volume", "PAPER_10 + scatter normal and depth (VOLUME_FEATURES)",
               with_channels(V2_SHIP, "VOLUME_FEATURES")),
    Experiment("color", "colour only (COLOR_ONLY)", with_channels(V2_SHIP, "COLOR_ONLY")),
    Experiment("paper10_l1", "PAPER_10, L1 on tone-mapped images instead of relative MSE",
               V2_SHIP + ["--loss", "l1"]),
]


# ONNX Runtime's NCHWc convolution pads the second conv's 8 outputs to 16 on AVX-512, which made it
# the costlier of the two at 5 x 5 (ORT profile: 10.7 of 18.6 ms at 1024²); a 3 x 3 second conv, 3 x 3
# throughout, and the network at 1/4 resolution are the cheaper candidates (first is the shipped one).
V2_CPU_CANDIDATES = ((16, 5, 5, 2), (16, 5, 3, 2), (16, 3, 3, 2), (16, 5, 3, 4))
STUDIES["v2-cpu"] = [v2_cpu_candidate(*c) for c in V2_CPU_CANDIDATES]


# The architecture shipped since the v2-cpu study (d251c34): hidden 32, 3 x 3 throughout.
V3_SHIP = with_flag(with_flag(V2_SHIP, "--hidden", 32), "--kernel", 3)
# The leave-one-out studies: each trains ``flags`` on every dataset, and once without each.
# The recipe shipped since the coverage study: PAPER_10 + the camera rays' coverage, level dropout,
# and the jittered presets of head, stent and concrete besides the random transfer functions.
PRESETS_DATA = Path(__file__).resolve().parents[2] / ".cache" / "training" / "presets"
V4_SHIP = with_channels(V3_SHIP, "PAPER_10,coverage") + [
    "--level-counts", "1,3", "--extra-data", str(PRESETS_DATA)]
LOO_FLAGS = {"v2-loo": V2_SHIP, "v3-loo": V3_SHIP, "v4-loo": V4_SHIP}


def leave_one_out(datasets: Sequence[str], flags: List[str]) -> List[Experiment]:
    """A leave-one-out study: ``flags`` on every dataset, and once without each."""
    return [Experiment("all", "every dataset (in-domain)", flags)] + [
        Experiment(f"no_{d}", f"trained without {d}", flags + ["--exclude", d])
        for d in datasets]


def on_second_data(study: str) -> bool:
    """Whether a study runs on the second data set (relative-MSE loss) rather than the first."""
    return study.startswith(("v2-", "v3-", "v4-"))


def data_datasets(data: Path) -> List[str]:
    """The datasets of a views folder's manifest, sorted."""
    manifest = json.loads((data / "manifest.json").read_text())
    return sorted({r["view"]["dataset"] for r in manifest["views"]})


def default_data(study: str) -> Path:
    return DATA_V2 if on_second_data(study) else DATA_V1


def run_dir(runs: Path, study: str, name: str, seed: int = 0) -> Path:
    """The run folder of an experiment; seeds other than 0 get folders of their own."""
    if seed:
        return runs / f"study_{study}_{name}_seed{seed}"
    key = (study if on_second_data(study) else "", name)
    return runs / SHARED.get(key, f"study_{study}_{name}")


def results_stem(study: str, seed: int) -> str:
    """Training/results/<stem>.md/.json: the study's name, with the seed unless it is 0."""
    return f"{study}_seed{seed}" if seed else study


def train(exp: Experiment, out: Path, args: argparse.Namespace) -> float:
    """Train one experiment unless its best.pt exists; returns the wall-clock seconds."""
    if (out / "best.pt").is_file() and (out / "done").is_file():
        return 0.0
    cmd = [sys.executable, str(TRAIN), "--out", str(out), "--max-steps", str(args.steps),
           "--minutes", "600", "--threads", "1", "--seed", str(args.seed), "--no-progress",
           *exp.args, "--data", str(args.data)]
    if not on_second_data(args.study):
        cmd += ["--loss", "l1"]  # the first studies' loss (before train.py's relmse default)
    if (out / "last.pt").is_file():
        cmd.append("--resume")
    start = time.monotonic()
    log = out.with_suffix(".log")
    out.parent.mkdir(parents=True, exist_ok=True)
    with open(log, "w") as fh:
        result = subprocess.run(cmd, stdout=fh, stderr=subprocess.STDOUT)
    if result.returncode != 0:
        raise RuntimeError(f"{exp.name} failed ({result.returncode}); see {log}")
    write_text(out / "done", " ".join(cmd) + "\n")
    return time.monotonic() - start


def summarise(exp: Experiment, out: Path) -> Dict[str, Any]:
    import torch

    ck = torch.load(out / "best.pt", weights_only=False)
    info = json.loads((out / "run.json").read_text())
    rows = [r for r in ck.get("validation_rows", []) if r["spp"] == 1]
    names = sorted({r["dataset"] for r in rows})
    per = {d: sum(r["psnr"] for r in rows if r["dataset"] == d)
           / max(1, sum(1 for r in rows if r["dataset"] == d)) for d in names}
    noisy = {d: sum(r["noisy"] for r in rows if r["dataset"] == d)
             / max(1, sum(1 for r in rows if r["dataset"] == d)) for d in names}
    return {"name": exp.name, "what": exp.what, "args": exp.args, "run": out.name,
            "channels": len(info["channels"]), "parameters": info["parameters"],
            "macs_per_pixel": info["macs_per_pixel"], "levels": info["levels"],
            "best_epoch": ck["state"]["best_epoch"], "steps": ck["state"]["steps"],
            "train_minutes": ck["state"]["elapsed"] / 60,
            "psnr_1spp": per, "noisy_1spp": noisy,
            "psnr_1spp_mean": sum(per.values()) / len(per),
            "val_psnr_1_2_4spp": ck["state"]["best_psnr"]}


def ensure_onnx(out: Path) -> Path:
    """``<run>/model.onnx`` exported from the run's best checkpoint (once)."""
    import torch

    from .export_onnx import export, export_image_model
    from .guidenet import GuideNet
    from .unet import UNet

    path = out / "model.onnx"
    if path.is_file():
        return path
    ck = torch.load(out / "best.pt", weights_only=False)
    extra = {"ptv.weights": f"study run {out.name}, epoch {ck['state']['best_epoch']}"}
    if "width" in ck["config"]:
        model = UNet(**ck["config"])
        model.load_state_dict(ck["model"])
        return export_image_model(model, path, ck["channels"], extra_metadata=extra)
    model = GuideNet(**ck["config"])
    model.load_state_dict(ck["model"])
    extra["ptv.demodulate"] = "1" if ck.get("demodulate", True) else "0"
    return export(model, path, ck["channels"], [tuple(l) for l in ck["levels"]],
                  extra_metadata=extra)


def time_cpp(models: Sequence[Path], data: Optional[Path], repeats: int
             ) -> List[Dict[str, float]]:
    """Median C++ denoise ms of each model on one validation view at 128² and tiled 4 x 4 to
    512², the models interleaved within each repeat (so load on a shared machine hits all
    alike)."""
    import numpy as np

    from . import exr_io
    from .data import split_views
    from .evaluate import cpp_denoise
    from .train import DEFAULT_DATA

    _, val, _ = split_views(data or DEFAULT_DATA, 3)
    passes = exr_io.read_view(val[0])["inputs"][1]
    names = sorted(passes)  # every pass a view has: enough for any model's channels
    results: List[Dict[str, float]] = [{} for _ in models]
    for size, tiles in ((128, 1), (512, 4)):
        tiled = {k: np.ascontiguousarray(np.tile(v, (tiles, tiles) + (1,) * (v.ndim - 2)))
                 for k, v in passes.items()}
        runs: List[List[float]] = [[] for _ in models]
        for _ in range(repeats):
            for i, model in enumerate(models):
                runs[i].append(cpp_denoise(model, tiled, names, threads=2)["ms"])
        for i in range(len(models)):
            results[i][f"ms_{size}"] = float(np.median(runs[i]))
    return results


def atomic_write(path: Path, text: str) -> None:
    write_text(path, text)  # temporary file + rename


def table(results: List[Dict[str, Any]], reference: Optional[Dict[str, Any]] = None) -> str:
    DATASETS = list(results[0]["psnr_1spp"])  # noqa: N806 (the runs' validation datasets)
    head = ("| experiment | what | params | MACs/px | train min | " + " | ".join(DATASETS)
            + " | mean | Δ vs first |\n|---|---|---|---|---|" + "---|" * len(DATASETS)
            + "---|---|\n")
    first = reference or results[0]
    lines = []
    for r in results:
        cells = " | ".join(f"{r['psnr_1spp'][d]:.2f}" for d in DATASETS)
        lines.append(f"| `{r['name']}` | {r['what']} | {r['parameters']} | "
                     f"{r['macs_per_pixel']} | {r['train_minutes']:.1f} | {cells} | "
                     f"{r['psnr_1spp_mean']:.2f} | "
                     f"{r['psnr_1spp_mean'] - first['psnr_1spp_mean']:+.2f} |")
    noisy = " | ".join(f"{results[0]['noisy_1spp'][d]:.2f}" for d in DATASETS)
    lines.append(f"| noisy 1 spp | — | — | — | — | {noisy} | "
                 f"{sum(results[0]['noisy_1spp'].values()) / len(DATASETS):.2f} | |")
    return head + "\n".join(lines) + "\n"


def verdict(study: str, results: List[Dict[str, Any]]) -> str:
    by = {r["name"]: r for r in results}
    if study == "unet":
        lines = ["| denoiser | C++ ms 128² | C++ ms 512² | mean PSNR 1 spp |", "|---|---|---|---|"]
        for r in results:
            lines.append(f"| `{r['name']}` | {r['ms_128']:.1f} | {r['ms_512']:.1f} | "
                         f"{r['psnr_1spp_mean']:.2f} |")
        a, b = results[0], by.get("unet_w16")
        if a and b:
            lines.append(f"\nU-Net / ours: {b['ms_512'] / a['ms_512']:.1f}x the time at 512², "
                         f"{b['psnr_1spp_mean'] - a['psnr_1spp_mean']:+.2f} dB.")
        return "\n".join(lines) + "\n"
    best = max(results, key=lambda r: r["psnr_1spp_mean"])
    ok = [r for r in results if r["psnr_1spp_mean"] >= best["psnr_1spp_mean"] - KEEP_WITHIN_DB]
    keep = min(ok, key=lambda r: (r["macs_per_pixel"], len(r["levels"].split(","))))
    cheapest = (f"- Best mean: `{best['name']}` {best['psnr_1spp_mean']:.2f} dB. Cheapest within "
                f"{KEEP_WITHIN_DB} dB of it: **`{keep['name']}`** ({keep['macs_per_pixel']} "
                f"MACs/px, {keep['levels']}).")
    if study in ("cpu", "v2-cpu"):
        ref = results[0]  # today's architecture
        lines = [cheapest] + [
            f"- `{r['name']}`: {r['macs_per_pixel'] / ref['macs_per_pixel']:.3f}x the MACs of "
            f"`{ref['name']}`, {r['psnr_1spp_mean'] - ref['psnr_1spp_mean']:+.2f} dB."
            for r in results[1:]]
        return "\n".join(lines) + "\n"
    if study == "v2-features":
        ref = by["paper10"]
        lines = [cheapest] + [
            f"- `{r['name']}` ({r['what']}): {r['psnr_1spp_mean'] - ref['psnr_1spp_mean']:+.2f} dB "
            f"mean over `paper10`, per dataset " + ", ".join(
                f"{d} {r['psnr_1spp'][d] - ref['psnr_1spp'][d]:+.2f}" for d in ref["psnr_1spp"])
            + "." for r in results if r is not ref]
        return "\n".join(lines) + "\n"
    if study == "ablation":
        lines = [cheapest]
        if "color_h8_L3" in by and "vol_h8_L3" in by:
            gain = by["vol_h8_L3"]["psnr_1spp_mean"] - by["color_h8_L3"]["psnr_1spp_mean"]
            lines.append(f"- Auxiliary features over colour only: {gain:+.2f} dB (target ≥ +0.5).")
        if "vol_h8_L1" in by and "vol_h8_L3" in by:
            gain = by["vol_h8_L3"]["psnr_1spp_mean"] - by["vol_h8_L1"]["psnr_1spp_mean"]
            lines.append(f"- 3 levels over 1 level: {gain:+.2f} dB.")
        if "vol_h8_L3_demod" in by and "vol_h8_L3" in by:
            gain = by["vol_h8_L3"]["psnr_1spp_mean"] - by["vol_h8_L3_demod"]["psnr_1spp_mean"]
            lines.append(f"- No demodulation over demodulation: {gain:+.2f} dB.")
        return "\n".join(lines) + "\n"
    lines = []
    ref = results[0]  # the in-domain model
    for d in ref["psnr_1spp"]:
        r = by.get(f"no_{d}")
        if r and ref:
            gap = r["psnr_1spp"][d] - ref["psnr_1spp"][d]
            # The same run on the datasets it did see: one seed's training noise, which the
            # unseen dataset's gap includes too.
            seen = [r["psnr_1spp"][e] - ref["psnr_1spp"][e] for e in ref["psnr_1spp"] if e != d]
            lines.append(f"- {d}, unseen: {r['psnr_1spp'][d]:.2f} dB vs in-domain "
                         f"{ref['psnr_1spp'][d]:.2f} dB ({gap:+.2f}; target within -0.5); the "
                         f"same run on the datasets it saw: {sum(seen) / len(seen):+.2f} dB "
                         f"mean ({min(seen):+.2f} to {max(seen):+.2f}).")
    return "\n".join(lines) + "\n"


def loo_gaps(results: List[Dict[str, Any]]) -> Dict[str, float]:
    """A leave-one-out study's unseen-volume gaps: no_<d> on d minus the in-domain run on d."""
    by = {r["name"]: r for r in results}
    ref = by["all"]["psnr_1spp"]
    return {d: by[f"no_{d}"]["psnr_1spp"][d] - ref[d] for d in ref if f"no_{d}" in by}


def seeds_summary(study: str, seeds: Sequence[int], results_dir: Path) -> Dict[str, Any]:
    """Each seed's unseen-volume gaps, read from ``<study>[_seed<N>].json``, and their mean.

    One seed's training noise is of the size of the target (the verdict lines show it on the
    volumes each run saw), so the mean over seeds is the figure to compare with the target."""
    gaps: Dict[int, Dict[str, float]] = {}
    for seed in seeds:
        path = results_dir / f"{results_stem(study, seed)}.json"
        if not path.is_file():
            raise SystemExit(f"study.py: {path} is missing; run the study with --seed {seed} "
                             "first")
        gaps[seed] = loo_gaps(json.loads(path.read_text())["results"])
    datasets = sorted(set.intersection(*(set(g) for g in gaps.values())))
    mean = {d: sum(gaps[s][d] for s in seeds) / len(seeds) for d in datasets}
    rows = ["| unseen volume | " + " | ".join(f"seed {s}" for s in seeds)
            + " | mean | within 0.5 dB |", "|---|" + "---|" * (len(seeds) + 2)]
    rows += [f"| {d} | " + " | ".join(f"{gaps[s][d]:+.2f}" for s in seeds)
             + f" | {mean[d]:+.2f} | {'yes' if mean[d] >= -0.5 else 'no'} |" for d in datasets]
    worst = min(datasets, key=lambda d: mean[d])
    sources = "`, `".join(f"{results_stem(study, s)}.json" for s in seeds)
    text = (f"# GuideNet {study} study over {len(seeds)} seeds\n\n"
            f"Command: `python Training/ptv_training/study.py {study} --seeds-summary "
            f"{' '.join(map(str, seeds))}` (reads `{sources}`; trains nothing).\n\n"
            "Validation PSNR of the run trained without each volume, on that volume, minus the "
            "in-domain run's of the same seed (dB, 1 spp, torch, 3 levels); target: within "
            "0.5 dB.\n\n" + "\n".join(rows) + "\n\n"
            f"- {sum(mean[d] >= -0.5 for d in datasets)} of {len(datasets)} unseen volumes are "
            f"within 0.5 dB on the mean of the seeds; the worst is {worst} ({mean[worst]:+.2f}; "
            f"its seeds {min(gaps[s][worst] for s in seeds):+.2f} to "
            f"{max(gaps[s][worst] for s in seeds):+.2f}).\n")
    return {"text": text, "gaps": {str(s): gaps[s] for s in seeds}, "mean": mean}


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(prog="python Training/ptv_training/study.py",
                                description="Train and tabulate one study: ablation, "
                                            "leave-one-out, U-Net or CPU cost (runs are reused "
                                            "when already trained).")
    p.add_argument("study", choices=sorted([*STUDIES, *LOO_FLAGS]), help="which study")
    p.add_argument("--steps", type=int, default=800, help="training steps per run (default 800)")
    p.add_argument("--seed", type=int, default=0,
                   help="seed of every run (default 0); another seed trains runs of its own and "
                        "writes <study>_seed<N>.md/.json")
    p.add_argument("--seeds-summary", type=int, nargs="+", default=None, metavar="SEED",
                   help="leave-one-out studies: train nothing, read the results of these seeds "
                        "and write <study>_seeds.md/.json (each seed's unseen-volume gaps and "
                        "their mean)")
    p.add_argument("--jobs", type=int, default=2,
                   help="runs trained at once, one thread each (default 2)")
    p.add_argument("--data", type=Path, default=None,
                   help=f"views folder (default: {DATA_V2} for the v2-*/v3-* studies, else "
                        f"{DATA_V1})")
    p.add_argument("--holdout", nargs="*", default=None, metavar="DATASET",
                   help="v2-loo, v3-loo: the datasets to leave out one at a time (default: all)")
    p.add_argument("--repeats", type=int, default=9, help="C++ timing repeats (unet study)")
    p.add_argument("--runs", type=Path, default=DEFAULT_RUNS, help="run folders go here")
    p.add_argument("--results", type=Path, default=DEFAULT_RESULTS,
                   help="write <study>.md/.json here")
    return p.parse_args(argv)


def main(argv: Optional[Sequence[str]] = None) -> int:
    from tqdm import tqdm

    args = parse_args(argv)
    if args.seeds_summary:
        if args.study not in LOO_FLAGS:
            raise SystemExit(f"study.py: --seeds-summary needs a leave-one-out study "
                             f"({', '.join(sorted(LOO_FLAGS))}), not {args.study}")
        summary = seeds_summary(args.study, args.seeds_summary, args.results)
        text = summary.pop("text")
        atomic_write(args.results / f"{args.study}_seeds.md", text)
        atomic_write(args.results / f"{args.study}_seeds.json",
                     json.dumps({"seeds": args.seeds_summary, **summary}, indent=1) + "\n")
        print(text)
        return 0
    args.data = args.data or default_data(args.study)
    experiments = leave_one_out(args.holdout or data_datasets(args.data), LOO_FLAGS[args.study]) \
        if args.study in LOO_FLAGS else STUDIES[args.study]
    outs = [run_dir(args.runs, args.study, e.name, args.seed) for e in experiments]
    start = time.monotonic()
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        futures = [pool.submit(train, e, o, args) for e, o in zip(experiments, outs)]
        for f in tqdm(futures, desc=args.study, unit="run"):
            f.result()
    wall = time.monotonic() - start
    results = [summarise(e, o) for e, o in zip(experiments, outs)]
    if args.study == "unet":
        timings = time_cpp([ensure_onnx(o) for o in outs], args.data, args.repeats)
        for r, t in zip(results, timings):
            r.update(t)
    if args.study in ("cpu", "v2-cpu"):  # the models for Testing/Benchmarks/pareto_denoiser.py
        for o in outs:
            ensure_onnx(o)
    command = "python Training/ptv_training/study.py " + " ".join(
        sys.argv[1:] if argv is None else list(argv))
    text = (f"# GuideNet {args.study} study\n\n"
            f"Command: `{command}` ({args.steps} steps per run, seed {args.seed}, batch 4 "
            f"views, 1 thread per run, several runs sharing the 2 cores; this invocation's wall "
            f"time {wall / 60:.1f} min, runs already trained are reused; 'train min' is each "
            "run's own training time).\n\n"
            "Validation PSNR (dB) at 1 spp, tone-mapped, against the 1024-spp reference, mean "
            "over each dataset's held-out views; MACs per full-resolution pixel.\n\n"
            + table(results) + "\n"
            + verdict(args.study, results))
    stem = results_stem(args.study, args.seed)
    atomic_write(args.results / f"{stem}.md", text)
    atomic_write(args.results / f"{stem}.json",
                 json.dumps({"command": command, "steps": args.steps, "seed": args.seed,
                             "results": results}, indent=1) + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
