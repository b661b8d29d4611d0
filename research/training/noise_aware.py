"""CLI: does a guide told how noisy its depth is denoise the narrow bands better?

On the held-out narrow bands the 1-spp depth, albedo and normal are as noisy as the colour
(``feature_noise.py``), and the guide follows them. The edge rule gives two samples to most of
those pixels, whose disagreement measures that noise per pixel. The study channel
``depth_spread`` (``features.py``; the pass ``DepthSpread`` of ``data.with_edge_samples``)
gives it to the network; a run trained with it (``train.py --channels
PAPER_10,coverage,depth_spread --edge-samples 2``) is compared here with runs of the same
recipe without it.

Every run given (``--run``: a training run folder, its ``best.pt``) denoises in torch (the
pipeline that ``evaluate.py`` checks against the C++ denoiser to 1e-4), with its finest level
at this size as the shipped model does (``--export-default-levels 1``), the 1-spp frame with
two samples on its edge pixels built from each view's stored 1- and 2-spp accumulations
(``data.sample_passes``: independent jitters, not the mapper's lattice, so ours is up to 0.5 dB
below ``heldout.py``'s figure on the narrow bands); OIDN RT fast denoises the same frame.
Views: the held-out transfer functions (``--views-dir``, ``heldout.py``'s) and the validation
views of the first run (its ``run.json``). ``--masked-blur`` also tries, on the last run, fixed
filters in place of a trained input: the box mean (3x3 or 5x5) of the network's input
features or of its guides on the pixels whose ``depth_spread`` is above 0.02 or 0.1. Reported:
PSNR against each view's reference (tone-mapped, data_range 1), mean per group, and the share
of covered pixels whose ``depth_spread`` is above 0.05. Writes ``<results>/noise_aware.md``
and ``.json`` atomically; needs no rendering.

    PYTHONPATH=build/python .venv/bin/python Training/ptv_training/noise_aware.py \
        --run .cache/training/runs/spread_s1 .cache/training/runs/ship_v6
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np
from tqdm import tqdm

if __package__ in (None, ""):  # run as a file
    sys.path.append(str(Path(__file__).resolve().parents[1]))
    import ptv_training  # noqa: F401
    __package__ = "ptv_training"

from . import exr_io  # noqa: E402
from .heldout import SHAPES  # noqa: E402
from .tables import REPO_ROOT, row, shown, write_results  # noqa: E402

EDGE_SAMPLES = 2
OIDN = "OIDN fast"
#: The table's share of covered pixels with a depth_spread above this.
SPREAD_SHOWN = 0.05
#: ``--masked-blur``: (where, tau, radius) of the fixed filters tried on the last run.
BLURS = tuple((where, tau, radius) for where in ("features", "guides")
              for radius in (1, 2) for tau in (0.02, 0.1))


def blur_name(run: str, blur: Tuple[str, float, int]) -> str:
    """The method name of ``run`` with a masked blur (:func:`denoise`)."""
    where, tau, radius = blur
    return f"{run}, {where} box {2 * radius + 1}, spread > {tau:g}"


def load_run(run: Path) -> Dict[str, Any]:
    """A run's best checkpoint as ``{"model", "ck"}`` (``level_probe.load_run``)."""
    from .level_probe import load_run as load

    model, ck = load(run)
    return {"model": model, "ck": ck}


def _box(x: Any, radius: int) -> Any:
    """The (2 radius + 1)^2 box mean of ``(N, C, H, W)`` (edges replicated)."""
    import torch.nn.functional as F

    k = 2 * radius + 1
    return F.avg_pool2d(F.pad(x, (radius,) * 4, mode="replicate"), k, stride=1)


def denoise(run: Dict[str, Any], passes: Dict[str, np.ndarray],
            blur: Optional[Tuple[str, float, int]] = None,
            spread: Optional[np.ndarray] = None) -> np.ndarray:
    """The run's torch denoise of ``passes`` with its finest level's default (as shipped:
    ``evaluate.torch_denoise``). ``blur`` (where, tau, radius): a fixed filter instead of a
    trained input, the box mean of the ``"features"`` (network inputs) or of the
    ``"guides"`` replacing them on the pixels whose ``depth_spread`` exceeds tau (``spread``:
    that channel ``(H, W)`` when already built)."""
    import torch

    from .bilateral_grid import automatic_levels
    from .bilateral_grid import denoise as grid_denoise
    from .data import chw
    from .evaluate import torch_denoise
    from .features import build_features

    ck, model = run["ck"], run["model"]
    levels = [tuple(v) for v in ck["levels"]]
    demodulate = ck.get("demodulate", True)
    if blur is None:
        return torch_denoise(model, ck["channels"], levels, ck["clamp"], passes, demodulate,
                             None, 1)
    where, tau, radius = blur
    if spread is None:
        spread = build_features(passes, ["depth_spread"])[0]
    height, width = passes["Radiance"].shape[:2]
    count = automatic_levels(levels[:model.levels], 1, height, width)
    with torch.no_grad():
        mask = torch.from_numpy((spread > tau).astype(np.float32))[None, None]
        f = torch.from_numpy(build_features(passes, ck["channels"]))[None]
        if where == "features":
            f = f * (1 - mask) + _box(f, radius) * mask
        guides, weights = model.split(model(f))  # as train.run_model, with the guides blurred
        guides = guides[:, :count] * 255.0
        if where == "guides":
            guides = guides * (1 - mask) + _box(guides, radius) * mask
        out = grid_denoise(chw(passes["Radiance"])[None],
                           chw(passes["Albedo"])[None] if demodulate else None,
                           guides, weights[:, :count - 1] if count > 1 else None,
                           levels=levels[:count], clamp=ck["clamp"])
    return out[0].permute(1, 2, 0).numpy()


