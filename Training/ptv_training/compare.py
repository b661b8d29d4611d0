"""CLI: compare denoisers on a data set's validation views: ONNX models through the C++
``vtkPTVDenoiser``, training runs exported with 1, 2 or 3 of their grid levels, and OIDN RT fast.

Each validation view's 1-spp passes are denoised by every method; the table gives the mean PSNR
per dataset against the view's (1024-spp) reference (tone-mapped ``clip(max(0, x)^(1/2.2), 0,
1)``, scikit-image, data_range 1), beside the noisy input and the 16-spp baseline of the same
seed. ``--paper-views SIZE ...`` adds the evaluation report's Table-1 views (head, stent and
concrete under their paper presets, cameras 30/10 and 150/-20 degrees, the default light) at
each size: 1-spp input of seed 1 and a ``--paper-reference-spp`` reference of seed 100003, the
report's seeds, rendered once into ``--paper-cache``. Writes ``<out>.md`` and ``<out>.json``
atomically.

    PYTHONPATH=build/python .venv/bin/python Training/ptv_training/compare.py \\
        --run .cache/training/runs/ship_v2 --levels 1 2 3 --model first=old.onnx
"""
from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence

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
    from .export_onnx import export
    from .train import load_run

    model, ck = load_run(run)
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
    p.add_argument("--run", type=Path, nargs="*", default=[],
                   help="training runs to export (their best checkpoints)")
    p.add_argument("--levels", type=int, nargs="*", default=[], choices=(1, 2, 3),
                   help="level counts to export each run with")
    p.add_argument("--paper-views", type=int, nargs="*", default=[], metavar="SIZE",
                   help="also the report's Table-1 views at these sizes (e.g. 256 512)")
    p.add_argument("--paper-reference-spp", type=int, default=256,
                   help="samples of the Table-1 views' references (default 256)")
    p.add_argument("--paper-cache", type=Path,
                   default=REPO_ROOT / ".cache" / "training" / "paper_views",
                   help="rendered Table-1 views (default .cache/training/paper_views)")
    p.add_argument("--model", nargs="*", default=[], metavar="NAME=FILE",
                   help="ONNX models to compare, each named")
    p.add_argument("--out", type=Path,
                   default=REPO_ROOT / "Training" / "results" / "v2_validation",
                   help="write OUT.md and OUT.json (default Training/results/v2_validation)")
    args = p.parse_args(argv)
    if bool(args.levels) != bool(args.run):
        p.error("--run and --levels go together")
    for item in args.model:
        if "=" not in item or not Path(item.split("=", 1)[1]).is_file():
            p.error(f"--model {item!r}: expected NAME=FILE with an existing FILE")
    return args


def add_paper_view_arguments(p: argparse.ArgumentParser) -> None:
    """The options of the benchmarks that denoise the Table-1 views (``paper_view``) with a
    model: ``--reference-spp``, ``--model``, ``--cache``, ``--json``, ``--markdown``."""
    p.add_argument("--reference-spp", type=int, default=256, help="reference frames (256)")
    p.add_argument("--model", type=Path, default=REPO_ROOT / "Data" / "Models" / "guidenet.onnx",
                   help="the model (default the shipped one)")
    p.add_argument("--cache", type=Path,
                   default=REPO_ROOT / ".cache" / "training" / "paper_views",
                   help="rendered Table-1 views (default .cache/training/paper_views)")
    p.add_argument("--json", type=Path, default=None, help="also write the rows as JSON")
    p.add_argument("--markdown", type=Path, default=None, help="also write the tables")


PAPER_DATASETS = ("head", "stent", "concrete")
PAPER_CAMERAS = ((30.0, 10.0), (150.0, -20.0))
PAPER_SEEDS = (1, 100003)  # input, reference: the evaluation report's


def paper_view_meta(dataset: str, camera: int) -> Dict[str, Any]:
    """The parameters of Table-1 view ``camera`` of ``dataset`` (``Scene.set_view``'s view):
    the dataset's paper preset seen from ``PAPER_CAMERAS[camera]``."""
    from pathtracedvolume.scene import paper_preset

    azimuth, elevation = PAPER_CAMERAS[camera]
    return {"dataset": dataset, "transfer_function": paper_preset(dataset),
            "azimuth": azimuth, "elevation": elevation}


