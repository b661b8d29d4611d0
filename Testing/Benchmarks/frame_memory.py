"""Memory per pixel: peak resident memory of one render against the window size.

Each (mapper, size) runs in its own process: it loads the head with its paper preset, opens an
offscreen window of size x size, renders once and reports its peak resident set (``VmHWM``).
The slope of a least-squares line through the peaks over the sizes is the memory one more pixel
costs (bytes per pixel), the window's own buffers included; the stock
``vtkFixedPointVolumeRayCastMapper`` in the same window gives the comparison. ``--still`` makes the
path tracer's render a converging still render (the default for a script's ``Render()``) instead
of one frame.

Example (docs/reliability.md, "Costs")::

    PYTHONPATH=build/python xvfb-run -a .venv/bin/python Testing/Benchmarks/frame_memory.py \\
        --sizes 256 512 1024 2048
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path
from typing import Dict, List

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
MAPPERS = ("pathtraced", "stock")


def peak_resident_bytes() -> int:
    """This process's peak resident set (VmHWM) in bytes."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) * 1024
    raise RuntimeError("no VmHWM in /proc/self/status")


def measure_one(mapper: str, size: int, still: bool, dolly: float) -> Dict[str, float]:
    """Renders the head once at size x size with ``mapper``; the peak memory, seconds and the
    share of the window the volume's bounding rectangle covers (the path tracer's display
    textures are that rectangle's)."""
    if str(ROOT / "Python") not in sys.path:
        sys.path.append(str(ROOT / "Python"))
    from pathtracedvolume.scene import Scene

    scene = Scene.of_dataset("head", (size, size), azimuth=30.0, elevation=10.0, mapper=mapper)
    scene.view(30.0, 10.0, dolly)
    if mapper == "pathtraced" and still:
        scene.mapper.ConvergeStillRendersOn()
    start = time.perf_counter()
    scene.window.Render()
    seconds = time.perf_counter() - start
    covered = float("nan")
    if mapper == "pathtraced":
        alpha = scene.get_pass("Alpha").reshape(size, size)
        rows, cols = np.nonzero(alpha > 0)
        covered = 0.0 if rows.size == 0 else float(
            (np.ptp(rows) + 1) * (np.ptp(cols) + 1)) / float(size * size)
    return {"peak": float(peak_resident_bytes()), "seconds": seconds, "covered": covered}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[256, 512, 1024, 2048],
                        help="window sizes (square; default 256 512 1024 2048)")
    parser.add_argument("--still", action="store_true",
                        help="the path tracer converges a still render instead of one frame")
    parser.add_argument("--dolly", type=float, default=1.0,
                        help="camera dolly (default 1; larger fills more of the window)")
    parser.add_argument("--one", nargs=2, metavar=("MAPPER", "SIZE"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one:
        print(json.dumps(measure_one(args.one[0], int(args.one[1]), args.still, args.dolly)))
        return
    if len(args.sizes) < 2:
        parser.error("--sizes needs at least two sizes for a slope")

    rows: Dict[str, List[Dict[str, float]]] = {m: [] for m in MAPPERS}
    for size in args.sizes:
        for mapper in MAPPERS:  # interleaved, each in a fresh process
            command = [sys.executable, __file__, "--one", mapper, str(size), "--dolly",
                       str(args.dolly)]
            if args.still:
                command.append("--still")
            out = subprocess.run(command, check=True, capture_output=True, text=True).stdout
            row = json.loads(out.strip().splitlines()[-1])
            row["size"] = size
            rows[mapper].append(row)
            print(f"{mapper:10s} {size:5d}^2  peak {row['peak'] / 2**20:8.1f} MiB"
                  f"  render {row['seconds']:6.2f} s  covered {row['covered']:.2f}", flush=True)
    for mapper in MAPPERS:
        pixels = np.array([r["size"] ** 2 for r in rows[mapper]], dtype=float)
        peaks = np.array([r["peak"] for r in rows[mapper]])
        slope, intercept = np.polyfit(pixels, peaks, 1)
        print(f"{mapper}: {slope:.0f} bytes per pixel (peak = {intercept / 2**20:.0f} MiB"
              f" + {slope:.0f} B x pixels)")


if __name__ == "__main__":
    main()
