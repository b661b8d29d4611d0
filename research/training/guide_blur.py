"""CLI (study): where a denoised 1-spp frame's error sits, and whether the guides need their detail.

Two questions about the held-out shapes, where GuideNet stays behind OIDN RT fast:

* **Where the error sits.** The squared error of an image against the reference (tone-mapped)
  splits into a low-frequency part, the error of both images blurred by a Gaussian of
  ``--split-sigma`` pixels, and the rest. A denoiser that leaves noise has a small
  low-frequency share; one that blurs structure or shifts the mean a large one. Reported for
  the run's output and for OIDN RT fast, with the ratio of mean luminances (a bias check).
* **Do the guides need their per-pixel detail?** The model's guides of the chosen levels are
  blurred by a Gaussian before the grid slices with them (``--blur``, one variant per
  argument: ``LEVEL:SIGMA`` pairs, levels 1..3 from the finest). A noisy guide scatters a fog's
  pixels over many range bins of the coarse grid; a blurred one keeps them together, and loses
  what the guide's detail keeps apart.

Every run (``best.pt``) denoises each view's 1-spp passes in torch (``bilateral_grid.denoise``,
the C++ path's numbers to 1e-4) with its own blend weights. Groups: a held-out view's shape,
else the view's dataset (as ``level_probe.py``). Writes ``<out>.md`` and ``<out>.json``
atomically.

Example::

    PYTHONPATH=build/python .venv/bin/python Training/ptv_training/guide_blur.py \\
        --run .cache/training/runs/data2x_s0 --views .cache/training/heldout/*.exr \\
        .cache/training/v2/*_05[01].exr --out research/training/results/guide_blur
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

if __package__ in (None, ""):  # run as a file
    sys.path.append(str(Path(__file__).resolve().parents[1]))
    import ptv_training  # noqa: F401
    __package__ = "ptv_training"

from pathtracedvolume.atomic import write_text  # noqa: E402

from .bilateral_grid import LUMINANCE  # noqa: E402
from .level_probe import group_of, load_run, read_views  # noqa: E402


def parse_variant(text: str) -> Dict[int, float]:
    """``"2:2,3:4"`` -> {1: 2.0, 2: 4.0} (0-based level -> sigma in pixels)."""
    out: Dict[int, float] = {}
    for item in text.split(","):
        level, _, sigma = item.partition(":")
        try:
            index, s = int(level) - 1, float(sigma)
        except ValueError:
            raise argparse.ArgumentTypeError(f"--blur {text!r}: expected LEVEL:SIGMA pairs") \
                from None
        if not 0 <= index <= 2 or not s > 0:
            raise argparse.ArgumentTypeError(
                f"--blur {text!r}: level {index + 1} must be 1..3 and sigma {s} above 0")
        out[index] = s
    return out


def gaussian(image: np.ndarray, sigma: float) -> np.ndarray:
    """Gaussian blur of the first two axes (edges replicated)."""
    from scipy.ndimage import gaussian_filter
    sigmas = (sigma, sigma) + (0,) * (image.ndim - 2)
    return gaussian_filter(image, sigmas, mode="nearest")


def low_share(image: np.ndarray, reference: np.ndarray, sigma: float) -> float:
    """The low-frequency share of the squared error of the tone-mapped images."""
    from pathtracedvolume.metrics import tonemap
    a, b = tonemap(image), tonemap(reference)
    total = float(np.mean((a - b) ** 2))
    low = float(np.mean((gaussian(a, sigma) - gaussian(b, sigma)) ** 2))
    return low / max(total, 1e-12)


def mean_ratio(image: np.ndarray, reference: np.ndarray) -> float:
    """Mean luminance of ``image`` over the reference's."""
    weights = np.asarray(LUMINANCE, np.float32)
    return float((image @ weights).mean() / max((reference @ weights).mean(), 1e-12))


