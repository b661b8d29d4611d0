#!/usr/bin/env python3
"""Benchmark: what the Footprint pass buys the denoised image (vtkPTVDenoiser, DenoiserFootprint).

At one sample a pixel whose camera ray missed cannot be told from the fringe of a thin structure,
so the bilateral grid spreads the structure's colour into the empty pixels of its guide bin (the
halo of ``docs/denoiser-empty-space.md``). The Footprint pass marks the pixels whose corner rays
meet nothing, and the denoiser keeps them black. This runs the shipped model through the C++
denoiser on the Table-1 views of ``Training/ptv_training/compare.py`` (1-spp passes of seed 1,
references of ``--reference-spp`` frames of another seed; cached in ``--cache``) with and
without the Footprint image, and OIDN RT fast on the same passes; PSNR after the tone map of
``docs/measuring.md`` (the premultiplied colour against the premultiplied reference), and the
share of pixels it clears, of which how many the reference leaves empty (below 0.02 after the
tone map). Quality only: the pass's trace cost is ``coverage_cost.py --pass Footprint``.

    PYTHONPATH=build/python xvfb-run -a .venv/bin/python research/benchmarks/footprint_quality.py
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
    p.add_argument("--sizes", nargs="+", type=int, default=[256, 512],
                   help="image sizes (default 256 512)")
    from ptv_training.compare import add_paper_view_arguments
    add_paper_view_arguments(p)
    return p.parse_args()


def main() -> int:
    a = parse_args()
    from evaluation.common import md_table
    from pathtracedvolume.atomic import write_text
    from pathtracedvolume.metrics import psnr
    from ptv_training import compare
    from ptv_training.evaluate import cpp_denoise

    rows: List[Dict[str, Any]] = []
    for size in a.sizes:
        for ds in compare.PAPER_DATASETS:
            for cam in range(len(compare.PAPER_CAMERAS)):
                view = compare.paper_view(ds, size, cam, a.reference_spp, a.cache)
                passes, ref = view["inputs"], view["reference"]
                if "Footprint" not in passes:
                    raise RuntimeError(f"{ds} {size} {cam}: the cached view has no Footprint "
                                       "pass: run Training/ptv_training/coverage.py add "
                                       "--pass Footprint")
                plain = {k: v for k, v in passes.items() if k != "Footprint"}
                without = cpp_denoise(a.model, plain, sorted(plain), threads=2)["output"]
                marked = cpp_denoise(a.model, passes, sorted(passes), threads=2)["output"]
                cleared = np.all(marked == 0, axis=-1) & ~np.all(without == 0, axis=-1)
                empty_ref = np.clip(np.maximum(ref, 0) ** (1 / 2.2), 0, 1).max(-1) < 0.02
                rows.append({"size": size, "dataset": ds, "camera": cam,
                             "without": psnr(without, ref), "with": psnr(marked, ref),
                             "oidn_fast": psnr(compare.oidn_fast(passes), ref),
                             "cleared": float(cleared.mean()),
                             "cleared_empty_in_reference": float(
                                 (cleared & empty_ref).sum() / max(cleared.sum(), 1))})
                print(rows[-1], flush=True)
    table = [[f"{r['size']}²", r["dataset"], str(r["camera"]), f"{r['without']:.2f}",
              f"{r['with']:.2f}", f"{r['with'] - r['without']:+.2f}", f"{r['oidn_fast']:.2f}",
              f"{100 * r['cleared']:.1f} %", f"{100 * r['cleared_empty_in_reference']:.1f} %"]
             for r in rows]
    for size in a.sizes:
        sel = [r for r in rows if r["size"] == size]
        mean = {k: float(np.mean([r[k] for r in sel])) for k in ("without", "with", "oidn_fast")}
        table.append([f"{size}²", "**mean**", "", f"{mean['without']:.2f}", f"{mean['with']:.2f}",
                      f"{mean['with'] - mean['without']:+.2f}", f"{mean['oidn_fast']:.2f}", "",
                      ""])
    text = "\n".join([
        "# The Footprint pass: denoised quality", "",
        f"Command: `{' '.join(sys.argv)}`", "",
        f"The Table-1 views (`compare.paper_view`: 1-spp passes of seed 1, {a.reference_spp}-spp "
        f"references of another seed), `{a.model.name}` through vtkPTVDenoiser (its automatic "
        "level count: 3 at 256², 1 at 512²) without and with the Footprint image, OIDN RT fast "
        "on the same passes; PSNR (dB) after the tone map. 'cleared': pixels the Footprint "
        "pass turned black; 'empty in reference': of those, the share whose reference is below "
        "0.02 after the tone map.", "",
        *md_table(["size", "dataset", "camera", "without", "with Footprint", "gain",
                   "OIDN fast", "cleared", "empty in reference"], table), ""])
    if a.markdown:
        write_text(a.markdown, text)
    if a.json:
        write_text(a.json, json.dumps({"rows": rows}, indent=1) + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
