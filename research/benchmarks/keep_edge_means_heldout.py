"""Study (issues #58, #61): KeepEdgeMeans on the held-out transfer functions, judged on what the
mapper shows.

KeepEdgeMeans was left off because it cost the held-out narrow bands 1.1 dB of the denoised
1-spp frame (`research/notes/edge-samples-log.md`); since then the shown image (pass
``Converged``) mixes the denoised image with the raw mean per pixel, and on the Table-1 views
the switch gains 0-0.7 dB on a view's first frame (`research/results/edge_switches.md`). For
each volume and held-out shape (``heldout.py``'s first camera, 256²), the mapper with Denoise on
and its default EdgeSamples renders one view with KeepEdgeMeans off and on; PSNR of the shown
image after 1 and 2 frames against ``--reference-spp`` of the view's reference seed.

    PYTHONPATH=build/python xvfb-run -a .venv/bin/python \\
        research/benchmarks/keep_edge_means_heldout.py
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "Training"))

DATASETS = ("head", "stent", "concrete", "mri", "snow", "neutron", "nuclei")
SHAPES = ("translucent", "smooth", "narrow")
COUNTS = (1, 2)


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    p.add_argument("--datasets", nargs="+", default=list(DATASETS))
    p.add_argument("--shapes", nargs="+", default=list(SHAPES), choices=SHAPES)
    p.add_argument("--size", type=int, default=256)
    p.add_argument("--reference-spp", type=int, default=512)
    p.add_argument("--out", type=Path,
                   default=ROOT / "research/results/keep_edge_means_heldout")
    return p.parse_args(argv)


def measure(args: argparse.Namespace) -> List[Dict[str, Any]]:
    from tqdm import tqdm

    from pathtracedvolume.metrics import quality
    from ptv_training.generate import dataset_histogram
    from ptv_training.heldout import heldout_view
    from ptv_training.scene import Scene
    from ptv_training.transfer import held_out_transfer_functions

    rows: List[Dict[str, Any]] = []
    for dataset in tqdm(args.datasets, desc="volumes", unit="volume"):
        scene = Scene(dataset, (args.size, args.size))
        tfs = held_out_transfer_functions(dataset_histogram(dataset))
        for shape in args.shapes:
            view = heldout_view(dataset, shape, 0, tfs[shape], args.size, args.reference_spp)
            scene.set_view(view, seed=view["reference_seed"], max_frames=args.reference_spp,
                           coverage=False)
            scene.render(args.reference_spp)
            reference = scene.get_pass("Radiance")
            row: Dict[str, Any] = {"dataset": dataset, "shape": shape}
            for keep in (False, True):
                mapper = scene.set_view(view, seed=view["input_seed"], denoise=True,
                                        max_frames=max(COUNTS), footprint=True)
                mapper.GetExpertOptions().SetKeepEdgeMeans(keep)
                for k in range(1, max(COUNTS) + 1):
                    scene.render(1)
                    if k in COUNTS:
                        row[f"{'on' if keep else 'off'} {k}"] = quality(
                            reference, scene.get_pass("Converged"))[0]
            rows.append(row)
    return rows


def table(rows: Sequence[Dict[str, Any]]) -> str:
    keys = [f"{s} {k}" for k in COUNTS for s in ("off", "on")]
    lines = ["| shape | dataset | " + " | ".join(f"KeepEdgeMeans {k} fr" for k in keys) + " |",
             "|" + "---|" * (2 + len(keys))]
    for shape in SHAPES:
        group = [r for r in rows if r["shape"] == shape]
        if not group:
            continue
        for r in group:
            lines.append(f"| {shape} | {r['dataset']} | " +
                         " | ".join(f"{r[k]:.2f}" for k in keys) + " |")
        lines.append(f"| {shape} | **mean** | " + " | ".join(
            f"{sum(r[k] for r in group) / len(group):.2f}" for k in keys) + " |")
    return "\n".join(lines)


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = parse_args(argv)
    rows = measure(args)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.with_suffix(".json").write_text(json.dumps({"rows": rows}, indent=1))
    text = ("# KeepEdgeMeans on the held-out transfer functions, shown image\n\nPSNR (dB) of "
            f"pass Converged against {args.reference_spp} spp of the view's reference seed; "
            f"`{' '.join(sys.argv)}`.\n\n" + table(rows) + "\n")
    args.out.with_suffix(".md").write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
