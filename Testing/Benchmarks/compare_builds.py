#!/usr/bin/env python3
"""Benchmark: the same denoise in two or more builds of the project, interleaved.

A change to the denoiser's code (not its model) is judged against the build before it: each
build's ``vtkPTVDenoiser`` denoises the same cached 1-spp passes (those of
``benchmark_denoiser.py``, rendered once by the first build) in a process of its own, one
process per build and round, the builds' order alternating from round to round; each process
times ``--repeats`` denoises after a warm-up and reports their median, per stage too. Times are
medians over rounds, ratios medians of per-round ratios against the first build; the images'
largest difference from the first build's says whether the change kept them. Run it on an idle
machine.

Example (the build before a change in /tmp/oldbuild)::

    xvfb-run -a .venv/bin/python Testing/Benchmarks/compare_builds.py \\
        --builds before=/tmp/oldbuild/python after=build/python --sizes 512 1024
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path
from typing import Dict, List, Tuple

from tqdm import tqdm

ROOT = Path(__file__).resolve().parents[2]
STAGES = ("features", "guidenet", "splat", "slice", "alpha")


def parse_args(argv: List[str] | None = None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--builds", nargs="+", required=True, metavar="NAME=PYTHONPATH",
                        help="two or more builds: a name and the build's python folder")
    parser.add_argument("--datasets", nargs="+", default=["head", "stent", "concrete"])
    parser.add_argument("--sizes", nargs="+", type=int, default=[512, 1024])
    parser.add_argument("--ref-spp", type=int, default=64,
                        help="the cached passes' reference (benchmark_denoiser.py's; default 64)")
    parser.add_argument("--rounds", type=int, default=7, help="rounds of every build (default 7)")
    parser.add_argument("--repeats", type=int, default=5,
                        help="timed denoises per process, after a warm-up (default 5)")
    parser.add_argument("--levels", type=int, default=0,
                        help="grid levels (default 0: the model's default for the size)")
    parser.add_argument("--cache", type=Path,
                        default=Path(os.environ.get("PTV_CACHE_DIR", ROOT / ".cache")) / "bench")
    parser.add_argument("--json", type=Path, default=None, help="write every round as JSON")
    parser.add_argument("--one", nargs=3, metavar=("DATASET", "SIZE", "IMAGE"),
                        help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if not args.one and len(args.builds) < 2:
        parser.error("--builds needs at least two builds")
    return args


def builds_of(specs: List[str]) -> List[Tuple[str, str]]:
    """[(name, python folder)] from NAME=PYTHONPATH arguments."""
    out = []
    for spec in specs:
        name, sep, path = spec.partition("=")
        if not sep or not name or not Path(path).is_dir():
            raise SystemExit(f"--builds: '{spec}' is not NAME=<an existing build/python folder>")
        out.append((name, str(Path(path).resolve())))
    return out


def run_one(args: argparse.Namespace) -> None:
    """In a build's own process: time its denoiser on the cached passes; JSON on stdout."""
    import numpy as np

    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import ptvbench as pb

    dataset, size, image_path = args.one[0], int(args.one[1]), Path(args.one[2])
    passes = pb.bench_passes(dataset, size, args.ref_spp, args.cache)
    row = pb.run_ours(passes, args.levels, "", args.repeats)
    np.save(image_path, row["image"])
    print(json.dumps({"ms": row["ms"], **{k: row[k] for k in STAGES},
                      "kernels": row["kernels"]}))


def main() -> None:
    args = parse_args()
    if args.one:
        run_one(args)
        return
    import numpy as np

    builds = builds_of(args.builds)
    rounds: Dict[str, Dict[str, List[dict]]] = {}
    images = args.cache / "compare_builds"
    images.mkdir(parents=True, exist_ok=True)
    common = [sys.executable, __file__, "--builds", *args.builds, "--ref-spp", str(args.ref_spp),
              "--repeats", str(args.repeats), "--levels", str(args.levels),
              "--cache", str(args.cache)]
    cells = [(d, s) for s in args.sizes for d in args.datasets]
    bar = tqdm(total=len(cells) * args.rounds * len(builds), desc="denoises", unit="process")
    for dataset, size in cells:
        key = f"{dataset} {size}²"
        rounds[key] = {name: [] for name, _ in builds}
        for r in range(args.rounds):
            order = builds if r % 2 == 0 else builds[::-1]
            for name, path in order:
                image = images / f"{dataset}_{size}_{name}.npy"
                # A build outside this tree finds the datasets through PTV_SOURCE_DIR.
                env = dict(os.environ, PYTHONPATH=path, PTV_SOURCE_DIR=str(ROOT))
                done = subprocess.run([*common, "--one", dataset, str(size), str(image)], env=env,
                                      capture_output=True, text=True)
                if done.returncode != 0:
                    raise SystemExit(f"build {name} failed on {key}:\n{done.stderr[-2000:]}")
                rounds[key][name].append(json.loads(done.stdout.strip().splitlines()[-1]))
                bar.update(1)
    bar.close()

    first = builds[0][0]
    lines = ["| image | build | denoise ms | " + " | ".join(STAGES) + f" | ratio to {first} "
             "| largest image difference |", "|---|---|---|" + "---|" * len(STAGES) + "---|---|"]
    for dataset, size in cells:
        key = f"{dataset} {size}²"
        base = np.load(images / f"{dataset}_{size}_{first}.npy")
        for name, _ in builds:
            rows = rounds[key][name]
            median = {k: statistics.median(row[k] for row in rows) for k in ("ms", *STAGES)}
            ratio = statistics.median(a["ms"] / b["ms"] for a, b in zip(rows, rounds[key][first]))
            diff = float(np.abs(np.load(images / f"{dataset}_{size}_{name}.npy") - base).max())
            lines.append(f"| {key} | {name} | {median['ms']:.1f} | "
                         + " | ".join(f"{median[k]:.1f}" for k in STAGES)
                         + f" | {ratio:.3f} | {diff:.3g} |")
    print("\n".join(lines))
    if args.json:
        args.json.write_text(json.dumps(rounds, indent=1))


if __name__ == "__main__":
    main()
