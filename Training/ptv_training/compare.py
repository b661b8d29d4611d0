"""CLI: compare denoisers on a data set's validation views: ONNX models through the C++
``vtkPTVDenoiser``, a training run exported with 1, 2 or 3 of its grid levels, and OIDN RT fast.

Each validation view's 1-spp passes are denoised by every method; the table gives the mean PSNR
per dataset against the view's (1024-spp) reference (tone-mapped ``clip(max(0, x)^(1/2.2), 0,
1)``, scikit-image, data_range 1), beside the noisy input and the 16-spp baseline of the same
seed. Writes ``<out>.md`` and ``<out>.json`` atomically.

    PYTHONPATH=build/python .venv/bin/python Training/ptv_training/compare.py \\
        --run .cache/training/runs/ship_v2 --levels 1 2 3 --model first=old.onnx
"""
from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path
from typing import Dict, List, Optional, Sequence

import numpy as np

if __package__ in (None, ""):  # run as a file
    sys.path.append(str(Path(__file__).resolve().parents[1]))
    import ptv_training  # noqa: F401
    __package__ = "ptv_training"

from pathtracedvolume.atomic import write_text  # noqa: E402

from . import exr_io  # noqa: E402
from .data import split_views  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parents[2]


def export_levels(run: Path, levels: int, folder: Path) -> Path:
    """The run's best checkpoint as ONNX with its finest ``levels`` grid levels."""
    import torch

    from .export_onnx import export
    from .guidenet import GuideNet

    ck = torch.load(run / "best.pt", weights_only=False)
    model = GuideNet(**ck["config"])
    model.load_state_dict(ck["model"])
    return export(model, folder / f"{run.name}_L{levels}.onnx", ck["channels"],
                  [tuple(level) for level in ck["levels"]],
                  extra_metadata={"ptv.demodulate": "1" if ck.get("demodulate", True) else "0"},
                  use_levels=levels)


def oidn_fast(passes: Dict[str, np.ndarray]) -> np.ndarray:
    import pyoidn
    return pyoidn.denoise(
        np.ascontiguousarray(np.maximum(np.nan_to_num(passes["Radiance"]), 0), np.float32),
        np.ascontiguousarray(np.clip(passes["Albedo"], 0, 1), np.float32),
        np.ascontiguousarray(np.clip(np.nan_to_num(passes["Normal"]), -1, 1), np.float32),
        hdr=True, quality="fast")


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(prog="python Training/ptv_training/compare.py",
                                description="Mean validation PSNR per dataset of ONNX models, "
                                            "a run's exports at several level counts and OIDN "
                                            "fast, all through the same passes.")
    p.add_argument("--data", type=Path, default=REPO_ROOT / ".cache" / "training" / "v2",
                   help="views folder (default .cache/training/v2)")
    p.add_argument("--run", type=Path, default=None, help="a training run to export")
    p.add_argument("--levels", type=int, nargs="*", default=[], choices=(1, 2, 3),
                   help="level counts to export the run with")
    p.add_argument("--model", nargs="*", default=[], metavar="NAME=FILE",
                   help="ONNX models to compare, each named")
    p.add_argument("--out", type=Path,
                   default=REPO_ROOT / "Training" / "results" / "v2_validation",
                   help="write OUT.md and OUT.json (default Training/results/v2_validation)")
    args = p.parse_args(argv)
    if args.levels and args.run is None:
        p.error("--levels needs --run")
    for item in args.model:
        if "=" not in item or not Path(item.split("=", 1)[1]).is_file():
            p.error(f"--model {item!r}: expected NAME=FILE with an existing FILE")
    return args


def main(argv: Optional[Sequence[str]] = None) -> int:
    from pathtracedvolume.metrics import psnr

    from .evaluate import cpp_denoise

    args = parse_args(argv)
    command = "python Training/ptv_training/compare.py " + " ".join(
        sys.argv[1:] if argv is None else list(map(str, argv)))
    _, val, _ = split_views(args.data, 2)
    with tempfile.TemporaryDirectory() as tmp:
        models = {name: Path(path) for name, path in (m.split("=", 1) for m in args.model)}
        for levels in args.levels:
            models[f"{args.run.name}, {levels} level{'s' * (levels > 1)}"] = \
                export_levels(args.run, levels, Path(tmp))
        rows: List[Dict[str, object]] = []
        for path in val:
            view = exr_io.read_view(path)
            passes, dataset = view["inputs"][1], view["view"]["dataset"]
            images = {"noisy 1 spp": passes["Radiance"], "16 spp": view["spp16"]}
            for name, model in models.items():
                images[name] = cpp_denoise(model, passes, sorted(passes), threads=2)["output"]
            images["OIDN RT fast"] = oidn_fast(passes)
            rows += [{"view": path.name, "dataset": dataset, "method": m,
                      "psnr": psnr(image, view["reference"])} for m, image in images.items()]
    methods = list(dict.fromkeys(r["method"] for r in rows))
    datasets = sorted({r["dataset"] for r in rows})

    def mean(method: str, dataset: Optional[str] = None) -> float:
        return float(np.mean([r["psnr"] for r in rows if r["method"] == method
                              and dataset in (None, r["dataset"])]))

    lines = ["# Validation views: denoisers compared\n",
             f"Command: `{command}`. {len(val)} validation views of `{args.data.name}`, 1-spp "
             "input, mean PSNR (dB) per dataset against each view's reference, tone-mapped, "
             "scikit-image, data_range 1; models run by the C++ `vtkPTVDenoiser`.\n",
             "| method | " + " | ".join(datasets) + " | mean |",
             "|---|" + "---|" * (len(datasets) + 1)]
    lines += [f"| {m} | " + " | ".join(f"{mean(m, d):.2f}" for d in datasets)
              + f" | {mean(m):.2f} |" for m in methods]
    text = "\n".join(lines) + "\n"
    write_text(args.out.with_suffix(".md"), text)
    write_text(args.out.with_suffix(".json"),
               json.dumps({"command": command, "rows": rows}, indent=1) + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
