"""A split volume's composite: bytes each rank receives per sample and time per composite
against the rank count.

Runs ``mpirun -np N ptvMpiTests --traffic SIZE REPEATS`` (Testing/Cxx/TestPTVRanksMPI.cxx) for
every N, in interleaved rounds: every rank composites a SIZE x SIZE frame of its piece's default
traced passes (16 floats a pixel) by direct send, REPEATS times; the figures are the medians over
the rounds of each run's median time and the bytes rank 0 and the busiest other rank received
from the others in one composite, also as multiples of one image's passes. Oversubscribed ranks
share the machine's cores, so times grow with N here for that reason as well.

Example (docs/parallel.md)::

    .venv/bin/python Testing/Benchmarks/split_composite.py --ranks 2 4 8 --size 512
"""
from __future__ import annotations

import argparse
import json
import statistics
import subprocess
from pathlib import Path
from typing import Dict, List

from tqdm import tqdm

ROOT = Path(__file__).resolve().parents[2]
FLOATS_PER_PIXEL = 16  # Radiance 3, Alpha, Albedo 3, Depth, Position 3, Normal 3, Coverage, Footprint


def run(ranks: int, size: int, repeats: int, binary: Path) -> Dict[str, object]:
    """One mpirun of the benchmark; its JSON line."""
    command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks), str(binary),
               "--traffic", str(size), str(repeats)]
    out = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    return json.loads([line for line in out.splitlines() if line.startswith("{")][-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--ranks", type=int, nargs="+", default=[2, 4, 8])
    parser.add_argument("--size", type=int, default=512, help="image width and height")
    parser.add_argument("--repeats", type=int, default=9, help="composites per run")
    parser.add_argument("--rounds", type=int, default=3, help="interleaved rounds")
    parser.add_argument("--binary", type=Path, default=ROOT / "build" / "bin" / "ptvMpiTests")
    args = parser.parse_args()

    results: Dict[int, List[Dict[str, object]]] = {n: [] for n in args.ranks}
    for _ in tqdm(range(args.rounds), desc="rounds"):
        for n in args.ranks:
            results[n].append(run(n, args.size, args.repeats, args.binary))
    image = 4.0 * FLOATS_PER_PIXEL * args.size * args.size
    print(f"{args.size}^2, one image's passes = {image / 2**20:.2f} MiB")
    print("| ranks | rank 0 receives | busiest other rank | a gather on rank 0 would receive "
          "| composite time |")
    print("|---|---|---|---|---|")
    for n in args.ranks:
        rank0 = statistics.median(r["bytes_received"][0] for r in results[n])
        other = statistics.median(max(r["bytes_received"][1:]) for r in results[n])
        ms = statistics.median(r["median_ms"] for r in results[n])
        print(f"| {n} | {rank0 / 2**20:.2f} MiB ({rank0 / image:.2f} images) "
              f"| {other / 2**20:.2f} MiB ({other / image:.2f}) "
              f"| {(n - 1) * image / 2**20:.2f} MiB ({n - 1}) | {ms:.1f} ms |")


if __name__ == "__main__":
    main()
