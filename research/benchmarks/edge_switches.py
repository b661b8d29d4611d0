"""Study (issues #58, #61): do the edge switches still pay now that the shown image is the learned
per-pixel mix of the denoised image and the raw mean?

``KeepEdgeMeans`` (expert option, default off) leans a view's first denoised frame towards each
edge pixel's own mean; ``EdgeSamples`` (default 3) traces that many samples on the volume's edge
pixels of every denoised frame. For each dataset (view 0 of the report's Table 1, paper preset)
and size, one accumulation per setting, read after 1, 2, 4 and 8 frames: PSNR of the shown image
(pass ``Converged``) against the report's reference (``--ref-spp`` of an independent seed, cached
as the report caches it), and the median trace time of a frame. Settings: the defaults
(EdgeSamples 3, KeepEdgeMeans off), KeepEdgeMeans on, EdgeSamples 1.

    PYTHONPATH=build/python xvfb-run -a .venv/bin/python research/benchmarks/edge_switches.py
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "Testing/Benchmarks"))

from evaluation.common import parse_args as report_args  # noqa: E402
from evaluation.samples import _psnr  # noqa: E402
from evaluation.scenes import Bench  # noqa: E402

SETTINGS = {"defaults": {}, "KeepEdgeMeans on": {"KeepEdgeMeans": True},
            "EdgeSamples 1": {"EdgeSamples": 1}}
COUNTS = (1, 2, 4, 8)
SEED = 1


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    p.add_argument("--sizes", type=int, nargs="+", default=[256, 512])
    p.add_argument("--datasets", nargs="+", default=["head", "stent", "concrete"])
    p.add_argument("--ref-spp", type=int, default=1024)
    p.add_argument("--out", type=Path, default=ROOT / "research/results/edge_switches")
    return p.parse_args(argv)


def measure(args: argparse.Namespace) -> List[Dict[str, Any]]:
    from tqdm import tqdm

    bench = Bench(report_args(["--ref-spp", str(args.ref_spp)]))
    rows: List[Dict[str, Any]] = []
    jobs = [(s, d, n) for s in args.sizes for d in args.datasets for n in SETTINGS]
    for size, dataset, name in tqdm(jobs, desc="edge switches", unit="run"):
        spec = bench.view_spec(dataset, 0, size)
        ref = bench.reference(spec, args.ref_spp)["ref"]
        scene = bench.scenes.scene(spec)
        mapper = scene.mapper
        options = mapper.GetExpertOptions()
        keep, edge = options.GetKeepEdgeMeans(), options.GetEdgeSamples()
        options.SetKeepEdgeMeans(SETTINGS[name].get("KeepEdgeMeans", keep))
        options.SetEdgeSamples(SETTINGS[name].get("EdgeSamples", edge))
        mapper.DenoiseOn()
        row: Dict[str, Any] = {"size": size, "dataset": dataset, "setting": name}

        def on_frame(k: int) -> None:
            if k in COUNTS:
                row[str(k)] = _psnr(scene.grab("Converged"), ref)

        try:
            times = scene.render(seed=SEED, frames=max(COUNTS), on_frame=on_frame)
        finally:
            mapper.DenoiseOff()
            options.SetKeepEdgeMeans(keep)
            options.SetEdgeSamples(edge)
        row["trace ms"] = statistics.median(times)
        rows.append(row)
    return rows


def table(rows: Sequence[Dict[str, Any]]) -> str:
    head = "| size | dataset | setting | " + " | ".join(f"{k} fr" for k in COUNTS) + \
        " | trace ms (median) |"
    lines = [head, "|" + "---|" * (4 + len(COUNTS))]
    for r in rows:
        lines.append(f"| {r['size']} | {r['dataset']} | {r['setting']} | " +
                     " | ".join(f"{r[str(k)]:.2f}" for k in COUNTS) +
                     f" | {r['trace ms']:.1f} |")
    return "\n".join(lines)


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = parse_args(argv)
    rows = measure(args)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.with_suffix(".json").write_text(json.dumps({"rows": rows}, indent=1))
    text = ("# Edge switches against the learned shown mix\n\nShown image (Converged) PSNR in "
            f"dB against {args.ref_spp} spp of another seed; `{' '.join(sys.argv)}`.\n\n"
            + table(rows) + "\n")
    args.out.with_suffix(".md").write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
