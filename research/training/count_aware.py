"""CLI: does a GuideNet that knows how many samples it has keep improving as they accumulate?

Issue #58: the shipped model, trained on 1-, 2- and 4-spp inputs, stalls when given the mean of
many frames (head 256²: 36.1 dB at 1 frame, 37.8 from 8 on). This study compares, on views none
of them trained on, the shipped model with models fine-tuned from it on inputs of 1, 4, 16 and
64 spp (``generate.py --input-spp 1,4,16,64``), with and without the sample count as an input
(the ``history`` channel: 1 / k for a still accumulation of k frames, which the C++ denoiser
already builds from the mapper's HistoryLength pass).

Every model (``--model NAME=FILE``, ONNX) denoises each validation view's k-spp accumulation
through the C++ ``vtkPTVDenoiser`` (all grid levels at 256², as the mapper does), given the
passes and a HistoryLength of k; OIDN RT fast denoises the same accumulated Radiance, Albedo and
Normal. Reported: mean PSNR (tone-mapped, data_range 1) against each view's reference, per
sample count, over all validation views and per dataset. The last column is each denoiser's
ceiling: the reference itself denoised (with the most-sampled input's other passes and a
HistoryLength of the reference's count), against itself -- what the denoiser takes away from a
converged image. Writes ``<out>.md`` and ``<out>.json``.

    PYTHONPATH=build/python .venv/bin/python research/training/count_aware.py \\
        --model shipped=Data/Models/guidenet.onnx \\
        "fine-tuned=.cache/training/runs/cnt_base/model.onnx" \\
        "fine-tuned + count=.cache/training/runs/cnt_hist/model.onnx"
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Dict, List, Optional, Sequence

import numpy as np
from tqdm import tqdm

ROOT = Path(__file__).resolve().parents[2]
sys.path.append(str(ROOT / "Training"))

from ptv_training import exr_io  # noqa: E402
from ptv_training.compare import oidn_fast  # noqa: E402
from ptv_training.data import sample_passes, split_views  # noqa: E402
from ptv_training.evaluate import cpp_denoise  # noqa: E402
from pathtracedvolume.metrics import psnr  # noqa: E402

RAW = "raw mean"
KNOWN = (*exr_io.INPUT_PASSES, "HistoryLength")  #: the passes given to the C++ denoiser
CEILING = 10**9  #: the "spp" of the ceiling rows (the reference itself denoised)
OIDN = "OIDN fast"


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(prog="python research/training/count_aware.py",
                                description="Denoisers against the sample count on held-out "
                                            "views (mean PSNR per count).")
    p.add_argument("--data", type=Path, default=ROOT / ".cache/training/counts",
                   help="views generated with --input-spp (default .cache/training/counts)")
    p.add_argument("--model", nargs="+", required=True, metavar="NAME=FILE",
                   help="ONNX models to compare")
    p.add_argument("--out", type=Path,
                   default=ROOT / "research/training/results/count_aware",
                   help="results path without suffix (.md and .json are written)")
    p.add_argument("--threads", type=int, default=2, help="denoiser threads (default 2)")
    return p.parse_args(argv)


def table(rows: List[Dict], methods: Sequence[str], counts: Sequence[int],
          groups: Sequence[str]) -> List[str]:
    lines = ["| method | " + " | ".join("ceiling" if k == CEILING else f"{k} spp"
                                        for k in counts) + " |",
             "|---|" + "---|" * len(counts)]
    for method in methods:
        cells = []
        for k in counts:
            values = [r["psnr"] for r in rows if r["method"] == method and r["spp"] == k
                      and r["dataset"] in groups]
            cells.append(f"{np.mean(values):.2f}" if values else "-")
        lines.append(f"| {method} | " + " | ".join(cells) + " |")
    return lines


def main(argv: Optional[Sequence[str]] = None) -> int:
    from pathtracedvolume.atomic import write_text

    args = parse_args(argv)
    models = {name: Path(path) for name, path in (m.split("=", 1) for m in args.model)}
    _, val, _ = split_views(args.data, 0)
    if not val:
        raise SystemExit(f"{args.data}: no validation views")
    rows: List[Dict] = []
    for path in tqdm(val, desc="views", unit="view"):
        view = exr_io.read_view(path)
        dataset = view["view"]["dataset"]
        for k in sorted(view["inputs"]):
            passes = {name: image for name, image in sample_passes(view, path, k).items()
                      if name in KNOWN}  # not DepthSpread, a study pass C++ does not know
            images = {RAW: passes["Radiance"], OIDN: oidn_fast(passes)}
            for name, model in models.items():
                images[name] = cpp_denoise(model, passes, sorted(passes),
                                           threads=args.threads)["output"]
            rows.extend({"view": path.name, "dataset": dataset, "spp": k, "method": m,
                         "psnr": psnr(image, view["reference"])} for m, image in images.items())
        passes = dict(passes, Radiance=view["reference"])  # the ceiling: the most-sampled
        passes["HistoryLength"] = np.full_like(passes["HistoryLength"],  # input's passes
                                               view["view"]["reference_spp"])
        images = {OIDN: oidn_fast(passes), **{name: cpp_denoise(model, passes, sorted(passes),
                                                                threads=args.threads)["output"]
                                              for name, model in models.items()}}
        rows.extend({"view": path.name, "dataset": dataset, "spp": CEILING, "method": m,
                     "psnr": psnr(image, view["reference"])} for m, image in images.items())
    methods = [RAW, *models, OIDN]
    counts = sorted({r["spp"] for r in rows})
    datasets = sorted({r["dataset"] for r in rows})
    command = "python research/training/count_aware.py " + " ".join(
        f'"{a}"' if " " in a else a for a in (sys.argv[1:] if argv is None else argv))
    lines = ["# Denoisers against the sample count (held-out views)", "",
             f"Command: `{command}`. {len(val)} validation views of `{args.data.name}` (one "
             f"per dataset, views no model trained on), mean PSNR (dB) of each k-spp "
             f"accumulation's image against the view's reference.", "",
             *table(rows, methods, counts, datasets), ""]
    for dataset in datasets:
        lines += [f"## {dataset}", "", *table(rows, methods, counts, [dataset]), ""]
    write_text(args.out.with_suffix(".md"), "\n".join(lines))
    write_text(args.out.with_suffix(".json"),
               json.dumps({"command": command, "rows": rows}, indent=1) + "\n")
    print("\n".join(lines[:6 + len(methods)]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
