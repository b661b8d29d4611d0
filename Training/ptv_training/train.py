"""Train GuideNet through the differentiable bilateral grid on the generated views.

Samples are whole views (``--crop 0``, default: the 128 x 128 views are the paper's patch size)
or random square crops, each with one of the 8 flips/rotations per step; inputs are the 1-, 2-
and 4-spp accumulated passes of every training view (``--spp``). Per step::

    features --GuideNet--> guides (x 255), blend weights --bilateral_grid.denoise--> output
    loss (--loss relmse, default) = mean((output - reference)^2 / (sg(output)^2 + 0.01))
    loss (--loss l1)              = L1(tonemap(output), tonemap(reference))
    loss (--loss tmse)            = mean(((output - reference) * tonemap'(sg(y)))^2),
                                    y = clip(output, 0.01, 1)

with ``tonemap(x) = clip(max(0, x)^(1/2.2), 0, 1)`` and ``sg`` = no gradient. The relative MSE
(Lehtinen et al. 2018, "Noise2Noise", their loss for Monte Carlo renderings) is minimised by the
reference's expectation, so a noisy but unbiased reference (``generate.py``'s 64-spp training
targets) trains as well as a converged one; an L1 loss on tone-mapped images would instead
seek the noisy target's median, which is darker. ``tmse`` is the tone-mapped MSE (what the PSNR
measures) linearised at the output: the weight carries no gradient, so its minimiser is still
the reference's mean, while each pixel's error counts as much as it does after the tone map
(relmse weighs bright pixels the tone map clips, and caps dark ones at 1 / 0.01). Validation
always reports the tone-mapped PSNR against the validation views' converged references.

GuideNet's ``--stride`` s runs the network on s x s average-pooled features and upsamples its
output bilinearly (``guidenet.py``); ``--out-channels`` pads its output for ONNX Runtime.
Adam (``--lr``, default 1e-3: a short run; the paper uses 1e-4 for long ones), halved after
``--lr-patience`` epochs without a better validation PSNR (``--lr-schedule plateau``, default)
or lowered along a cosine to 1 % of ``--lr`` at ``--max-steps`` (``--lr-schedule cosine``,
step by step, so that the last epochs settle instead of jumping around the optimum), gradient
norm clipped to ``--clip-grad``. The last ``--val-per-dataset`` views of each dataset are held out;
after every epoch the validation PSNR (tone-mapped, scikit-image, data_range 1) of every held-out
(view, spp) is logged to ``log.csv``; the best epoch (mean validation PSNR over all held-out
samples) is kept in ``best.pt`` with PNGs of its guides/weights on a validation view.
``last.pt`` is written after every epoch: ``--resume`` continues a run where it stopped (same
order of samples, same wall-clock budget ``--minutes`` counted over all sessions).
``--export`` writes the best model as a guidenet-v1 ONNX file at the end.

Example::

    .venv/bin/python Training/ptv_training/train.py --data .cache/training/v1 \\
        --out .cache/training/runs/h16 --hidden 16 --minutes 20 --export Data/Models/guidenet.onnx
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import sys
import time
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np
import torch

if __package__ in (None, ""):  # run as a file: python Training/ptv_training/train.py
    sys.path.append(str(Path(__file__).resolve().parents[1]))
    import ptv_training  # noqa: F401
    __package__ = "ptv_training"

from pathtracedvolume.atomic import atomic_path, write_text  # noqa: E402
from pathtracedvolume.metrics import GAMMA  # noqa: E402

from .bilateral_grid import denoise  # noqa: E402
from .data import (HISTORY_SPP, Sample, batch, load_samples, psnr,  # noqa: E402
                   split_views, tonemap, tonemap_np)
from .export_onnx import levels_string, parse_levels  # noqa: E402
from .features import resolve_channels  # noqa: E402
from .guidenet import BLENDS, STRIDES, GuideNet, count_parameters  # noqa: E402
from .guidenet import macs_per_pixel as guidenet_macs  # noqa: E402
from .unet import UNet  # noqa: E402
from .unet import macs_per_pixel as unet_macs  # noqa: E402
from .warm_start import ChannelAdapter, Teacher, warm_start  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parents[2]
DEFAULT_DATA = REPO_ROOT / ".cache" / "training" / "v2"
LOG_FIELDS = ["epoch", "steps", "elapsed_s", "train_loss", "val_loss", "val_psnr",
              "val_psnr_1spp", "val_psnr_2spp", "val_psnr_4spp", "noisy_psnr_1spp", "lr", "best",
              "val_psnr_history"]


def macs_per_pixel(model: GuideNet | UNet) -> int:
    return unet_macs(model) if isinstance(model, UNet) else guidenet_macs(model)


def run_model(model: GuideNet | UNet, features: torch.Tensor, radiance: torch.Tensor,
              albedo: torch.Tensor, levels: Sequence, clamp: float, demodulate: bool = True,
              use_levels: Optional[int] = None):
    """(denoised radiance, guides in [0, 255], weights) of a batch; an image-to-image model
    (the U-Net baseline) gives (its output, None, None). ``use_levels`` N: the grid uses only
    the finest N levels (guides 0..N-1, weights 0..N-2), as the C++ does with fewer levels."""
    if isinstance(model, UNet):
        return model(features), None, None
    guides, weights = model.split(model(features))
    guides = guides * 255.0
    n = model.levels if use_levels is None else use_levels
    guides, weights, levels = guides[:, :n], weights[:, :n - 1], list(levels)[:n]
    out = denoise(radiance, albedo if demodulate else None, guides,
                  weights if n > 1 else None,
                  levels=levels, clamp=clamp)
    return out, guides, weights


def load_run(run: Path) -> Tuple[GuideNet, Dict[str, Any]]:
    """(GuideNet in eval mode, checkpoint) of a training run's ``best.pt``."""
    ck = torch.load(run / "best.pt", weights_only=False)
    model = GuideNet(**ck["config"])
    model.load_state_dict(ck["model"])
    model.eval()
    return model, ck