def paper_view(dataset: str, size: int, camera: int, reference_spp: int,
               cache: Path) -> Dict[str, object]:
    """A Table-1 view: its 1-spp passes ("inputs") and reference, rendered once into ``cache``."""
    from pathtracedvolume.atomic import atomic_path

    from .scene import Scene

    path = cache / f"{dataset}_{size}_{camera}_{reference_spp}.npz"
    if not path.is_file():
        view = paper_view_meta(dataset, camera)
        scene = Scene(dataset, (size, size))
        scene.set_view(view, seed=PAPER_SEEDS[0], max_frames=1, footprint=True)
        scene.render(1)
        arrays = {name: scene.get_pass(name) for name in exr_io.INPUT_PASSES + ("Footprint",)}
        scene.set_view(view, seed=PAPER_SEEDS[1], max_frames=reference_spp, coverage=False)
        if scene.render(reference_spp) != reference_spp:
            raise RuntimeError(f"{path.name}: the reference did not accumulate")
        arrays["reference"] = scene.get_pass("Radiance")
        cache.mkdir(parents=True, exist_ok=True)
        with atomic_path(path) as tmp:
            with open(tmp, "wb") as fh:
                np.savez(fh, **arrays)
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    reference = arrays.pop("reference")
    return {"inputs": arrays, "reference": reference}


def main(argv: Optional[Sequence[str]] = None) -> int:
    from pathtracedvolume.metrics import psnr

    from .evaluate import cpp_denoise

    args = parse_args(argv)
    command = "python Training/ptv_training/compare.py " + " ".join(
        sys.argv[1:] if argv is None else list(map(str, argv)))
    _, val, _ = split_views(args.data, 2)
    with tempfile.TemporaryDirectory() as tmp:
        models = {name: Path(path) for name, path in (m.split("=", 1) for m in args.model)}
        for run in args.run:
            for levels in args.levels:
                models[f"{run.name}, {levels} level{'s' * (levels > 1)}"] = \
                    export_levels(run, levels, Path(tmp))
        rows: List[Dict[str, object]] = []

        def compare(name: str, group: str, passes: Dict[str, np.ndarray],
                    reference: np.ndarray, extra: Dict[str, np.ndarray]) -> None:
            images = {"noisy 1 spp": passes["Radiance"], **extra}
            for method, model in models.items():
                images[method] = cpp_denoise(model, passes, sorted(passes),
                                             threads=2)["output"]
            images["OIDN RT fast"] = oidn_fast(passes)
            rows.extend({"view": name, "dataset": group, "method": m,
                         "psnr": psnr(image, reference)} for m, image in images.items())

        for path in val:
            view = exr_io.read_view(path)
            compare(path.name, view["view"]["dataset"], view["inputs"][1], view["reference"],
                    {"16 spp": view["spp16"]})
        for size in args.paper_views:
            for dataset in PAPER_DATASETS:
                for camera in range(len(PAPER_CAMERAS)):
                    view = paper_view(dataset, size, camera, args.paper_reference_spp,
                                      args.paper_cache)
                    compare(f"{dataset}_{size}_{camera}", f"Table 1 {dataset} {size}²",
                            view["inputs"], view["reference"], {})
    methods = list(dict.fromkeys(r["method"] for r in rows))
    groups = list(dict.fromkeys(r["dataset"] for r in rows))
    datasets = sorted(g for g in groups if not g.startswith("Table 1"))
    paper = [g for g in groups if g.startswith("Table 1")]
    paper_sizes = [f"{size}²" for size in args.paper_views]

    def mean(method: str, dataset: Optional[str] = None, among: Sequence[str] = ()) -> float:
        among = among or datasets
        values = [r["psnr"] for r in rows if r["method"] == method
                  and (r["dataset"] == dataset if dataset else r["dataset"] in among)]
        return float(np.mean(values)) if values else float("nan")

    lines = ["# Validation views: denoisers compared\n",
             f"Command: `{command}`. {len(val)} validation views of `{args.data.name}`, 1-spp "
             "input, mean PSNR (dB) per dataset against each view's reference, tone-mapped, "
             "scikit-image, data_range 1; models run by the C++ `vtkPTVDenoiser`.\n",
             "| method | " + " | ".join(datasets) + " | mean |",
             "|---|" + "---|" * (len(datasets) + 1)]
    lines += [f"| {m} | " + " | ".join(f"{mean(m, d):.2f}" for d in datasets)
              + f" | {mean(m):.2f} |" for m in methods]
    if paper:
        lines += ["", f"The evaluation report's Table-1 views (paper presets, 2 cameras each; "
                  f"{args.paper_reference_spp}-spp references), mean PSNR (dB):", "",
                  "| method | " + " | ".join(g[len("Table 1 "):] for g in paper) + " | "
                  + " | ".join(f"mean {s}" for s in paper_sizes) + " |",
                  "|---|" + "---|" * (len(paper) + len(paper_sizes))]
        paper_methods = [m for m in methods if m != "16 spp"]
        lines += [f"| {m} | " + " | ".join(f"{mean(m, g):.2f}" for g in paper) + " | "
                  + " | ".join(f"{mean(m, among=[g for g in paper if g.endswith(s)]):.2f}"
                               for s in paper_sizes) + " |" for m in paper_methods]
    text = "\n".join(lines) + "\n"
    write_text(args.out.with_suffix(".md"), text)
    write_text(args.out.with_suffix(".json"),
               json.dumps({"command": command, "rows": rows}, indent=1) + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
