"""Evaluate an exported GuideNet end to end in C++ and write the model card (guidenet.json).

For every held-out view of a training run (``<run>/run.json``) and each input spp, the ONNX
model is run by the C++ ``vtkPTVDenoiser`` (the code the mapper uses) on the view's passes, and
the same denoise is computed by the torch pipeline from the run's best checkpoint. Reported:
PSNR of noisy / denoised (C++) / 16 spp against the view's reference (1024 spp; tone-mapped
``clip(max(0, x)^(1/2.2), 0, 1)``, scikit-image, data_range 1), per dataset; the largest
C++ - torch difference relative to the image range; C++ denoise time. ``--card`` writes the model
card JSON next to the model.

Needs the compiled package (``PYTHONPATH=<build>/python``); no display (nothing is rendered).

Example::

    PYTHONPATH=build/python .venv/bin/python Training/ptv_training/evaluate.py \\
        --run .cache/training/runs/ship --model Data/Models/guidenet.onnx \\
        --card Data/Models/guidenet.json
"""
from __future__ import annotations

import argparse
import csv
import hashlib
import json
import sys
import time
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence

import numpy as np
import torch

if __package__ in (None, ""):  # run as a file
    sys.path.append(str(Path(__file__).resolve().parents[1]))
    import ptv_training  # noqa: F401
    __package__ = "ptv_training"

from pathtracedvolume.atomic import write_text  # noqa: E402

from . import exr_io  # noqa: E402
from .data import HISTORY_SPP, chw, psnr, sample_passes  # noqa: E402
from .bilateral_grid import automatic_levels  # noqa: E402
from .features import build_features, required_passes  # noqa: E402
from .guidenet import GuideNet, count_parameters, macs_per_pixel  # noqa: E402
from .scene import ensure_paths  # noqa: E402
from .train import run_model  # noqa: E402

ensure_paths()
from pathtracedvolume.scene import numpy_to_image  # noqa: E402


LOSSES = {"l1": "L1(tonemap(out), tonemap(reference))",
          "relmse": "relative MSE (out - reference)^2 / (sg(out)^2 + 0.01), sg = no gradient "
                    "(Noise2Noise: training references of 64 spp)"}


def cpp_denoise(model_file: Path, passes: Dict[str, np.ndarray], names: Sequence[str],
                threads: int = 0, alpha: bool = False) -> Dict[str, Any]:
    """Denoise ``passes`` (VTK row order) with vtkPTVDenoiser; output ``(H, W, 3)``. With
    ``alpha`` as the mapper does (DenoiseAlpha: the Alpha pass, then required, through the grid
    too, and the colour 0 where that opacity is 0)."""
    from pathtracedvolume import vtkPTVDenoiser
    from vtkmodules.util.numpy_support import vtk_to_numpy

    den = vtkPTVDenoiser()
    den.SetModelFile(str(model_file))
    den.SetNumberOfThreads(threads)
    den.SetDenoiseAlpha(alpha)
    images = []
    extra = ["Alpha"] if alpha and "Alpha" not in names else []
    for name in ["Radiance", "Albedo", *[n for n in [*names, *extra]
                                         if n not in ("Radiance", "Albedo")]]:
        if name == "HistoryLength" and name not in passes:
            continue  # a view's frame without history: both sides count one frame
        image = numpy_to_image(passes[name], name)
        images.append(image)
        den.SetImage(name, image)
    if not den.Execute():
        raise RuntimeError(f"vtkPTVDenoiser.Execute failed: {den.GetStatus()}")
    t = time.perf_counter()
    den.Execute()  # second run: timed without the model load
    seconds = time.perf_counter() - t
    out = den.GetOutput()
    w, h, _ = out.GetDimensions()
    result = vtk_to_numpy(out.GetPointData().GetArray("Denoised")).reshape(h, w, 3).copy()
    return {"output": result, "network_active": bool(den.GetNetworkActive()),
            "status": den.GetStatus(), "ms": seconds * 1e3,
            "stages_ms": {"features": den.GetLastFeatureTime(),
                          "guidenet": den.GetLastGuideNetTime(),
                          "splat": den.GetLastSplatTime(), "slice": den.GetLastSliceTime()}}


def torch_denoise(model: GuideNet, channels: Sequence[str], levels, clamp: float,
                  passes: Dict[str, np.ndarray], demodulate: bool = True,
                  use_levels: Optional[int] = None,
                  default_levels: Optional[int] = None) -> np.ndarray:
    # As the C++ denoiser with its automatic level count: the model's (or use_levels, the
    # file's) levels, its default_levels on a large image, less those too coarse for the frame
    # (bilateral_grid.automatic_levels).
    height, width = passes["Radiance"].shape[:2]
    count = use_levels if use_levels is not None else model.levels
    count = automatic_levels(list(levels)[:count], default_levels or count, height, width)
    with torch.no_grad():
        f = torch.from_numpy(build_features(passes, channels))[None]
        out, _, _ = run_model(model, f, chw(passes["Radiance"])[None],
                              chw(passes["Albedo"])[None], levels, clamp, demodulate,
                              count)
    return out[0].permute(1, 2, 0).numpy()


def sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _mean(rows: List[Dict[str, Any]], key: str) -> float:
    return float(np.mean([r[key] for r in rows]))


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(prog="python Training/ptv_training/evaluate.py",
                                description="Evaluate an exported model on a run's held-out "
                                            "views through the C++ denoiser; write the model card.")
    p.add_argument("--run", type=Path, required=True,
                   help="training run folder (run.json, best.pt)")
    p.add_argument("--model", type=Path, required=True, help="the exported .onnx model")
    p.add_argument("--data", type=Path, default=None, help="views folder (default: the run's)")
    p.add_argument("--card", type=Path, default=None, help="write the model card JSON here")
    p.add_argument("--ablation", type=Path, nargs="*", default=[],
                   help="other run folders to summarise in the card (what was tried)")
    p.add_argument("--note", action="append", default=[], metavar="KEY=TEXT",
                   help="free-text note stored under 'notes' in the card (repeatable)")
    p.add_argument("--threads", type=int, default=2, help="denoiser/torch threads (default 2)")
    p.add_argument("--tolerance", type=float, default=1e-4,
                   help="max |C++ - torch| / image range (default 1e-4)")
    return p.parse_args(argv)


def spp_key(spp: int) -> str:
    """A sample kind's name in the card: "1spp", ... or "history" (``data.HISTORY_SPP``)."""
    return "history" if spp == HISTORY_SPP else f"{spp}spp"