def probe_view(model, ck: Dict[str, Any], passes: Dict[str, np.ndarray], reference: np.ndarray,
               variants: Sequence[Tuple[str, Dict[int, float]]], sigma: float
               ) -> Dict[str, float]:
    import torch

    from pathtracedvolume.metrics import psnr

    from .bilateral_grid import denoise
    from .compare import oidn_fast
    from .data import chw
    from .features import build_features

    levels = [tuple(level) for level in ck["levels"]]
    features = torch.from_numpy(build_features(passes, ck["channels"]))[None]
    radiance = chw(passes["Radiance"])[None]
    albedo = chw(passes["Albedo"])[None] if ck.get("demodulate", True) else None
    row: Dict[str, float] = {}
    with torch.no_grad():
        guides, weights = model.split(model(features))
        guides = (guides * 255.0).numpy()
        for name, blur in variants:
            g = guides.copy()
            for level, s in blur.items():
                g[0, level] = gaussian(g[0, level], s)
            out = denoise(radiance, albedo, torch.from_numpy(g), weights, levels=levels,
                          clamp=ck["clamp"])[0].permute(1, 2, 0).numpy()
            row[name] = psnr(out, reference)
            if name == "model":
                row["model low share"] = low_share(out, reference, sigma)
                row["model mean ratio"] = mean_ratio(out, reference)
    oidn = oidn_fast(passes)
    row["OIDN fast"] = psnr(oidn, reference)
    row["OIDN low share"] = low_share(oidn, reference, sigma)
    row["OIDN mean ratio"] = mean_ratio(oidn, reference)
    return row


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--run", type=Path, nargs="+", required=True,
                   help="training runs (their best.pt)")
    p.add_argument("--views", type=Path, nargs="+", required=True,
                   help="view EXR files (training data or heldout.py's views)")
    p.add_argument("--out", type=Path, required=True, help="results path without suffix")
    p.add_argument("--blur", type=parse_variant, nargs="+",
                   default=[parse_variant(v) for v in ("3:2", "3:4", "3:8", "2:2,3:4",
                                                        "1:1,2:2,3:4")],
                   help="guide blurs, one variant each: LEVEL:SIGMA pairs (default 3:2 3:4 "
                        "3:8 2:2,3:4 1:1,2:2,3:4)")
    p.add_argument("--split-sigma", type=float, default=6.0,
                   help="Gaussian sigma (pixels) of the error's low-frequency part (default 6)")
    p.add_argument("--threads", type=int, default=2, help="torch threads (default 2)")
    a = p.parse_args(argv)
    if not a.split_sigma > 0:
        p.error(f"--split-sigma {a.split_sigma}: must be above 0")
    return a


def main(argv: Optional[Sequence[str]] = None) -> int:
    import torch

    args = parse_args(argv)
    torch.set_num_threads(max(1, args.threads))
    variants = [("model", {})] + [
        (" ".join(f"L{level + 1} σ{s:g}" for level, s in sorted(b.items())), b)
        for b in args.blur]
    views = read_views(args.views)
    rows: List[Dict[str, Any]] = []
    for run in args.run:
        model, ck = load_run(run)
        deepest = max((level for _, blur in variants for level in blur), default=0)
        if deepest >= len(ck["levels"]):
            raise SystemExit(f"--blur level {deepest + 1}: {run.name} has "
                             f"{len(ck['levels'])} levels")
        for path, view in views:
            row = probe_view(model, ck, view["inputs"][1], view["reference"], variants,
                             args.split_sigma)
            rows.append({"run": run.name, "view": path.name, "group": group_of(view["view"]),
                         **row})
    names = [n for n, _ in variants]
    stats = ["model low share", "model mean ratio", "OIDN fast", "OIDN low share",
             "OIDN mean ratio"]
    command = " ".join(sys.argv[1:]) if argv is None else " ".join(map(str, argv))
    lines = ["# Guide blur: where the error sits, and whether the guides need their detail", "",
             f"Command: `python Training/ptv_training/guide_blur.py {command}`. 1-spp inputs "
             "denoised in torch with the model's guides and blend, then with the guides of the "
             "named levels (1 = finest) blurred by a Gaussian of σ pixels; mean PSNR (dB, "
             "tone-mapped, data_range 1) per group. 'low share': the part of the squared error "
             f"left when both images are blurred by a Gaussian of σ = {args.split_sigma:g} "
             "pixels; 'mean ratio': mean luminance over the reference's.", "",
             "| run | group | views | " + " | ".join(names + stats) + " |",
             "|---|---|---|" + "---|" * (len(names) + len(stats))]
    summary: List[Dict[str, Any]] = []
    for run in dict.fromkeys(r["run"] for r in rows):
        for group in dict.fromkeys(r["group"] for r in rows if r["run"] == run):
            sel = [r for r in rows if r["run"] == run and r["group"] == group]
            mean = {k: float(np.mean([r[k] for r in sel])) for k in names + stats}
            summary.append({"run": run, "group": group, "views": len(sel), **mean})
            cells = [f"{mean[k]:.2f}" for k in names] + [
                f"{mean[k]:.2f}" if k == "OIDN fast" else f"{mean[k]:.3f}" for k in stats]
            lines.append(f"| {run} | {group} | {len(sel)} | " + " | ".join(cells) + " |")
    out: Path = args.out
    out.parent.mkdir(parents=True, exist_ok=True)
    write_text(out.with_suffix(".md"), "\n".join(lines) + "\n")
    write_text(out.with_suffix(".json"),
               json.dumps({"command": command, "rows": rows, "summary": summary}, indent=1)
               + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