def cosine_rate(base: float, step: int, total: int, floor: float = 0.01) -> float:
    """The learning rate of ``step`` (0-based) of ``total`` on a cosine from ``base`` down to
    ``floor * base`` (``--lr-schedule cosine``)."""
    t = min(max(step / max(total, 1), 0.0), 1.0)
    return base * (floor + (1.0 - floor) * 0.5 * (1.0 + math.cos(math.pi * t)))


#: ``--loss tmse``: the tone map's slope is taken at no less than this radiance (its slope at 0
#: is infinite); below it the weight is that of 0.01, about 31 times that at 1.
TMSE_FLOOR = 0.01


def training_loss(output: torch.Tensor, reference: torch.Tensor, kind: str) -> torch.Tensor:
    """The training loss (module doc): ``"relmse"``, ``"tmse"`` or ``"l1"``."""
    if kind == "tmse":
        y = output.detach().clamp(TMSE_FLOOR, 1.0)
        slope = GAMMA * y ** (GAMMA - 1.0)
        return ((output - reference) * slope).pow(2).mean()
    if kind == "l1":
        return (tonemap(output) - tonemap(reference)).abs().mean()
    if kind == "relmse":
        return ((output - reference) ** 2 / (output.detach() ** 2 + 0.01)).mean()
    raise ValueError(f"unknown loss {kind!r}")


def _atomic_save(obj: Any, path: Path) -> None:
    with atomic_path(path) as tmp:
        torch.save(obj, tmp)


