#!/usr/bin/env python3
"""Study: where a denoised frame's squared error sits -- empty space, the volume's fringe or its
interior -- with and without EdgeSamples.

For the report's Table-1 views (``Training/ptv_training/compare.py``'s: paper presets, cameras
30/10 and 150/-20 degrees, 1-spp input of seed 1, ``--reference-spp`` references of another
seed, cached in ``--cache``), each frame is traced with EdgeSamples ``--counts`` (1 = none)
and denoised by the shipped model through vtkPTVDenoiser (the Footprint pass as the mapper gives
it). Pixels are classed by the reference after the tone map of ``docs/measuring.md``: *empty*
(its largest channel below 0.02), *fringe* (covered, with an empty pixel in its 3x3
neighbourhood) and *interior* (the other covered pixels), and the fringe and interior again by
whether the frame's own (first) sample met the volume (Alpha). Per class: its share of the
pixels and of the squared error, and its mean tone-mapped colour against the reference's.
Quality only (``edge_samples.py`` has the cost).

    PYTHONPATH=build/python xvfb-run -a .venv/bin/python research/benchmarks/error_by_pixel_class.py
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any, Dict, List

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "Training"))
sys.path.insert(0, str(Path(__file__).resolve().parent))


def parse_args() -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--size", type=int, default=256, help="image size (default 256)")
    p.add_argument("--counts", nargs="+", type=int, default=[1, 2],
                   help="EdgeSamples values (default 1 2)")
    from ptv_training.compare import add_paper_view_arguments
    add_paper_view_arguments(p)
    return p.parse_args()


def tone(x: np.ndarray) -> np.ndarray:
    return np.clip(np.maximum(x, 0.0) ** (1 / 2.2), 0.0, 1.0)


def classes(reference: np.ndarray, hit: np.ndarray) -> Dict[str, np.ndarray]:
    """Pixel classes of a (H, W, 3) reference and a (H, W) hit mask of the frame."""
    from scipy.ndimage import minimum_filter
    level = tone(reference).max(axis=-1)
    empty = level < 0.02
    fringe = ~empty & (minimum_filter(level, size=3, mode="nearest") < 0.02)
    interior = ~empty & ~fringe
    return {"empty": empty, "fringe, hit": fringe & hit, "fringe, missed": fringe & ~hit,
            "interior, hit": interior & hit, "interior, missed": interior & ~hit}


def main() -> int:
    a = parse_args()
    from evaluation.common import md_table
    from pathtracedvolume.atomic import write_text
    from pathtracedvolume.scene import paper_preset
    from ptv_training import compare, exr_io
    from ptv_training.evaluate import cpp_denoise
    from ptv_training.scene import Scene
    from pathtracedvolume.edges import edge_mask

    names = list(exr_io.INPUT_PASSES) + ["Footprint"]
    rows: List[Dict[str, Any]] = []
    for ds in compare.PAPER_DATASETS:
        scene = Scene(ds, (a.size, a.size))
        for cam, (azimuth, elevation) in enumerate(compare.PAPER_CAMERAS):
            cached = compare.paper_view(ds, a.size, cam, a.reference_spp, a.cache)
            ref = cached["reference"]
            hit = cached["inputs"]["Alpha"][..., 0] > 0.5  # the frame's first sample
            kinds = classes(ref, hit)
            fringe = kinds["fringe, hit"] | kinds["fringe, missed"]
            # the fringe that gets edge samples (the rule on the frame sample's Coverage)
            edged = edge_mask(cached["inputs"]["Coverage"][..., 0])
            fringe_edged = float(edged[fringe].mean()) if fringe.any() else float("nan")
            view = {"dataset": ds, "transfer_function": paper_preset(ds),
                    "azimuth": azimuth, "elevation": elevation}
            for count in a.counts:
                mapper = scene.set_view(view, seed=compare.PAPER_SEEDS[0], max_frames=1,
                                        footprint=True)
                mapper.GetExpertOptions().SetEdgeSamples(count)
                mapper.GetExpertOptions().SetComputeEdgeSamples(count > 1)
                scene.render(1)
                passes = {n: scene.get_pass(n) for n in names}
                out = cpp_denoise(a.model, passes, sorted(passes), threads=2)["output"]
                error = ((tone(out) - tone(ref)) ** 2).mean(axis=-1)
                total = float(error.sum())
                row: Dict[str, Any] = {"dataset": ds, "camera": cam, "count": count,
                                       "psnr": float(-10 * np.log10(error.mean())),
                                       "fringe_with_edge_samples": fringe_edged}
                for name, mask in kinds.items():
                    row[name] = {
                        "pixels": float(mask.mean()),
                        "error_share": float(error[mask].sum() / total),
                        "mean": float(tone(out).mean(-1)[mask].mean()) if mask.any() else None,
                        "reference_mean": (float(tone(ref).mean(-1)[mask].mean())
                                           if mask.any() else None)}
                rows.append(row)
                print({k: v for k, v in row.items() if k in ("dataset", "camera", "count",
                                                             "psnr")}, flush=True)
    kinds = list(classes(np.zeros((1, 1, 3)), np.zeros((1, 1), bool)))  # type: ignore[assignment]
    table = []
    for r in rows:
        cells = []
        for k in kinds:
            c = r[k]
            shown = "" if c["mean"] is None else f", {c['mean']:.3f} / {c['reference_mean']:.3f}"
            cells.append(f"{100 * c['pixels']:.1f} % / {100 * c['error_share']:.1f} %{shown}")
        table.append([r["dataset"], str(r["camera"]), str(r["count"]), f"{r['psnr']:.2f}",
                      f"{100 * r['fringe_with_edge_samples']:.0f} %", *cells])
    text = "\n".join([
        "# Where the denoised frame's error sits", "",
        f"Command: `{' '.join(sys.argv)}`", "",
        f"The Table-1 views at {a.size}² (1-spp input of seed 1, {a.reference_spp}-spp "
        f"references), traced with EdgeSamples {', '.join(map(str, a.counts))} and denoised "
        f"by `{a.model.name}` (vtkPTVDenoiser, Footprint pass on). Classes from the reference "
        "after the tone map: empty (below 0.02), fringe (covered, an empty pixel in its 3x3 "
        "neighbourhood), interior; hit / missed: the frame's first sample met the volume or "
        "not. Each cell: share of the pixels / share of the squared error, mean tone-mapped "
        "colour of the denoised frame / of the reference. 'fringe with edge samples': the "
        "share of the fringe that the edge rule marks (on the frame sample's Coverage).", "",
        *md_table(["dataset", "camera", "EdgeSamples", "PSNR", "fringe with edge samples",
                   *kinds], table), ""])
    if a.markdown:
        write_text(a.markdown, text)
    if a.json:
        write_text(a.json, json.dumps({"rows": rows}, indent=1) + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
