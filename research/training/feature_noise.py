"""CLI: how noisy the 1-spp auxiliary features of the held-out views are, next to the colour's.

GuideNet's guide follows the auxiliary features (albedo, depth, normal of the sampled event);
it can do that only where they are cleaner than the colour. For every view in ``--views-dir``
(``heldout.py``'s rendered held-out views by default), over the pixels whose 4-spp Alpha is
above 0.5, the noise figure of each pass is

    rms(1-spp pass - 4-spp pass) / std(4-spp pass over those pixels),

the 1-spp sample's deviation from the view's 4-spp accumulation (which contains it: the
generated accumulations are nested) in units of the image's own spatial spread. Near 0: a
clean feature a guide can follow; near or above the colour's: as noisy as what it should
smooth. Also the share of those pixels that the mapper's edge rule (``pathtracedvolume.edges``,
on the 1-spp Coverage) gives edge samples: there the frame holds two samples whose
disagreement a denoiser could read. ``--views-dir`` may also hold training views
(``generate.py``'s, grouped as "training", summarised by their mean and maximum). Writes
``<results>/feature_noise.md`` and ``.json`` atomically; needs no rendering.

    .venv/bin/python Training/ptv_training/feature_noise.py \
        --views-dir .cache/training/heldout .cache/training/v2 .cache/training/presets
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Dict, List, Optional, Sequence

import numpy as np
from tqdm import tqdm

if __package__ in (None, ""):  # run as a file
    sys.path.append(str(Path(__file__).resolve().parents[1]))
    import ptv_training  # noqa: F401
    __package__ = "ptv_training"

from pathtracedvolume.edges import edge_mask  # noqa: E402

from . import exr_io  # noqa: E402
from .heldout import SHAPES  # noqa: E402
from .tables import REPO_ROOT, row, shown, write_results  # noqa: E402

PASSES = ("Radiance", "Albedo", "Depth", "Normal")
COVERED_ALPHA = 0.5


def noise_figures(inputs: Dict[int, Dict[str, np.ndarray]]) -> Dict[str, float]:
    """The noise figure of each of PASSES (module doc) and the covered share, from a view's
    1- and 4-spp passes."""
    one, four = inputs[1], inputs[4]
    covered = four["Alpha"][..., 0] > COVERED_ALPHA
    out: Dict[str, float] = {"covered": float(covered.mean())}
    if covered.sum() < 2:  # nothing covered: no figure
        return {**out, "edges": float("nan"), **{name: float("nan") for name in PASSES}}
    out["edges"] = float(edge_mask(one["Coverage"][..., 0])[covered].mean())
    for name in PASSES:
        a = one[name][covered].astype(np.float64)
        b = four[name][covered].astype(np.float64)
        spread = float(b.std())
        out[name] = float(np.sqrt(((a - b) ** 2).mean()) / spread) if spread > 0 else float("nan")
    return out


def main(argv: Optional[Sequence[str]] = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--views-dir", type=Path, nargs="+",
                   default=[REPO_ROOT / ".cache" / "training" / "heldout"],
                   help="folders of views: heldout.py's (default .cache/training/heldout) "
                        "and/or generate.py's")
    p.add_argument("--results", type=Path, default=REPO_ROOT / "research" / "training" / "results",
                   help="write feature_noise.md/.json here (default research/training/results)")
    p.add_argument("--no-progress", action="store_true", help="no tqdm progress bar")
    args = p.parse_args(argv)
    files = sorted(f for d in args.views_dir for f in d.glob("*.exr"))
    if not files:
        raise SystemExit(f"no views in {[str(d) for d in args.views_dir]}: run heldout.py "
                         "(or generate.py) first")
    rows: List[Dict[str, object]] = []
    for path in tqdm(files, desc="views", unit="view", disable=args.no_progress):
        view = exr_io.read_view(path)
        meta = view["view"]
        rows.append({"dataset": meta["dataset"], "shape": meta.get("heldout", "training"),
                     "view": path.stem, **noise_figures(view["inputs"])})
    lines = ["# Noise of the 1-spp auxiliary features on the held-out views", "",
             f"Command: `.venv/bin/python Training/ptv_training/feature_noise.py "
             f"--views-dir {' '.join(shown(d) for d in args.views_dir)}` ({len(rows)} views). "
             "Per pass: rms(1-spp - 4-spp) / std(4-spp) "
             f"over the pixels with 4-spp Alpha > {COVERED_ALPHA} (module doc); near 0 a clean "
             "feature, near the colour's as noisy as the colour. 'edge pixels': the share of "
             "those pixels with edge samples.", "",
             row("shape", "dataset", "covered", "edge pixels", *PASSES),
             "|---|---|---|---|" + "---|" * len(PASSES)]
    for shape in SHAPES + ("training",):
        group = [r for r in rows if r["shape"] == shape]
        if not group:
            continue
        if shape == "training":  # hundreds of views: their spread, not each one
            lines.append(row("training", f"max of {len(group)} views", "", "", *(
                f"{np.nanmax([r[n] for r in group]):.2f}" for n in PASSES)))
            lines.append(row("training", "share of views above 1", "", "", *(
                f"{np.mean([r[n] > 1 for r in group]):.1%}" for n in PASSES)))
        else:
            lines += [row(shape, r["dataset"], f"{r['covered']:.3f}", f"{r['edges']:.0%}",
                           *(f"{r[n]:.2f}" for n in PASSES)) for r in group]
        lines.append(row(shape, "**mean**", "", f"{np.nanmean([r['edges'] for r in group]):.0%}",
                          *(f"**{np.nanmean([r[n] for r in group]):.2f}**" for n in PASSES)))
    write_results(args.results, "feature_noise", lines, rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