@torch.no_grad()
def evaluate(model: GuideNet, samples: Sequence[Sample], levels, clamp: float,
             demodulate: bool = True) -> Dict[str, Any]:
    """Validation loss and PSNRs (per sample, per spp, per dataset at 1 spp)."""
    model.eval()
    rows = []
    losses = []
    for s in samples:
        f, r, a, ref = batch([s])
        out, _, _ = run_model(model, f, r, a, levels, clamp, demodulate)
        losses.append(float((tonemap(out) - tonemap(ref)).abs().mean()))
        den = out[0].permute(1, 2, 0).numpy()
        rows.append({"name": s.name, "dataset": s.dataset, "spp": s.spp,
                     "psnr": psnr(den, s.reference.permute(1, 2, 0).numpy()),
                     "noisy": psnr(s.radiance.permute(1, 2, 0).numpy(),
                                   s.reference.permute(1, 2, 0).numpy())})
    model.train()
    result: Dict[str, Any] = {"loss": float(np.mean(losses)) if losses else math.nan,
                              "psnr": float(np.mean([r["psnr"] for r in rows])) if rows
                              else math.nan, "rows": rows}
    for spp in sorted({r["spp"] for r in rows}):
        sel = [r for r in rows if r["spp"] == spp]
        result[f"psnr_{spp}spp"] = float(np.mean([r["psnr"] for r in sel]))
        result[f"noisy_{spp}spp"] = float(np.mean([r["noisy"] for r in sel]))
    return result