def evaluate(files: Sequence[Path], runs: Dict[str, Dict[str, Any]], group_of,
             progress: bool = True, blurs: Sequence[Tuple[str, float, int]] = ()
             ) -> List[Dict[str, Any]]:
    """One row per (view, method): PSNR of each run and of OIDN fast on the edge frame, and of
    the last run with each of ``blurs`` (:func:`denoise`)."""
    from pathtracedvolume.metrics import quality

    from .compare import oidn_fast
    from .data import sample_passes
    from .features import build_features

    last = list(runs)[-1]
    rows: List[Dict[str, Any]] = []
    for path in tqdm(list(files), desc="views", unit="view", disable=not progress):
        view = exr_io.read_view(path)
        passes = sample_passes(view, path, 1, EDGE_SAMPLES)
        spread = build_features(passes, ["depth_spread"])[0]
        images = {name: denoise(run, passes) for name, run in runs.items()}
        for blur in blurs:
            images[blur_name(last, blur)] = denoise(runs[last], passes, blur, spread)
        images[OIDN] = oidn_fast(passes)
        covered = view["inputs"][4]["Alpha"][..., 0] > 0.5  # as feature_noise.py
        share = float((spread > SPREAD_SHOWN)[covered].mean()) if covered.any() else np.nan
        for method, image in images.items():
            rows.append({"view": path.stem, "dataset": view["view"]["dataset"],
                         "group": group_of(view["view"]), "method": method,
                         "psnr": quality(view["reference"], image)[0], "spread_share": share})
    return rows


def table(rows: Sequence[Dict[str, Any]], methods: Sequence[str]) -> List[str]:
    """Markdown: per method (a row) and group (a column), the mean PSNR and its difference to
    OIDN fast's; first the groups' view counts and shares of noisy depth."""
    groups = [g for g in (*SHAPES, "validation") if any(r["group"] == g for r in rows)]

    def mean(group: str, method: str, key: str = "psnr") -> float:
        return float(np.nanmean([r[key] for r in rows
                                 if r["group"] == group and r["method"] == method]))

    def views(group: str) -> int:
        return len({r["view"] for r in rows if r["group"] == group})

    lines = [row("method", *groups), "|---|" + "---|" * len(groups),
             row("views", *(views(g) for g in groups)),
             row(f"covered pixels with depth_spread > {SPREAD_SHOWN:g}",
                  *(f"{mean(g, OIDN, 'spread_share'):.1%}" for g in groups))]
    for m in methods:
        lines.append(row(m, *(f"{mean(g, m):.2f}" + ("" if m == OIDN else
                                                       f" ({mean(g, m) - mean(g, OIDN):+.2f})")
                               for g in groups)))
    return lines


def main(argv: Optional[Sequence[str]] = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--run", type=Path, nargs="+", required=True,
                   help="training run folders (best.pt, run.json); the first one's "
                        "validation views are evaluated too")
    p.add_argument("--views-dir", type=Path, default=REPO_ROOT / ".cache" / "training" / "heldout",
                   help="heldout.py's rendered views (default .cache/training/heldout)")
    p.add_argument("--results", type=Path, default=REPO_ROOT / "research" / "training" / "results",
                   help="write noise_aware.md/.json here (default research/training/results)")
    p.add_argument("--masked-blur", action="store_true",
                   help="also the last run with a box mean of its features or guides on the "
                        "pixels whose depth_spread exceeds a threshold (module doc)")
    p.add_argument("--no-progress", action="store_true", help="no tqdm progress bar")
    args = p.parse_args(argv)
    runs = {run.name: load_run(run) for run in args.run}
    held_out = sorted(args.views_dir.glob("*.exr"))
    if not held_out:
        raise SystemExit(f"no views in {args.views_dir}: run heldout.py first")
    first = json.loads((args.run[0] / "run.json").read_text())
    data_dir = Path(first["args"]["data"])
    validation = [data_dir / name for name in first["val_views"]
                  if (data_dir / name).exists()]
    blurs = BLURS if args.masked_blur else ()
    rows = evaluate(held_out + validation, runs,
                    lambda meta: meta.get("heldout", "validation"), not args.no_progress, blurs)
    methods = [*runs, *(blur_name(args.run[-1].name, b) for b in blurs), OIDN]
    lines = ["# A guide told how noisy its depth is (the edge samples' depth spread)", "",
             "Command: `PYTHONPATH=build/python .venv/bin/python Training/ptv_training/"
             f"noise_aware.py --run {' '.join(shown(r) for r in args.run)}"
             f"{' --masked-blur' if blurs else ''}`. Torch denoise "
             f"of the 1-spp frame with {EDGE_SAMPLES} samples on its edge pixels (built from "
             "the stored accumulations, module doc); OIDN fast on the same frame; mean PSNR "
             "(dB) against the references, in brackets the difference to OIDN fast's. Channels "
             "per run: " + "; ".join(
                 f"{name}: {', '.join(run['ck']['channels'])}" for name, run in runs.items())
             + ".", "", *table(rows, methods)]
    write_results(args.results, "noise_aware", lines, rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