def run_summary(run: Path) -> Dict[str, Any]:
    """Configuration, epochs and validation curve of a training run."""
    info = json.loads((run / "run.json").read_text())
    with open(run / "log.csv") as fh:
        log = list(csv.DictReader(fh))
    flagged = [r for r in log if r.get("best") == "1"]  # the epoch best.pt holds
    best = flagged[-1] if flagged else {}
    return {"run": run.name, "channels": info["channels"], "config": info["config"],
            "parameters": info["parameters"], "macs_per_pixel": info["macs_per_pixel"],
            "epochs": len(log), "steps": int(log[-1]["steps"]) if log else 0,
            "train_seconds": float(log[-1]["elapsed_s"]) if log else 0.0,
            "best_epoch": int(best.get("epoch", 0)),
            "best_val_psnr": float(best.get("val_psnr", "nan")),
            "best_val_psnr_1spp": float(best.get("val_psnr_1spp", "nan")),
            "noisy_val_psnr_1spp": float(best.get("noisy_psnr_1spp", "nan")),
            "val_psnr_curve": {"columns": ["epoch", "elapsed_s", "val_psnr", "val_psnr_1spp"],
                               "rows": [[int(r["epoch"]), float(r["elapsed_s"]),
                                         float(r["val_psnr"]), float(r["val_psnr_1spp"])]
                                        for i, r in enumerate(log)
                                        if i % max(1, len(log) // 15) == 0 or i == len(log) - 1]}}


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = parse_args(argv)
    torch.set_num_threads(max(1, args.threads))
    info = json.loads((args.run / "run.json").read_text())
    data_dir = args.data or Path(info["data"])
    ck = torch.load(args.run / "best.pt")
    model = GuideNet(**ck["config"])
    model.load_state_dict(ck["model"])
    model.eval()
    channels = ck["channels"]
    levels = [tuple(level) for level in ck["levels"]]
    names = required_passes(channels)
    # A model shipped with its finest N levels only (train.py --export-levels), or run with D of
    # them by default (ptv.default_levels): torch does what the C++ denoiser does by default.
    import onnx
    props = {p.key: p.value for p in onnx.load(str(args.model)).metadata_props}
    use_levels = len(props.get("ptv.levels", "").split(",")) if "ptv.levels" in props else None
    default_levels = int(props["ptv.default_levels"]) if "ptv.default_levels" in props else None

    # A model trained on the mapper's edge-sampled input (train.py --edge-samples K) is
    # evaluated on it too (data.sample_passes).
    edge_samples = int(info.get("args", {}).get("edge_samples", 0))
    rows: List[Dict[str, Any]] = []
    worst = 0.0
    for name in info["val_views"]:
        view = exr_io.read_view(data_dir / name)
        ref = view["reference"]
        for spp in info["spp"]:
            passes = sample_passes(view, data_dir / name, spp, edge_samples)
            c = cpp_denoise(args.model, passes, names, args.threads)
            if not c["network_active"]:
                raise RuntimeError(f"the network is not active: {c['status']}")
            t = torch_denoise(model, channels, levels, ck["clamp"], passes,
                              ck.get("demodulate", True), use_levels, default_levels)
            span = float(t.max() - t.min()) or 1.0
            diff = float(np.abs(c["output"] - t).max() / span)
            worst = max(worst, diff)
            rows.append({"view": name, "dataset": view["view"]["dataset"], "spp": spp,
                         "noisy": psnr(passes["Radiance"], ref),
                         "denoised": psnr(c["output"], ref),
                         "denoised_torch": psnr(t, ref),
                         "spp16": psnr(view["spp16"], ref),
                         "cpp_vs_torch_rel": diff, "cpp_ms": c["ms"],
                         "cpp_stages_ms": c["stages_ms"]})

    table: Dict[str, Any] = {}
    for ds in sorted({r["dataset"] for r in rows}) + ["all"]:
        sel = [r for r in rows if ds in ("all", r["dataset"])]
        entry: Dict[str, Any] = {"views": len({r["view"] for r in sel})}
        for spp in info["spp"]:
            s = [r for r in sel if r["spp"] == spp]
            entry[spp_key(spp)] = {"noisy": _mean(s, "noisy"), "denoised": _mean(s, "denoised")}
        entry["16spp"] = _mean([r for r in sel if r["spp"] == info["spp"][0]], "spp16")
        table[ds] = entry

    print(f"{'dataset':10s} {'views':>5s} {'noisy 1spp':>11s} {'denoised':>9s} "
          f"{'16 spp':>7s} | " + " ".join(f"{spp_key(s)} n/d" for s in info["spp"][1:]))
    for ds, e in table.items():
        extra = " ".join(f"{e[spp_key(s)]['noisy']:5.2f}/{e[spp_key(s)]['denoised']:5.2f}"
                         for s in info["spp"][1:])
        print(f"{ds:10s} {e['views']:5d} {e['1spp']['noisy']:11.2f} "
              f"{e['1spp']['denoised']:9.2f} {e['16spp']:7.2f} | {extra}")
    ms = [r["cpp_ms"] for r in rows]
    print(f"C++ vs torch: max |diff| / range = {worst:.2e} (tolerance {args.tolerance:g}); "
          f"C++ denoise {np.median(ms):.1f} ms median at {ref.shape[1]}x{ref.shape[0]}, "
          f"{args.threads} threads")

    if args.card is not None:
        manifest = json.loads((data_dir / "manifest.json").read_text())
        reference_spp = exr_io.read_view(data_dir / info["val_views"][0])["view"]["reference_spp"]
        timings = [sum(v["timings"].values()) for v in manifest["views"] if v["timings"]]
        card = {
            "model": args.model.name,
            "format": "guidenet-v1",
            "sha256": sha256(args.model),
            "bytes": args.model.stat().st_size,
            "architecture": ck["config"],
            "parameters": count_parameters(model),
            "macs_per_pixel": macs_per_pixel(model),
            "channels": channels,
            "levels": [list(level) for level in
                       levels[:len(props["ptv.levels"].split(",")) if "ptv.levels" in props
                              else len(levels)]],
            "default_levels": default_levels or use_levels or len(levels),
            "trained_levels": [list(level) for level in levels],
            "clamp": ck["clamp"],
            "demodulate": ck.get("demodulate", True),
            "training": {**run_summary(args.run), "command": info["command"],
                         "train_views": info["train_views"], "val_views": info["val_views"],
                         "spp": info["spp"], "optimizer": f"Adam lr {info['args']['lr']}, "
                         f"batch {info['args']['batch']}, grad-norm clip "
                         f"{info['args']['clip_grad']}, 8 flips/rotations, whole "
                         f"{ref.shape[1]}x{ref.shape[0]} views",
                         "loss": LOSSES[info["args"].get("loss", "l1")]},
            "data": {"command": manifest.get("command"), "format": manifest.get("format"),
                     "parameters": manifest.get("parameters"), "views": len(manifest["views"]),
                     "bytes": manifest.get("bytes"),
                     "render_seconds_total": float(np.sum(timings)) if timings else None,
                     "render_seconds_median_view": float(np.median(timings)) if timings
                     else None,
                     "reference_check": (manifest.get("reference_check") or {}).get("all")},
            "validation": {"metric": f"PSNR (dB) vs the {reference_spp}-spp reference, tone-mapped "
                                     "clip(max(0,x)^(1/2.2),0,1), skimage data_range 1; "
                                     "denoised = C++ vtkPTVDenoiser with this file",
                           "per_dataset": table,
                           "cpp_vs_torch_max_rel_diff": worst,
                           "cpp_denoise_ms_median": float(np.median(ms)),
                           "cpp_threads": args.threads,
                           "rows": [{k: v for k, v in r.items() if k != "cpp_stages_ms"}
                                    for r in rows]},
            "tried": [run_summary(r) for r in args.ablation],
            "notes": dict(n.split("=", 1) for n in args.note),
        }
        write_text(args.card, json.dumps(card, indent=1) + "\n")
        print(f"wrote {args.card}")
    return 0 if worst <= args.tolerance else 1


if __name__ == "__main__":
    raise SystemExit(main())