def save_guide_maps(model: GuideNet, sample: Sample, levels, clamp: float, path: Path,
                    demodulate: bool = True) -> None:
    """One PNG: noisy | denoised | reference (tone-mapped), then each guide / 255 and each blend
    weight (grey), top row of the image up."""
    from skimage.io import imsave

    model.eval()
    with torch.no_grad():
        f, r, a, ref = batch([sample])
        out, guides, weights = run_model(model, f, r, a, levels, clamp, demodulate)
    model.train()

    def rgb(t: torch.Tensor) -> np.ndarray:
        return tonemap_np(t[0].permute(1, 2, 0).numpy())[::-1]

    def grey(t: torch.Tensor) -> np.ndarray:
        g = np.clip(t.numpy()[::-1], 0, 1)
        return np.repeat(g[:, :, None], 3, axis=2)

    top = [rgb(r), rgb(out), rgb(ref)]
    bottom = []  # guides and blend weights (none for an image-to-image model)
    if guides is not None:
        bottom += [grey(guides[0, i] / 255.0) for i in range(guides.shape[1])]
    if weights is not None:
        bottom += [grey(weights[0, i]) for i in range(weights.shape[1])]
    width = max(len(top), len(bottom))
    blank = np.zeros_like(top[0])
    top += [blank] * (width - len(top))
    bottom += [blank] * (width - len(bottom))
    image = np.concatenate([np.concatenate(top, 1), np.concatenate(bottom, 1)], 0)
    with atomic_path(path, suffix=".tmp.png") as tmp:
        imsave(str(tmp), (image * 255 + 0.5).astype(np.uint8), check_contrast=False)


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(prog="python Training/ptv_training/train.py",
                                description="Train GuideNet (neural bilateral grid) on "
                                            "generated views; resumable.")
    p.add_argument("--data", type=Path, default=DEFAULT_DATA,
                   help=f"folder with manifest.json and the views (default: {DEFAULT_DATA})")
    p.add_argument("--extra-data", type=Path, nargs="+", default=[], metavar="DIR",
                   help="more folders of generated views (generate.py --val-views 0): every "
                        "view joins the training split; validation stays --data's")
    p.add_argument("--out", type=Path, required=True,
                   help="run folder (checkpoints, log.csv, guide maps)")
    p.add_argument("--channels", default="VOLUME_FEATURES",
                   help="feature preset or comma-separated channels (default: VOLUME_FEATURES)")
    p.add_argument("--arch", choices=("guidenet", "unet"), default="guidenet",
                   help="guidenet (bilateral grid, default) or unet (the image-to-image baseline "
                        "of Hofmann et al. 2020; ignores --hidden/--kernel/--levels/--stride/"
                        "--out-channels)")
    p.add_argument("--width", type=int, default=16, help="U-Net base width (default 16)")
    p.add_argument("--hidden", type=int, default=16, help="GuideNet hidden channels (default 16)")
    p.add_argument("--kernel", type=int, default=5, help="GuideNet kernel size (default 5)")
    p.add_argument("--kernel2", type=int, default=0,
                   help="kernel size of GuideNet's second conv (default 0 = --kernel)")
    p.add_argument("--levels", type=parse_levels, default=((4, 4), (8, 8), (16, 16)),
                   help="grid levels ss:sr (default 4:4,8:8,16:16)")
    p.add_argument("--context", type=int, default=0, metavar="P",
                   help="GuideNet's coarse context branch: pool the network's input by P, "
                        "conv 3x3 + LeakyReLU + conv 1x1 there, added before the sigmoid "
                        "(ptv_training.guidenet; default 0 = none)")
    p.add_argument("--context-hidden", type=int, default=16,
                   help="hidden channels of the context branch (default 16)")
    p.add_argument("--blend", choices=BLENDS, default="sigmoid",
                   help="GuideNet's blend weights: a sigmoid each, the coarsest level getting "
                        "1 - their sum (default), or a softmax over the levels (needs "
                        "--out-channels >= 2 * levels; guidenet.py)")
    p.add_argument("--stride", type=int, choices=STRIDES, default=1,
                   help="GuideNet guide stride: the network runs on s x s average-pooled "
                        "features, its output is upsampled bilinearly (default 1)")
    p.add_argument("--out-channels", type=int, default=0,
                   help="GuideNet output channels incl. padding, >= 2 * levels - 1 "
                        "(default 0 = 2 * levels - 1)")
    p.add_argument("--no-demodulate", dest="demodulate", action="store_false",
                   help="denoise radiance itself, not radiance / albedo (1-spp volume albedo is "
                        "noisy: re-modulating by it puts noise back)")
    p.add_argument("--loss", choices=("relmse", "tmse", "l1"), default="relmse",
                   help="relmse: relative MSE on linear radiance, right for noisy (Noise2Noise) "
                        "references (default); tmse: MSE weighted by the tone map's slope at "
                        "the output (also unbiased); l1: L1 on tone-mapped images")
    p.add_argument("--clamp", type=float, default=8.0,
                   help="outlier clamp of the grid (default 8, as the C++ default)")
    p.add_argument("--spp", default="1,2,4",
                   help="input spp used for training (default 1,2,4; 0: the view after a "
                        "reprojected history, history.py)")
    p.add_argument("--aux-spp", type=int, default=0, choices=(0, 2, 4),
                   help="study: samples of fewer spp take their auxiliary passes from this "
                        "spp's accumulation (anti-aliased features; the C++ mapper has no such "
                        "input yet; default 0: off)")
    p.add_argument("--edge-samples", type=int, default=0, metavar="K",
                   help="train on the input the mapper denoises with EdgeSamples K: a sample "
                        "of s spp takes its edge pixels (data.with_edge_samples) from the "
                        "view's K*s-spp accumulation where the view has one (default 0: off, "
                        "the plain accumulation; the mapper's default is 2)")
    p.add_argument("--val-per-dataset", type=int, default=3,
                   help="views per dataset held out for validation (default 3)")
    p.add_argument("--exclude", nargs="*", default=[], metavar="DATASET",
                   help="train without these datasets' views (leave-one-out); validation "
                        "still covers every dataset")
    p.add_argument("--max-views", type=int, default=0,
                   help="use at most this many training views (0 = all; for smoke tests)")
    p.add_argument("--batch", type=int, default=4, help="samples per step (default 4)")
    p.add_argument("--crop", type=int, default=0,
                   help="random square crop size (0 = whole views, default)")
    p.add_argument("--lr", type=float, default=1e-3, help="Adam learning rate (default 1e-3)")
    p.add_argument("--level-counts", default="",
                   help="level dropout: each step runs the grid with the finest N levels, N "
                        "drawn uniformly from this comma-separated list (e.g. 1,3), as the C++ "
                        "does with fewer levels, so that the model is trained for each count it "
                        "runs with (the default count on large images is ptv.default_levels); "
                        "default: every level, always")
    p.add_argument("--small-stride", type=int, default=0,
                   help="study: the level-dropout steps that run every level (the denoiser's "
                        "case at or below 256^2 pixels) run GuideNet at this stride instead of "
                        "--stride, the others at --stride; validation and the export use "
                        "--stride (the C++ does not pick a stride by image size yet: measure the "
                        "small-image case with the export's ptv.guide_stride set to this). "
                        "Default 0: off")
    p.add_argument("--lr-schedule", choices=("plateau", "cosine"), default="plateau",
                   help="plateau: halve the rate after --lr-patience epochs without a better "
                        "validation PSNR (default); cosine: lower it along a cosine to 1%% of "
                        "--lr at --max-steps (needs --max-steps)")
    p.add_argument("--lr-patience", type=int, default=4,
                   help="halve the learning rate after this many epochs without a better "
                        "validation PSNR (0 = constant; default 4; floor 1e-5)")
    p.add_argument("--clip-grad", type=float, default=1.0,
                   help="gradient norm clip (0 = off; default 1)")
    p.add_argument("--epochs", type=int, default=10000, help="most epochs (default 10000)")
    p.add_argument("--max-steps", type=int, default=0,
                   help="stop after this many steps in all (0 = no limit)")
    p.add_argument("--minutes", type=float, default=20.0,
                   help="wall-clock training budget over all sessions (default 20)")
    p.add_argument("--seed", type=int, default=0, help="torch/numpy seed (default 0)")
    p.add_argument("--threads", type=int, default=2, help="torch threads (default 2)")
    p.add_argument("--init", type=Path, default=None,
                   help="start from a trained model: a guidenet-v1 ONNX file or a checkpoint "
                        "(same architecture; its channels copied by name, new ones at zero "
                        "weight; warm_start.py)")
    p.add_argument("--adapt", nargs="+", default=[], metavar="CHANNEL",
                   help="with --init: train only these new channels' first-layer weights, the "
                        "first bias compensated so that their neutral value (history: 1) keeps "
                        "the init's output (warm_start.py)")
    p.add_argument("--distill", type=float, default=0.0, metavar="WEIGHT",
                   help="with --init: add WEIGHT x the relative MSE between the output and the "
                        "init model's on each 1-spp sample (keeps its single frames while every "
                        "weight trains; default 0: off)")
    p.add_argument("--resume", action="store_true", help="continue from <out>/last.pt")
    p.add_argument("--export-levels", type=int, default=0,
                   help="ship only the finest N grid levels in --export (default 0: all)")
    p.add_argument("--export-default-levels", type=int, default=0,
                   help="the level count the denoiser runs the --export file with unless told "
                        "otherwise (ptv.default_levels; default 0: every shipped level)")
    p.add_argument("--export", type=Path, default=None,
                   help="write the best model to this .onnx file at the end")
    p.add_argument("--no-progress", action="store_true", help="no tqdm progress bars")
    return p.parse_args(argv)


