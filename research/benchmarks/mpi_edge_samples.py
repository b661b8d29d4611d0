#!/usr/bin/env python3
"""Benchmark: edge samples on a volume split across MPI ranks (DistributedVolume), quality and cost.

``mpirun -np N pvbatch Testing/ParaView/mpi_render.py`` (the head CT as "Path Traced Volume",
two-band preset, front view, Denoise on, the shipped model) for 1 rank with the whole volume and
2 ranks each with its piece (ReplicateVolumeLimit 0), with EdgeSamples 1 (none) and the default:

* quality: PSNR of the Denoised pass of one 1-spp frame (seeds 1..--seeds) against a 2048-spp
  1-rank reference (seed 7) through the same denoiser, mean over the seeds;
* cost: the wall time per frame of --frames frames after the first (each traced, composited,
  denoised and shown), median of --repeats interleaved rounds.

Run it on an idle machine (docs/measuring.md).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Dict, List, Tuple

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "Testing/ParaView"))
sys.path.append(str(ROOT / "Python"))
from pathtracedvolume.atomic import write_text  # noqa: E402

# (ranks, split, edge samples: None = the representation's default)
CONFIGS: List[Tuple[int, bool, int | None]] = [(1, False, 1), (1, False, None), (2, True, 1),
                                               (2, True, None)]


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--frames", type=int, default=17, help="frames per timed run")
    parser.add_argument("--repeats", type=int, default=3, help="timed rounds (default 3)")
    parser.add_argument("--seeds", type=int, default=3, help="1-spp frames per configuration")
    parser.add_argument("--json", type=Path, default=None, help="write the rows as JSON")
    parser.add_argument("--markdown", type=Path, default=None, help="write the table")
    return parser.parse_args()


def render(out: Path, ranks: int, size: int, *args: str) -> Dict:
    """One mpi_render.py run into @a out; its info.json."""
    cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "--bind-to", "none", "-np",
           str(ranks), "pvbatch", "--force-offscreen-rendering",
           str(ROOT / "Testing/ParaView/mpi_render.py"), "--out", str(out), "--size", str(size),
           "--denoise", "1", *args]
    env = dict(os.environ)  # what ctest gives the ParaView tests, unless already set
    env.setdefault("PTV_SOURCE_DIR", str(ROOT))
    env.setdefault("PTV_CACHE_DIR", str(ROOT / ".cache"))
    env.setdefault("PTV_PLUGIN", str(ROOT / "build/lib/paraview-5.11/plugins/PathTracedVolume/"
                                          "PathTracedVolume.so"))
    env.setdefault("PROTOCOL_BUFFERS_PYTHON_IMPLEMENTATION", "python")
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=1800, env=env)
    if done.returncode != 0:
        print(done.stdout + done.stderr)
        raise SystemExit(f"{' '.join(cmd)} exited with {done.returncode}")
    return json.loads((out / "info.json").read_text())


def config_args(split: bool, edges: int | None) -> List[str]:
    args = ["--replicate-limit", "0"] if split else []
    return args + (["--edge-samples", str(edges)] if edges is not None else [])


def name(config: Tuple[int, bool, int | None]) -> str:
    ranks, split, edges = config
    return (f"{ranks} rank{'s' if ranks > 1 else ''}{', split' if split else ''}, "
            f"EdgeSamples {'default' if edges is None else edges}")


def main() -> int:
    from mpi_distributed import denoised
    from pathtracedvolume.metrics import psnr

    args = parse_args()
    tmp = Path(tempfile.mkdtemp(prefix="mpi_edges_"))
    print("reference (1 rank, 2048 spp) ...", flush=True)
    render(tmp / "reference", 1, args.size, "--frames", "64", "--spp-per-frame", "32", "--seed",
           "7")
    ref = denoised(tmp / "reference" / "passes.exr")
    quality: Dict[Tuple, List[float]] = {c: [] for c in CONFIGS}
    fractions: Dict[Tuple, List[float]] = {c: [] for c in CONFIGS}
    for seed in range(1, args.seeds + 1):
        for config in CONFIGS:
            out = tmp / f"q_{config[0]}_{config[1]}_{config[2]}_{seed}"
            info = render(out, config[0], args.size, "--frames", "1", "--seed", str(seed),
                          *config_args(config[1], config[2]))
            quality[config].append(psnr(ref, denoised(out / "passes.exr")))
            fractions[config].append(info["rank0"]["edge_fraction"])
            print(f"seed {seed}: {name(config)}: {quality[config][-1]:.2f} dB", flush=True)
    times: Dict[Tuple, List[float]] = {c: [] for c in CONFIGS}
    for r in range(args.repeats):
        for config in CONFIGS:
            info = render(tmp / "t", config[0], args.size, "--frames", str(args.frames),
                          *config_args(config[1], config[2]))
            times[config].append(info["seconds_after_first"] / (args.frames - 1))
            print(f"round {r + 1}: {name(config)}: {1000 * times[config][-1]:.1f} ms / frame",
                  flush=True)
    rows = []
    for config in CONFIGS:
        without = (config[0], config[1], 1)
        rows.append({"ranks": config[0], "split": config[1],
                     "edge_samples": config[2] if config[2] is not None else "default",
                     "psnr_db": statistics.mean(quality[config]),
                     "gain_db": statistics.mean(quality[config]) - statistics.mean(quality[without]),
                     "edge_fraction": statistics.mean(fractions[config]),
                     "ms_per_frame": 1000 * statistics.median(times[config]),
                     "time_vs_without": statistics.median(
                         a / b for a, b in zip(times[config], times[without])),
                     "size": args.size, "seeds": args.seeds})
    lines = [f"{os.cpu_count()} cores; {args.size}^2, the head CT, front view, Denoise on (shipped "
             f"model); PSNR of one denoised 1-spp frame against a 2048-spp 1-rank reference, mean "
             f"of seeds 1-{args.seeds}; time per frame of {args.frames - 1} frames after the first "
             f"(trace, composite, denoise, show), median of {args.repeats} interleaved rounds; "
             "mpirun --bind-to none",
             "| ranks | edge samples | PSNR (dB) | gain (dB) | edge pixels | ms / frame | time vs "
             "without |", "|---|---|---|---|---|---|---|"]
    for row in rows:
        lines.append(f"| {row['ranks']}{' split' if row['split'] else ''} | "
                     f"{row['edge_samples']} | {row['psnr_db']:.2f} | {row['gain_db']:+.2f} | "
                     f"{100 * row['edge_fraction']:.2f} % | {row['ms_per_frame']:.1f} | "
                     f"{row['time_vs_without']:.2f} |")
    print("\n".join(lines))
    if args.json:
        write_text(args.json, json.dumps(rows, indent=2))
    if args.markdown:
        command = ("PYTHONPATH=build/python xvfb-run -a -s \"-screen 0 1024x768x24 -noreset\" "
                   ".venv/bin/python research/benchmarks/mpi_edge_samples.py --json ... "
                   "--markdown ...")
        write_text(args.markdown, "# Edge samples on a split volume\n\nCommand (idle machine): `"
                   + command + "`\n\n" + "\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
