#!/usr/bin/env python3
"""Benchmark: samples per second of ParaView's parallel engine with the plugin, 1 vs N ranks.

``mpirun -np N pvbatch Testing/ParaView/mpi_render.py`` (the head CT as "Path Traced Volume",
two-band preset, front view, Denoise off, --size, --frames frames of 1 spp) for each
configuration (ranks x threads per rank), in interleaved rounds (each round runs every
configuration once, so a slow spell of this shared machine slows all of them alike). The time is
the wall time of the frames after the first one (pvbatch's Render, which traces, averages over
the ranks, shows and composites); samples per second = ranks x size^2 x frames / time. Ratios
are medians of per-round ratios. Run it on an idle machine (docs/measuring.md).
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
sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.append(str(ROOT / "Python"))
from pathtracedvolume.atomic import write_text  # noqa: E402

# (ranks, threads per rank (0: the plugin's choice), mpirun's binding): mpirun binds each rank to
# one core by default, so one rank uses one core whatever its threads; "--bind-to none" lets the
# plugin share the host's cores between its ranks.
CONFIGS: List[Tuple[int, int, str]] = [(1, 0, "core"), (2, 0, "core"), (1, 0, "none"),
                                       (2, 0, "none")]


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--frames", type=int, default=17, help="frames per run (default 17)")
    parser.add_argument("--repeats", type=int, default=3, help="rounds (default 3)")
    parser.add_argument("--json", type=Path, default=None, help="write the rows as JSON")
    parser.add_argument("--markdown", type=Path, default=None, help="write the table")
    return parser.parse_args()


def run(ranks: int, threads: int, bind: str, size: int, frames: int) -> float:
    """Seconds of the frames after the first in one mpi_render.py run."""
    with tempfile.TemporaryDirectory() as out:
        cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "--bind-to", bind, "-np",
               str(ranks), "pvbatch",
               "--force-offscreen-rendering", str(ROOT / "Testing/ParaView/mpi_render.py"),
               "--out", out, "--size", str(size), "--frames", str(frames),
               "--threads", str(threads)]
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
        if done.returncode != 0:
            print(done.stdout + done.stderr)
            raise SystemExit(f"{' '.join(cmd)} exited with {done.returncode}")
        return float(json.loads(Path(out, "info.json").read_text())["seconds_after_first"])


def main() -> int:
    args = parse_args()
    env = dict(os.environ)
    env.setdefault("PTV_SOURCE_DIR", str(ROOT))
    times: Dict[Tuple[int, int, str], List[float]] = {c: [] for c in CONFIGS}
    for r in range(args.repeats):
        for config in CONFIGS:
            times[config].append(run(*config, args.size, args.frames))
            print(f"round {r + 1}: {config}: {times[config][-1]:.2f} s", flush=True)
    samples = args.size * args.size * (args.frames - 1)
    rows = []
    for ranks, threads, bind in CONFIGS:
        t = times[(ranks, threads, bind)]
        one = times[(1, threads, bind)]  # one rank with the same binding, same rounds
        rows.append({"ranks": ranks, "threads_per_rank": threads, "bind": bind,
                     "seconds": statistics.median(t),
                     "msamples_per_s": ranks * samples / statistics.median(t) / 1e6,
                     "speedup_vs_1_rank": statistics.median(ranks * b / a for a, b in zip(t, one)),
                     "size": args.size, "frames": args.frames - 1})
    lines = [f"{os.cpu_count()} cores; {args.size}^2, {args.frames - 1} timed frames of 1 spp per "
             f"rank, Denoise off, NumberOfThreads 0 (the plugin's choice: the rank's cores, the "
             f"host's shared by its ranks); median of {args.repeats} interleaved rounds",
             "| mpirun binding | ranks | s | Msamples/s | speed-up vs 1 rank (same binding) |",
             "|---|---|---|---|---|"]
    for row in rows:
        lines.append(f"| --bind-to {row['bind']} | {row['ranks']} | {row['seconds']:.2f} | "
                     f"{row['msamples_per_s']:.2f} | {row['speedup_vs_1_rank']:.2f} |")
    print("\n".join(lines))
    if args.json:
        write_text(args.json, json.dumps(rows, indent=2))
    if args.markdown:
        command = ("PYTHONPATH=build/python xvfb-run -a -s \"-screen 0 1024x768x24 -noreset\" "
                   ".venv/bin/python Testing/Benchmarks/benchmark_mpi.py --json ... --markdown ...")
        write_text(args.markdown, "# MPI benchmark\n\nCommand (idle machine): `" + command +
                   "`\n\n" + "\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