def main(argv: Optional[Sequence[str]] = None) -> int:
    from tqdm import tqdm

    args = parse_args(argv)
    level_counts = [int(n) for n in args.level_counts.split(",") if n.strip()]
    if any(not 1 <= n <= len(args.levels) for n in level_counts):
        raise SystemExit(f"--level-counts {args.level_counts}: each count must be 1 to "
                         f"{len(args.levels)} (the levels trained)")
    if args.small_stride and not (len(args.levels) in level_counts and min(level_counts) <
                                  len(args.levels) and args.small_stride in (1, 2, 4, 8)):
        raise SystemExit(f"--small-stride {args.small_stride}: needs a stride of 1, 2, 4 or 8 and "
                         f"--level-counts with {len(args.levels)} (every level) and a smaller "
                         "count")
    if args.small_stride and (args.distill or args.arch != "guidenet"):
        raise SystemExit("--small-stride is for a GuideNet trained without --distill")
    if args.lr_schedule == "cosine" and args.max_steps <= 0:
        raise SystemExit("--lr-schedule cosine needs --max-steps")
    torch.set_num_threads(max(1, args.threads))
    channels = resolve_channels(args.channels)
    spps = [int(s) for s in args.spp.split(",") if s.strip()]
    out: Path = args.out
    out.mkdir(parents=True, exist_ok=True)
    command = " ".join(sys.argv if argv is None else ["train.py", *map(str, argv)])

    def without_excluded(files: List[Path], folder: Path, views: dict) -> List[Path]:
        dataset_of = {folder / r["file"]: r["view"]["dataset"] for r in views["views"]}
        return [f for f in files if dataset_of[f] not in args.exclude]

    train_files, val_files, manifest = split_views(args.data, args.val_per_dataset)
    if args.exclude:
        unknown = set(args.exclude) - {r["view"]["dataset"] for r in manifest["views"]}
        if unknown:
            raise SystemExit(f"--exclude: no views of {sorted(unknown)} in {args.data}")
        train_files = without_excluded(train_files, args.data, manifest)
    if args.max_views:
        train_files = train_files[:args.max_views]
    for extra in args.extra_data:
        more, more_val, more_manifest = split_views(extra, 0)
        if more_val:
            raise SystemExit(f"--extra-data {extra}: has validation views; generate it with "
                             "--val-views 0")
        train_files += without_excluded(more, extra, more_manifest)
    progress = not args.no_progress
    train = load_samples(train_files, channels, spps, progress=progress, aux_spp=args.aux_spp,
                         edge_samples=args.edge_samples)
    val = load_samples(val_files, channels, spps, progress=progress, aux_spp=args.aux_spp,
                       edge_samples=args.edge_samples)
    if not train:
        raise SystemExit("no training views")

    torch.manual_seed(args.seed)
    if args.arch == "unet":
        model: GuideNet | UNet = UNet(len(channels), width=args.width)
    else:
        model = GuideNet(len(channels), hidden=args.hidden, kernel=args.kernel,
                         levels=len(args.levels), stride=args.stride,
                         out_channels=args.out_channels or None,
                         kernel2=args.kernel2 or None, context=args.context,
                         context_hidden=args.context_hidden, blend=args.blend)
    adapter: Optional[ChannelAdapter] = None
    if args.init is not None:
        if not isinstance(model, GuideNet):
            raise SystemExit("--init needs --arch guidenet")
        try:
            new = warm_start(model, channels, args.init)
            if args.adapt:
                adapter = ChannelAdapter(model, channels, args.adapt)
        except (ValueError, FileNotFoundError) as error:
            raise SystemExit(str(error))
        print(f"initialised from {args.init} (new channels at zero weight: {new or 'none'})"
              + (f"; training only {args.adapt}'s first-layer weights" if adapter else ""))
    elif args.adapt or args.distill:
        raise SystemExit("--adapt and --distill need --init")
    teacher = Teacher(channels, args.init) if args.distill > 0 else None
    trainable = adapter.parameters() if adapter else list(model.parameters())
    optimizer = torch.optim.Adam(trainable, lr=args.lr)
    scheduler = torch.optim.lr_scheduler.ReduceLROnPlateau(
        optimizer, mode="max", factor=0.5, patience=max(args.lr_patience, 1), threshold=0.01,
        threshold_mode="abs", min_lr=1e-5)
    state = {"epoch": 0, "steps": 0, "elapsed": 0.0, "best_psnr": -math.inf, "best_epoch": 0,
             "log": []}
    last_path, best_path = out / "last.pt", out / "best.pt"
    if args.resume and last_path.is_file():
        ck = torch.load(last_path)
        stored = dict(ck["config"])
        if isinstance(model, GuideNet):  # written before stride/out_channels: 1, 2L - 1
            stored.setdefault("stride", 1)
            stored.setdefault("out_channels", 2 * stored["levels"] - 1)
        if stored != model.config() or ck["channels"] != channels:
            raise SystemExit(f"{last_path} is a different model ({ck['config']}, "
                             f"{ck['channels']})")
        model.load_state_dict(ck["model"])
        optimizer.load_state_dict(ck["optimizer"])
        if "scheduler" in ck:
            scheduler.load_state_dict(ck["scheduler"])
        state = ck["state"]
        print(f"resumed at epoch {state['epoch']} ({state['elapsed']:.0f} s used)")
    elif last_path.exists() and not args.resume:
        raise SystemExit(f"{last_path} exists: pass --resume, or use another --out")

    info = {"command": command, "channels": channels, "config": model.config(),
            "levels": levels_string(args.levels), "parameters": count_parameters(model),
            "macs_per_pixel": macs_per_pixel(model), "train_views": [p.name for p in train_files],
            "val_views": [p.name for p in val_files], "spp": spps,
            "data": str(args.data), "extra_data": [str(d) for d in args.extra_data],
            "data_format": manifest.get("format"),
            "args": {k: (str(v) if isinstance(v, Path) else
                         [str(x) for x in v] if k == "extra_data" else v)
                     for k, v in vars(args).items()}}
    write_text(out / "run.json", json.dumps(info, indent=1) + "\n")
    print(f"{type(model).__name__} {model.config()}: {count_parameters(model)} parameters, "
          f"{macs_per_pixel(model)} MAC/pixel; {len(train)} training samples "
          f"({len(train_files)} views x {len(spps)} spp), {len(val)} validation samples")

    log_path = out / "log.csv"
    if not (args.resume and log_path.is_file()):
        write_text(log_path, ",".join(LOG_FIELDS) + "\n")
    budget = args.minutes * 60.0
    guide_sample = next((s for s in val if s.spp == 1), val[0] if val else train[0])

    while state["epoch"] < args.epochs and state["elapsed"] < budget and \
            not (args.max_steps and state["steps"] >= args.max_steps):
        epoch = state["epoch"] + 1
        rng = np.random.default_rng([args.seed, epoch])  # the same order after a resume
        torch.manual_seed(args.seed * 100003 + epoch)
        order = rng.permutation(len(train))
        transforms = rng.integers(0, 8, len(train))
        t_epoch = time.perf_counter()
        losses: List[float] = []
        steps = range(0, len(order), args.batch)
        bar = tqdm(steps, desc=f"epoch {epoch}", unit="step", leave=False, disable=not progress)
        for start in bar:
            idx = order[start:start + args.batch]
            f, r, a, ref = batch([train[i] for i in idx], [int(transforms[i]) for i in idx])
            if args.crop and args.crop < f.shape[-1]:
                y, x = (int(v) for v in rng.integers(0, f.shape[-1] - args.crop + 1, 2))
                sl = (Ellipsis, slice(y, y + args.crop), slice(x, x + args.crop))
                f, r, a, ref = f[sl], r[sl], a[sl], ref[sl]
            if args.lr_schedule == "cosine":
                for group in optimizer.param_groups:
                    group["lr"] = cosine_rate(args.lr, state["steps"], args.max_steps)
            use_levels = None
            if level_counts and isinstance(model, GuideNet):
                use_levels = level_counts[int(rng.integers(0, len(level_counts)))]
            trained_stride = model.stride if args.small_stride else None  # a GuideNet (checked)
            if args.small_stride and use_levels == len(args.levels):
                model.stride = args.small_stride  # the small-image case, for this step only
            try:
                result, _, _ = run_model(model, f, r, a, args.levels, args.clamp,
                                         args.demodulate, use_levels)
            finally:
                if trained_stride is not None:
                    model.stride = trained_stride
            loss = training_loss(result, ref, args.loss)
            one = torch.tensor([train[i].spp == 1 for i in idx]) if teacher else None
            if one is not None and bool(one.any()):  # hold the 1-spp samples to the init
                with torch.no_grad():
                    target, _, _ = run_model(teacher.model, f[one][:, teacher.columns], r[one],
                                             a[one], args.levels, args.clamp, args.demodulate,
                                             use_levels)
                loss = loss + args.distill * training_loss(result[one], target, "relmse")
            optimizer.zero_grad(set_to_none=True)
            loss.backward()
            if args.clip_grad > 0:
                torch.nn.utils.clip_grad_norm_(model.parameters(), args.clip_grad)
            optimizer.step()
            if adapter:
                adapter.project()
            losses.append(float(loss))
            state["steps"] += 1
            bar.set_postfix(loss=f"{np.mean(losses):.4f}")
            if args.max_steps and state["steps"] >= args.max_steps:
                break
        # Without validation views the criterion is the (negated) training loss.
        ev = evaluate(model, val, args.levels, args.clamp, args.demodulate) if val else \
            {"loss": math.nan, "psnr": -float(np.mean(losses))}
        state["elapsed"] += time.perf_counter() - t_epoch
        state["epoch"] = epoch
        is_best = ev["psnr"] > state["best_psnr"]
        row = {"epoch": epoch, "steps": state["steps"], "elapsed_s": round(state["elapsed"], 1),
               "train_loss": round(float(np.mean(losses)), 6),
               "val_loss": round(ev["loss"], 6), "val_psnr": round(ev["psnr"], 4),
               "val_psnr_1spp": round(ev.get("psnr_1spp", math.nan), 4),
               "val_psnr_2spp": round(ev.get("psnr_2spp", math.nan), 4),
               "val_psnr_4spp": round(ev.get("psnr_4spp", math.nan), 4),
               "val_psnr_history": round(ev.get(f"psnr_{HISTORY_SPP}spp", math.nan), 4),
               "noisy_psnr_1spp": round(ev.get("noisy_1spp", math.nan), 4),
               "lr": optimizer.param_groups[0]["lr"], "best": int(is_best)}
        if args.lr_patience > 0 and args.lr_schedule == "plateau":
            scheduler.step(ev["psnr"])
        state["log"].append(row)
        with open(log_path, "a", newline="") as fh:
            csv.DictWriter(fh, LOG_FIELDS).writerow(row)
        checkpoint = {"model": model.state_dict(), "optimizer": optimizer.state_dict(),
                      "scheduler": scheduler.state_dict(),
                      "config": model.config(), "channels": channels,
                      "levels": [list(l) for l in args.levels], "clamp": args.clamp,
                      "demodulate": args.demodulate,
                      "state": state, "validation": {k: v for k, v in ev.items() if k != "rows"}}
        if is_best:
            state["best_psnr"], state["best_epoch"] = ev["psnr"], epoch
            checkpoint["state"] = state
            checkpoint["validation_rows"] = ev.get("rows", [])
            _atomic_save(checkpoint, best_path)
            save_guide_maps(model, guide_sample, args.levels, args.clamp,
                            out / "guides_best.png", args.demodulate)
        _atomic_save(checkpoint, last_path)
        tqdm.write(f"epoch {epoch:4d}  {state['elapsed']:7.1f} s  loss {row['train_loss']:.4f}"
                   f"  val {row['val_psnr']:.2f} dB (1spp {row['val_psnr_1spp']:.2f}, noisy "
                   f"{row['noisy_psnr_1spp']:.2f}){'  *' if is_best else ''}")

    best = torch.load(best_path)
    model.load_state_dict(best["model"])
    save_guide_maps(model, guide_sample, args.levels, args.clamp, out / "guides_final_best.png",
                    args.demodulate)
    print(f"best epoch {best['state']['best_epoch']}: val PSNR {best['state']['best_psnr']:.3f} dB"
          f" after {state['epoch']} epochs, {state['steps']} steps, {state['elapsed']:.0f} s")
    if args.export is not None:
        from .export_onnx import export, export_image_model
        extra = {"ptv.weights": f"trained: {out.name}, epoch {best['state']['best_epoch']}, "
                                f"val PSNR {best['state']['best_psnr']:.2f} dB",
                 "ptv.training_command": command}
        if isinstance(model, UNet):
            path = export_image_model(model, args.export, channels, extra_metadata=extra)
        else:
            extra["ptv.demodulate"] = "1" if args.demodulate else "0"
            path = export(model, args.export, channels, args.levels, extra_metadata=extra,
                          use_levels=args.export_levels or None,
                          default_levels=args.export_default_levels or None)
        print(f"exported {path} ({path.stat().st_size} bytes)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
