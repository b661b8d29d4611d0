"""CLI: how a trained GuideNet blends its grid levels, against each level alone.

The denoised image is ``s1 w1 + s2 w2 + s3 (1 - w1 - w2)`` (``bilateral_grid.blend``): the slices
of the finest, middle and coarsest level, weighted by GuideNet's per-pixel blend weights. For
every view given (training-view or held-out EXR files, ``exr_io.read_view``) and every run
(``best.pt``), this denoises the 1-spp passes (``--spp``: also the 2- or 4-spp ones) in torch
(``train.run_model``, the C++ path's numbers to 1e-4) four ways: with the model's blend, and
with the weights forced to take one level alone (the model's own guides). It also reports the
blend weights the model chose on the pixels the view covers (reference above 0.02 in any
channel): their medians, and the coarsest level's share ``1 - w1 - w2``. A model with the
``history`` channel sees the spp of a still accumulation (``data.sample_passes``).

The question it answers: does the blend pick the level the view needs? Where one level alone
beats the blend by a wide margin, the weights are what loses, not the grid. Groups: the dataset
of a training view, the shape of a held-out view (``heldout.py``). Writes ``<out>.md`` and
``<out>.json`` atomically.

Example (the held-out views and the validation views of the training data)::

    PYTHONPATH=build/python .venv/bin/python Training/ptv_training/level_probe.py \\
        --run .cache/training/runs/ship_v4 --views .cache/training/heldout/*.exr \\
        .cache/training/v2/*_05[01].exr --out research/training/results/level_probe
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

from . import exr_io  # noqa: E402
from .data import sample_passes  # noqa: E402

METHODS = ("blend", "level 1 alone", "level 2 alone", "level 3 alone")
COVERED = 0.02  # reference value above which a pixel counts as covered


def probe_view(model, ck: Dict[str, Any], passes: Dict[str, np.ndarray],
               reference: np.ndarray) -> Dict[str, float]:
    """PSNR of the blend and of each level alone, and the blend weights on covered pixels."""
    import torch

    from pathtracedvolume.metrics import psnr

    from .bilateral_grid import denoise
    from .data import chw
    from .features import build_features

    levels = [tuple(level) for level in ck["levels"]]
    if len(levels) != 3:
        raise SystemExit(f"level_probe needs a 3-level model, this one has {len(levels)}")
    demodulate = ck.get("demodulate", True)
    features = torch.from_numpy(build_features(passes, ck["channels"]))[None]
    radiance = chw(passes["Radiance"])[None]
    albedo = chw(passes["Albedo"])[None] if demodulate else None
    with torch.no_grad():
        guides, weights = model.split(model(features))
        guides = guides * 255.0
        forced = {"blend": weights}
        for k in range(3):
            w = torch.zeros_like(weights)
            if k < 2:
                w[:, k] = 1.0
            forced[f"level {k + 1} alone"] = w
        row: Dict[str, float] = {}
        for name, w in forced.items():
            out = denoise(radiance, albedo, guides, w, levels=levels, clamp=ck["clamp"])
            row[name] = psnr(out[0].permute(1, 2, 0).numpy(), reference)
    covered = reference.max(axis=2) > COVERED
    w = weights[0].clamp(0, 1).numpy()
    if covered.any():
        row["w1"] = float(np.median(w[0][covered]))
        row["w2"] = float(np.median(w[1][covered]))
        row["coarse"] = float(np.median((1.0 - w[0] - w[1])[covered]))
    else:
        row["w1"] = row["w2"] = row["coarse"] = float("nan")
    return row


def load_run(run: Path) -> Tuple[Any, Dict[str, Any]]:
    """(GuideNet in eval mode, checkpoint) of a training run's ``best.pt``."""
    import torch

    from .guidenet import GuideNet

    ck = torch.load(run / "best.pt", weights_only=False)
    model = GuideNet(**ck["config"])
    model.load_state_dict(ck["model"])
    model.eval()
    return model, ck


def read_views(paths: Sequence[Path]) -> List[Tuple[Path, Dict[str, Any]]]:
    """(path, ``exr_io.read_view``) of each view file; exits naming any file that is missing."""
    missing = [str(p) for p in paths if not p.is_file()]
    if missing:
        raise SystemExit(f"no such view file: {', '.join(missing)}")
    return [(p, exr_io.read_view(p)) for p in paths]


def group_of(view: Dict[str, Any]) -> str:
    """A held-out view's shape, else the view's dataset."""
    return f"held-out {view['heldout']}" if "heldout" in view else str(view["dataset"])


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--run", type=Path, nargs="+", required=True,
                   help="training runs (their best.pt)")
    p.add_argument("--views", type=Path, nargs="+", required=True,
                   help="view EXR files (training data or heldout.py's views)")
    p.add_argument("--out", type=Path, required=True, help="results path without suffix")
    p.add_argument("--spp", type=int, nargs="+", default=[1], choices=(1, 2, 4),
                   help="input accumulations to probe, each a group of its own (default 1)")
    p.add_argument("--threads", type=int, default=2, help="torch threads (default 2)")
    return p.parse_args(argv)


def main(argv: Optional[Sequence[str]] = None) -> int:
    import torch

    args = parse_args(argv)
    torch.set_num_threads(max(1, args.threads))
    views = read_views(args.views)
    rows: List[Dict[str, Any]] = []
    for run in args.run:
        model, ck = load_run(run)
        for path, view in views:
            for spp in args.spp:
                row = probe_view(model, ck, sample_passes(view, path, spp), view["reference"])
                rows.append({"run": run.name, "view": path.name, "spp": spp,
                             "group": group_of(view["view"]), **row})

    lines = ["# Level probe: the learned blend against each grid level alone", "",
             f"Command: `python Training/ptv_training/level_probe.py "
             f"{' '.join(sys.argv[1:]) if argv is None else ' '.join(map(str, argv))}`. "
             "1-spp (or --spp) inputs denoised in torch with the model's blend weights and with "
             "the weights forced to one level; mean PSNR (dB, tone-mapped, data_range 1) per "
             "group; the blend weights' medians on the covered pixels (reference > 0.02), "
             "'coarse' = 1 - w1 - w2.", "",
             "| run | group | spp | views | " + " | ".join(METHODS) +
             " | best level − blend | w1 | w2 | coarse |",
             "|---|---|---|---|" + "---|" * (len(METHODS) + 4)]
    summary: List[Dict[str, Any]] = []
    for run in dict.fromkeys(r["run"] for r in rows):
        for group, spp in sorted({(r["group"], r["spp"]) for r in rows if r["run"] == run}):
            sel = [r for r in rows
                   if r["run"] == run and r["group"] == group and r["spp"] == spp]
            mean = {k: float(np.mean([r[k] for r in sel]))
                    for k in (*METHODS, "w1", "w2", "coarse")}
            best = max(mean[m] for m in METHODS[1:])
            summary.append({"run": run, "group": group, "spp": spp, "views": len(sel), **mean,
                            "best_level_minus_blend": best - mean["blend"]})
            lines.append(f"| {run} | {group} | {spp} | {len(sel)} | " +
                         " | ".join(f"{mean[m]:.2f}" for m in METHODS) +
                         f" | {best - mean['blend']:+.2f} | {mean['w1']:.2f} | "
                         f"{mean['w2']:.2f} | {mean['coarse']:+.2f} |")
    out: Path = args.out
    out.parent.mkdir(parents=True, exist_ok=True)
    write_text(out.with_suffix(".md"), "\n".join(lines) + "\n")
    write_text(out.with_suffix(".json"),
               json.dumps({"rows": rows, "summary": summary}, indent=1) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
