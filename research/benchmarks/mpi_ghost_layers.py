#!/usr/bin/env python3
"""Study: a volume split across MPI ranks -- how much the ghost layers matter, and what the
split costs per frame.

``mpirun -np N pvbatch Testing/ParaView/mpi_render.py --replicate-limit 0 --ghost-layers G``
(the head CT, which ParaView splits along y, front to back in the front view, so every ray
crosses a piece boundary) for N in --ranks and G in --ghosts, against one rank at the same
samples (--frames x --spp-per-frame) and a reference of --ref-spp samples traced with another
seed. Per row: PSNR of rank 0's Radiance pass against the reference and its difference to one
rank (negative: what the rays beyond the ghost layer -- shadows and occlusion -- are missing),
rank 0's voxels with ghosts over its own voxels (memory), and the wall time of the frames after
the first (trace + gather + composite + draw; the machine has 2 cores, so 4 ranks are
oversubscribed). Run it on an idle machine for the times (docs/measuring.md).
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Dict, List

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "Testing" / "ParaView"))
sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.append(str(ROOT / "Python"))
from mpi_replicated import radiance  # noqa: E402
from ptvbench import save_results  # noqa: E402
from pathtracedvolume.metrics import psnr  # noqa: E402


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=128)
    parser.add_argument("--frames", type=int, default=32)
    parser.add_argument("--spp-per-frame", type=int, default=8)
    parser.add_argument("--ref-spp", type=int, default=2048, help="reference samples (x 32/frame)")
    parser.add_argument("--ranks", type=int, nargs="+", default=[2, 4])
    parser.add_argument("--ghosts", type=int, nargs="+", default=[0, 2, 4, 8, 16, 32])
    parser.add_argument("--json", type=Path, default=None, help="write the rows as JSON")
    parser.add_argument("--markdown", type=Path, default=None, help="write the table")
    return parser.parse_args()


# What mpi_render.py needs (ctest's environment), defaulting to this checkout's build.
for key, value in (("PTV_SOURCE_DIR", ROOT), ("PTV_CACHE_DIR", ROOT / ".cache"),
                   ("PTV_PLUGIN", ROOT / "build/lib/paraview-5.11/plugins/PathTracedVolume/"
                    "PathTracedVolume.so"), ("PROTOCOL_BUFFERS_PYTHON_IMPLEMENTATION", "python")):
    os.environ.setdefault(key, str(value))


def run(ranks: int, out: Path, size: int, *args: str) -> Dict:
    cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks), "pvbatch",
           "--force-offscreen-rendering", str(ROOT / "Testing/ParaView/mpi_render.py"),
           "--out", str(out), "--size", str(size), *args]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=1800)
    if done.returncode != 0:
        print(done.stdout + done.stderr)
        raise SystemExit(f"{' '.join(cmd)} exited with {done.returncode}")
    return json.loads((out / "info.json").read_text())


def voxels(extent: List[int]) -> int:
    n = 1
    for a in range(3):
        n *= max(extent[2 * a + 1] - extent[2 * a] + 1, 0)
    return n


def main() -> int:
    args = parse_args()
    tmp = Path(tempfile.mkdtemp(prefix="ghosts_"))
    samples = ("--frames", str(args.frames), "--spp-per-frame", str(args.spp_per_frame))
    print(f"reference: {args.ref_spp} spp", flush=True)
    run(1, tmp / "ref", args.size, "--frames", str(max(1, args.ref_spp // 32)),
        "--spp-per-frame", "32", "--seed", "7")
    ref = radiance(tmp / "ref" / "passes.exr")
    one = run(1, tmp / "one", args.size, *samples)
    base = psnr(ref, radiance(tmp / "one" / "passes.exr"))
    rows = [{"ranks": 1, "ghosts": None, "psnr": base, "delta": 0.0, "memory": 1.0,
             "seconds": one["seconds_after_first"]}]
    for ranks in args.ranks:
        for ghosts in args.ghosts:
            name = f"r{ranks}_g{ghosts}"
            info = run(ranks, tmp / name, args.size, *samples, "--replicate-limit", "0",
                       "--ghost-layers", str(ghosts))
            value = psnr(ref, radiance(tmp / name / "passes.exr"))
            rank0 = info["rank0"]
            rows.append({"ranks": ranks, "ghosts": ghosts, "psnr": value, "delta": value - base,
                         "memory": voxels(rank0["input_extent"]) / voxels(rank0["piece_extent"]),
                         "seconds": info["seconds_after_first"]})
            print(rows[-1], flush=True)
    spp = args.frames * args.spp_per_frame
    lines = [f"{args.size}^2, {spp} spp ({args.frames} frames x {args.spp_per_frame}), "
             f"head CT front view, PSNR of rank 0's Radiance against a {args.ref_spp}-spp "
             "1-rank reference (another seed); memory: rank 0's voxels with ghosts / its own; "
             f"time: the {args.frames - 1} frames after the first (2 cores: 4 ranks share them)",
             "",
             "| ranks | GhostLayers | PSNR (dB) | vs 1 rank (dB) | memory | time (s) |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        ghosts = "-" if r["ghosts"] is None else str(r["ghosts"])
        lines.append(f"| {r['ranks']} | {ghosts} | {r['psnr']:.2f} | {r['delta']:+.2f} | "
                     f"{r['memory']:.3f} | {r['seconds']:.2f} |")
    save_results(rows, "\n".join(lines), args.json, args.markdown,
                 "Split volume: ghost layers", "mpi_ghost_layers.py")
    return 0


if __name__ == "__main__":
    sys.exit(main())
