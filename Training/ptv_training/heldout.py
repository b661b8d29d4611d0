"""CLI: the held-out transfer-function table: ours against OIDN RT fast on transfer-function shapes
the training data never has.

For every dataset (default: all of ``Data/datasets.json``) and each held-out shape of
:func:`ptv_training.transfer.held_out_transfer_functions` (translucent, smooth, narrow), the
first ``--views`` of two fixed cameras (azimuth 30, elevation 10; azimuth 210, elevation 25; a
key light up and to the right of the camera, the default background) are rendered once at
``--size`` squared like a training view (``generate.render_view``: 1/2/4-spp passes, with
the Footprint pass that the mapper gives its denoiser, a ``--reference-spp`` reference of an
independent seed and its first half for the convergence check) and kept as EXR files in
``--views-dir`` (rerun: verified and reused). Each model given (``--model``, default the
shipped one) then denoises the 1-spp passes through the C++ ``vtkPTVDenoiser``, and OIDN RT fast (``pyoidn``, HDR colour + albedo + normal) the same passes: the frame the mapper gives its
denoiser, i.e. with ``--edge-samples`` EdgeSamples on the volume's edge pixels (traced again
from the view's input seed; the stored frame elsewhere, bit for bit).

Reported per (shape, dataset): PSNR and SSIM of noisy 1 spp, each model and OIDN fast against the
reference (tone-mapped ``clip(max(0, x)^(1/2.2), 0, 1)``, scikit-image, data_range 1), and
``ours - OIDN fast``; per shape the mean over datasets, against the target ours >= OIDN fast -
0.3 dB. Writes ``<results>/heldout_tf.md`` and ``.json`` atomically.

Run under Xvfb with the built package on PYTHONPATH (rendering), e.g.::

    PYTHONPATH=build/python xvfb-run -a -s "-screen 0 1024x768x24 -noreset" \\
        .venv/bin/python Training/ptv_training/heldout.py
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence

import numpy as np

if __package__ in (None, ""):  # run as a file
    sys.path.append(str(Path(__file__).resolve().parents[1]))
    import ptv_training  # noqa: F401
    __package__ = "ptv_training"

from pathtracedvolume.atomic import write_text  # noqa: E402

from . import exr_io  # noqa: E402
from .scene import ensure_paths  # noqa: E402

ensure_paths()

REPO_ROOT = Path(__file__).resolve().parents[2]
SHAPES = ("translucent", "smooth", "narrow")
CAMERAS = ((30.0, 10.0), (210.0, 25.0))
TARGET_DB = -0.3


def heldout_view(dataset: str, shape: str, camera: int, tf: Dict[str, Any], size: int,
                 reference_spp: int) -> Dict[str, Any]:
    """The parameters of one held-out view (deterministic; seeds from the names)."""
    import hashlib

    from pathtracedvolume.scene import BACKGROUND

    key = hashlib.sha256(f"heldout/{dataset}/{shape}/{camera}".encode()).digest()
    seeds = np.random.default_rng(int.from_bytes(key[:8], "little")).integers(1, 2**31 - 1, 2)
    azimuth, elevation = CAMERAS[camera]
    return {"dataset": dataset, "index": camera, "split": "heldout", "heldout": shape,
            "transfer_function": tf, "azimuth": azimuth, "elevation": elevation,
            "distance_factor": 1.0,
            "light": {"azimuth": 35.0, "elevation": 40.0, "intensity": 1.0},
            "background": list(BACKGROUND), "input_seed": int(seeds[0]),
            "reference_seed": int(seeds[1]), "size": [size, size],
            "reference_spp": int(reference_spp), "input_spp": list(exr_io.INPUT_SPP),
            "baseline_spp": 16}


def ensure_views(args: argparse.Namespace) -> List[Path]:
    """Render the views that are missing or do not verify; return every view file."""
    from tqdm import tqdm

    from .generate import dataset_histogram, render_view
    from .scene import Scene
    from .transfer import held_out_transfer_functions

    args.views_dir.mkdir(parents=True, exist_ok=True)
    files: List[Path] = []
    jobs = [(d, s, c) for d in args.datasets for s in SHAPES for c in range(args.views)]
    scene: Optional[Scene] = None
    tfs: Dict[str, Dict[str, Any]] = {}
    for dataset, shape, camera in tqdm(jobs, desc="held-out views", unit="view",
                                       disable=args.no_progress):
        if dataset not in tfs:
            tfs = {dataset: held_out_transfer_functions(dataset_histogram(dataset))}
        view = heldout_view(dataset, shape, camera, tfs[dataset][shape], args.size,
                            args.reference_spp)
        path = args.views_dir / f"{dataset}_{shape}_{camera}.exr"
        files.append(path)
        ok, _ = exr_io.verify_view_file(path, view, (args.size, args.size)) \
            if path.is_file() else (False, "missing")
        if ok:
            continue
        if scene is None or scene.dataset != dataset:
            scene = Scene(dataset, (args.size, args.size))
        result = render_view(scene, view, footprint=True)
        exr_io.write_exr(path, result["channels"], {exr_io.VIEW_ATTRIBUTE: json.dumps(view)})
    return files


def trace_frame(scene: Any, meta: Dict[str, Any], seed: int, frames: int, edge_samples: int,
                expected_coverage: bool = False) -> Any:
    """Trace ``frames`` frames of the view ``meta`` from ``seed``; returns the mapper. With
    ``edge_samples`` > 1 each frame is the one the mapper traces for its denoiser (that many
    EdgeSamples on the volume's edge pixels, the Footprint pass), with 1 the plain frame; with
    ``expected_coverage`` the mapper's ExpectedCoverage."""
    edges = edge_samples > 1
    mapper = scene.set_view(meta, seed=seed, max_frames=frames, footprint=edges)
    mapper.GetExpertOptions().SetEdgeSamples(edge_samples)
    mapper.GetExpertOptions().SetComputeEdgeSamples(edges)
    mapper.GetExpertOptions().SetExpectedCoverage(expected_coverage)
    if scene.render(frames) != frames:
        raise RuntimeError(f"{meta['dataset']}: {frames} frames did not accumulate")
    return mapper


def edge_frame(scene: Any, meta: Dict[str, Any], stored: Dict[str, np.ndarray],
               edge_samples: int) -> Dict[str, np.ndarray]:
    """The view's 1-spp frame as the mapper traces it for its denoiser: the stored passes with
    ``edge_samples`` EdgeSamples on the volume's edge pixels (the same samples elsewhere,
    checked bit for bit outside those pixels)."""
    mapper = trace_frame(scene, meta, meta["input_seed"], 1, edge_samples)
    passes = {name: scene.get_pass(name).reshape(stored[name].shape) for name in stored}
    changed = np.zeros(passes["Radiance"].shape[:2], bool)
    for name, image in passes.items():
        changed |= np.any((image != stored[name]).reshape(changed.shape + (-1,)), axis=-1)
    if changed.mean() > mapper.GetStatistics().GetLastEdgeFraction() + 1e-9:
        raise RuntimeError(f"{meta['dataset']} {meta['heldout']}: the frame differs from the "
                           "stored 1-spp passes outside its edge pixels (render it again)")
    return passes


def evaluate(files: Sequence[Path], models: Sequence[Path],
             edge_samples: int = 1) -> List[Dict[str, Any]]:
    """One row per (view, method): PSNR, SSIM. The denoisers get the 1-spp frame with
    ``edge_samples`` EdgeSamples (> 1: traced again, :func:`edge_frame`); "noisy 1 spp" is
    the plain frame."""
    from pathtracedvolume.metrics import quality

    from .compare import oidn_fast
    from .evaluate import cpp_denoise
    from .scene import Scene

    rows: List[Dict[str, Any]] = []
    scene: Optional[Scene] = None
    for path in files:
        view = exr_io.read_view(path)
        meta = view["view"]
        plain = view["inputs"][1]
        passes = plain
        if edge_samples > 1:
            if scene is None or scene.dataset != meta["dataset"]:
                scene = Scene(meta["dataset"], tuple(meta["size"]))
            passes = edge_frame(scene, meta, plain, edge_samples)
        images = {"noisy 1 spp": plain["Radiance"]}
        for model in models:
            images[model.stem] = cpp_denoise(model, passes, sorted(passes), threads=2)["output"]
        images["OIDN fast"] = oidn_fast(passes)
        images["16 spp"] = view["spp16"]
        for method, image in images.items():
            p, s = quality(view["reference"], image)
            rows.append({"dataset": meta["dataset"], "shape": meta["heldout"],
                         "camera": meta["index"], "method": method, "psnr": p, "ssim": s})
        rows.append({"dataset": meta["dataset"], "shape": meta["heldout"],
                     "camera": meta["index"], "method": "reference half",
                     "psnr": quality(view["reference"], view["reference_half"])[0],
                     "ssim": float("nan")})
    return rows


def mean(rows: Sequence[Dict[str, Any]], key: str = "psnr", **match: Any) -> float:
    values = [r[key] for r in rows if all(r[k] == v for k, v in match.items())]
    return float(np.mean(values)) if values else float("nan")


def report(rows: Sequence[Dict[str, Any]], models: Sequence[Path], args: argparse.Namespace,
           command: str) -> str:
    ours = models[0].stem
    methods = ["noisy 1 spp", *[m.stem for m in models], "OIDN fast", "16 spp"]
    lines = [f"# Held-out transfer functions: {ours} against OIDN RT fast\n",
             f"Command: `{command}`. {args.size}² views, {args.views} camera(s) per (shape, "
             f"dataset), references {args.reference_spp} spp of an independent seed "
             f"(PSNR of its first half against it: {mean(rows, method='reference half'):.1f} dB "
             "mean). PSNR (dB) / SSIM of 1-spp inputs denoised (both denoisers get the "
             f"frame the mapper denoises: EdgeSamples {args.edge_samples} on the volume's edge "
             "pixels; 'noisy 1 spp' is the plain frame), tone-mapped "
             "`clip(max(0, x)^(1/2.2), 0, 1)`, scikit-image, data_range 1. The shapes "
             "(`ptv_training/transfer.py`): *translucent*, one ramp over the occupied range with "
             "opacity at most 0.04; *smooth*, two Gaussian bumps; *narrow*, two bands 0.3 % of "
             "the range wide. None of them is a shape the training generator draws.\n"]
    for shape in SHAPES:
        lines.append(f"\n## {shape}\n")
        lines.append("| dataset | " + " | ".join(methods) + f" | {ours} − OIDN fast |")
        lines.append("|---|" + "---|" * (len(methods) + 1))
        for d in args.datasets:
            cells = [f"{mean(rows, dataset=d, shape=shape, method=m):.2f} / "
                     f"{mean(rows, 'ssim', dataset=d, shape=shape, method=m):.3f}"
                     for m in methods]
            diff = (mean(rows, dataset=d, shape=shape, method=ours)
                    - mean(rows, dataset=d, shape=shape, method="OIDN fast"))
            lines.append(f"| {d} | " + " | ".join(cells) + f" | {diff:+.2f} |")
        cells = [f"{mean(rows, shape=shape, method=m):.2f}" for m in methods]
        diff = mean(rows, shape=shape, method=ours) - mean(rows, shape=shape, method="OIDN fast")
        lines.append("| **mean** | " + " | ".join(cells) + f" | **{diff:+.2f}** |")
    lines.append("\n## Verdict (target: ours ≥ OIDN fast − 0.3 dB on each shape, mean over "
                 "datasets)\n")
    for shape in SHAPES:
        diff = mean(rows, shape=shape, method=ours) - mean(rows, shape=shape, method="OIDN fast")
        worst = min(args.datasets, key=lambda d: mean(rows, dataset=d, shape=shape, method=ours)
                    - mean(rows, dataset=d, shape=shape, method="OIDN fast"))
        wdiff = (mean(rows, dataset=worst, shape=shape, method=ours)
                 - mean(rows, dataset=worst, shape=shape, method="OIDN fast"))
        lines.append(f"- {shape}: {diff:+.2f} dB ({'met' if diff >= TARGET_DB else 'missed'});"
                     f" worst dataset {worst} {wdiff:+.2f} dB.")
    return "\n".join(lines) + "\n"


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    from pathtracedvolume.datasets import dataset_names

    p = argparse.ArgumentParser(prog="python Training/ptv_training/heldout.py",
                                description="Held-out transfer-function table: the denoiser "
                                            "against OIDN RT fast on transfer functions never "
                                            "seen in training.")
    p.add_argument("--model", type=Path, nargs="+",
                   default=[REPO_ROOT / "Data" / "Models" / "guidenet.onnx"],
                   help="ONNX models; the first is 'ours' (default: the shipped model)")
    p.add_argument("--datasets", nargs="+", default=list(dataset_names()),
                   help="datasets (default: all)")
    p.add_argument("--views", type=int, default=1, choices=(1, 2),
                   help="cameras per (shape, dataset) (default 1)")
    p.add_argument("--size", type=int, default=256, help="image size (default 256)")
    p.add_argument("--reference-spp", type=int, default=512,
                   help="reference samples per pixel (default 512)")
    p.add_argument("--views-dir", type=Path,
                   default=REPO_ROOT / ".cache" / "training" / "heldout",
                   help="where the rendered views are kept (default .cache/training/heldout)")
    p.add_argument("--results", type=Path, default=REPO_ROOT / "Training" / "results",
                   help="write heldout_tf.md/.json here (default Training/results)")
    p.add_argument("--edge-samples", type=int, default=0,
                   help="EdgeSamples of the denoisers' frame (0: the mapper's default; 1: "
                        "the plain 1-spp frame)")
    p.add_argument("--no-progress", action="store_true", help="no tqdm progress bar")
    args = p.parse_args(argv)
    if args.edge_samples <= 0:
        from pathtracedvolume import vtkPathTracedVolumeMapper
        args.edge_samples = int(vtkPathTracedVolumeMapper().GetExpertOptions().GetEdgeSamples())
    for model in args.model:
        if not model.is_file():
            p.error(f"--model: {model} does not exist")
    return args


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = parse_args(argv)
    command = "python Training/ptv_training/heldout.py " + " ".join(
        sys.argv[1:] if argv is None else list(map(str, argv)))
    files = ensure_views(args)
    rows = evaluate(files, args.model, args.edge_samples)
    text = report(rows, args.model, args, command)
    args.results.mkdir(parents=True, exist_ok=True)
    write_text(args.results / "heldout_tf.md", text)
    write_text(args.results / "heldout_tf.json",
               json.dumps({"command": command, "models": [str(m) for m in args.model],
                           "size": args.size, "reference_spp": args.reference_spp,
                           "edge_samples": args.edge_samples,
                           "rows": rows}, indent=1) + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
