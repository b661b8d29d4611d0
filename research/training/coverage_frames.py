"""CLI: the denoisers on frames traced with the camera ray's expected coverage.

By default a camera ray either has an event (the event's radiance, Alpha 1) or not (nothing),
with the probability of its opacity: a coin flip whose variance is largest where that opacity is
far from 0 and 1 (translucent media, thin shells). The mapper's ``ExpectedCoverage``
(``Rendering/Kernels/ptvIntegrator.h``, step 4b) marches the ray to its end instead and weights an event drawn along it by the ray's opacity: the same expectation
without the flip, for a longer march. ``Testing/Benchmarks/expected_coverage.py`` measured it on
the Table-1 presets (a little gain for 20-30 % more trace); this study asks what it does on the
transfer functions where the flip dominates, for the shipped model, for a model trained on such
frames (``reinput.py`` traces a training folder's inputs again with ``PTV_EXPECTED_COVERAGE=1``,
which turns the property on in every mapper), and for OIDN RT fast.

For every view, in both modes (ExpectedCoverage off, on): the 1-spp frame the mapper denoises (the view's
input seed, ``EdgeSamples`` 2 on the edge pixels, the Footprint pass) traced through
vtkPathTracedVolumeMapper, each ``--model`` (the C++ denoiser, as ``heldout.py``) and OIDN fast
on it, and the plain 8-spp accumulation of the same seed; PSNR against the view's stored
reference (tone-mapped, data_range 1), and the frame's trace time (median of ``--rounds``
interleaved rounds of a fresh frame, the second of two). Views: the held-out transfer functions
(``heldout.py``'s views), the validation views of ``--data`` (random transfer functions, 1024-spp
references) and the Table-1 views at 256² (``compare.paper_view``). Writes
``<results>/coverage_frames.md`` and ``.json`` atomically. Timings need an idle machine.

    PYTHONPATH=build/python xvfb-run -a .venv/bin/python Training/ptv_training/coverage_frames.py \
        --model Data/Models/guidenet.onnx .cache/training/runs/ec_s1/guidenet.onnx
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence

import numpy as np
from tqdm import tqdm

if __package__ in (None, ""):  # run as a file
    sys.path.append(str(Path(__file__).resolve().parents[1]))
    import ptv_training  # noqa: F401
    __package__ = "ptv_training"

from . import exr_io  # noqa: E402
from .heldout import SHAPES, trace_frame  # noqa: E402
from .tables import REPO_ROOT, row, shown, write_results  # noqa: E402

VARIABLE = "PTV_EXPECTED_COVERAGE"  # would turn ExpectedCoverage on in both modes
MODES = {"flip": False, "expected": True}
EDGE_SAMPLES = 2
BASELINE_SPP = 8
OIDN = "OIDN fast"
PASSES = exr_io.INPUT_PASSES + ("Footprint",)
GROUPS = (*SHAPES, "validation", "head", "stent", "concrete")


def views(heldout_dir: Path, data: Path, paper_cache: Path) -> List[Dict[str, Any]]:
    """Every view of the study: ``{"group", "name", "meta" (Scene.set_view's view), "seed",
    "reference"}``; the Table-1 views are rendered into ``paper_cache`` when missing."""
    from .compare import PAPER_CAMERAS, PAPER_SEEDS, paper_view, paper_view_meta

    out: List[Dict[str, Any]] = []
    files = sorted(heldout_dir.glob("*.exr"))
    if not files:
        raise SystemExit(f"no views in {heldout_dir}: run heldout.py first")
    manifest = json.loads((data / "manifest.json").read_text())
    files += [data / r["file"] for r in manifest["views"] if r["view"].get("split") == "val"]
    for path in files:
        view = exr_io.read_view(path)
        meta = view["view"]
        out.append({"group": meta.get("heldout", "validation"), "name": path.stem,
                    "meta": meta, "seed": meta["input_seed"], "reference": view["reference"]})
    for dataset in ("head", "stent", "concrete"):
        for camera in range(len(PAPER_CAMERAS)):
            ref = paper_view(dataset, 256, camera, 256, paper_cache)["reference"]
            meta = {**paper_view_meta(dataset, camera), "size": [256, 256]}
            out.append({"group": dataset, "name": f"{dataset}_256_{camera}", "meta": meta,
                        "seed": PAPER_SEEDS[0], "reference": ref})
    return out


def evaluate(items: Sequence[Dict[str, Any]], models: Sequence[Path], rounds: int,
             progress: bool = True) -> List[Dict[str, Any]]:
    """One row per (view, mode, method): PSNR; and per (view, mode) the trace time."""
    from pathtracedvolume.metrics import quality

    from .compare import oidn_fast
    from .evaluate import cpp_denoise
    from .scene import Scene

    if os.environ.get(VARIABLE):
        raise RuntimeError(f"{VARIABLE} is set: it would turn ExpectedCoverage on in both modes")
    rows: List[Dict[str, Any]] = []
    scene: Optional[Any] = None
    for item in tqdm(items, desc="views", unit="view", disable=not progress):
        meta = item["meta"]
        if scene is None or scene.dataset != meta["dataset"]:
            scene = Scene(meta["dataset"], tuple(meta["size"]))
        times: Dict[str, List[float]] = {mode: [] for mode in MODES}
        for r in range(rounds):
            for mode, expected in MODES.items():
                mapper = trace_frame(scene, meta, 1000 + r, 2, EDGE_SAMPLES, expected)
                times[mode].append(mapper.GetLastTraceTime())
        for mode, expected in MODES.items():
            trace_frame(scene, meta, item["seed"], 1, EDGE_SAMPLES, expected)
            passes = {name: scene.get_pass(name) for name in PASSES}
            images = {"noisy 1 spp": passes["Radiance"]}
            for model in models:
                images[model_name(model)] = cpp_denoise(model, passes, sorted(passes),
                                                        threads=2)["output"]
            images[OIDN] = oidn_fast(passes)
            trace_frame(scene, meta, item["seed"], BASELINE_SPP, 1, expected)
            images[f"{BASELINE_SPP} spp"] = scene.get_pass("Radiance")
            base = {"view": item["name"], "group": item["group"], "dataset": meta["dataset"],
                    "mode": mode}
            rows.append({**base, "method": "trace ms", "value": statistics.median(times[mode])})
            for method, image in images.items():
                rows.append({**base, "method": method,
                             "value": quality(item["reference"], image)[0]})
    return rows


def model_name(model: Path) -> str:
    """A model's name in the table: its run folder's name, or its file stem."""
    if model.parent.name == "Models":
        return "shipped"
    return model.parent.name if model.stem == "guidenet" else model.stem


def table(rows: Sequence[Dict[str, Any]], methods: Sequence[str]) -> List[str]:
    """Markdown: per group (a column) the mean PSNR of each method in each mode (a row; in
    brackets the difference to OIDN fast's in that mode) and the median trace-time ratio."""
    groups = [g for g in GROUPS if any(r["group"] == g for r in rows)]

    def mean(group: str, method: str, mode: str) -> float:
        return float(np.mean([r["value"] for r in rows if r["group"] == group
                              and r["method"] == method and r["mode"] == mode]))

    def ratio(group: str) -> float:
        times = {(r["view"], r["mode"]): r["value"] for r in rows
                 if r["group"] == group and r["method"] == "trace ms"}
        return statistics.median(times[v, "expected"] / times[v, "flip"]
                                 for v, m in times if m == "flip")

    lines = [row("PSNR (dB)", *groups), "|---|" + "---|" * len(groups),
             row("views", *(len({r["view"] for r in rows if r["group"] == g}) for g in groups)),
             row("trace time, expected / flip (median)", *(f"{ratio(g):.2f} ×" for g in groups))]
    for method in ("noisy 1 spp", f"{BASELINE_SPP} spp", *methods, OIDN):
        for mode in MODES:
            cells = []
            for g in groups:
                value = mean(g, method, mode)
                extra = "" if method in ("noisy 1 spp", f"{BASELINE_SPP} spp", OIDN) else \
                    f" ({value - mean(g, OIDN, mode):+.2f})"
                cells.append(f"{value:.2f}{extra}")
            lines.append(row(f"{method}, {mode}", *cells))
    return lines


def main(argv: Optional[Sequence[str]] = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--model", type=Path, nargs="+", required=True,
                   help="ONNX models (the C++ denoiser) to run on both modes' frames")
    p.add_argument("--views-dir", type=Path, default=REPO_ROOT / ".cache" / "training" / "heldout",
                   help="heldout.py's rendered views (default .cache/training/heldout)")
    p.add_argument("--data", type=Path, default=REPO_ROOT / ".cache" / "training" / "v2",
                   help="a generate.py folder whose validation views are evaluated "
                        "(default .cache/training/v2)")
    p.add_argument("--paper-cache", type=Path,
                   default=REPO_ROOT / ".cache" / "training" / "paper_views",
                   help="compare.py's Table-1 views (default .cache/training/paper_views)")
    p.add_argument("--rounds", type=int, default=3, help="timing rounds (default 3)")
    p.add_argument("--results", type=Path, default=REPO_ROOT / "research" / "training" / "results",
                   help="write coverage_frames.md/.json here (default research/training/results)")
    p.add_argument("--no-progress", action="store_true", help="no tqdm progress bar")
    args = p.parse_args(argv)
    missing = [str(m) for m in args.model if not m.is_file()]
    if missing:
        p.error(f"--model: no such file: {', '.join(missing)}")
    if args.rounds < 1:
        p.error(f"--rounds {args.rounds}: need at least 1")
    items = views(args.views_dir, args.data, args.paper_cache)
    rows = evaluate(items, args.model, args.rounds, not args.no_progress)
    methods = [model_name(m) for m in args.model]
    lines = ["# The denoisers on frames traced with the camera ray's expected coverage", "",
             "Command: `PYTHONPATH=build/python xvfb-run -a .venv/bin/python Training/"
             f"ptv_training/coverage_frames.py --model {' '.join(shown(m) for m in args.model)}`"
             f". Modes: *flip* (the tracer's default) and *expected* (the mapper's "
             "ExpectedCoverage on). The 1-spp "
             f"frame with EdgeSamples {EDGE_SAMPLES} (the frame the mapper denoises), denoised by "
             f"each model (C++) and by OIDN fast; {BASELINE_SPP} spp: the plain accumulation of "
             "the same seed in that mode. Mean PSNR (dB) against each view's reference "
             "(tone-mapped, data_range 1); in brackets the difference to OIDN fast on the same "
             "frames. Groups: the held-out transfer functions (256², 7 datasets), the "
             "validation views of random transfer functions, the Table-1 views at 256² (paper "
             "presets, 2 cameras).", "", *table(rows, methods)]
    write_results(args.results, "coverage_frames", lines, rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
