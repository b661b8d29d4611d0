"""Big volumes: extra memory and frame times against the volume's size, ours and VTK's ray caster.

The concrete micro-CT (100³, unsigned 16-bit) is tiled to N³ in its own type. Each (mapper, N)
runs in its own process: it builds the volume, resets its peak resident set (``clear_refs``),
renders a 512² view with the dataset's paper preset, then ``--later`` more renders while the
camera turns one degree a render. Reported: the extra peak resident memory over what the process
held with the volume built (``VmHWM`` after the reset minus ``VmRSS`` before it), the first
render's wall time and the median of the later ones. The path tracer traces one denoised frame a
render (still renders not converged), the stock ``vtkFixedPointVolumeRayCastMapper`` casts its
image; the methods alternate within each N.

Example (issue #62's table)::

    PYTHONPATH=build/python xvfb-run -a .venv/bin/python Testing/Benchmarks/volume_memory.py \\
        --sizes 256 512 768
"""
from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Dict, List

ROOT = Path(__file__).resolve().parents[2]
MAPPERS = ("pathtraced", "stock")
MIB = 2.0 ** 20


def status_bytes(field: str) -> int:
    """A ``/proc/self/status`` memory field (``VmRSS``, ``VmHWM``) in bytes."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith(field + ":"):
            return int(line.split()[1]) * 1024
    raise RuntimeError(f"no {field} in /proc/self/status")


def tiled_concrete(n: int):
    """The concrete tiled to n³ in its own type, built slab by slab (no temporary of its size)."""
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkCommonDataModel import vtkImageData

    from pathtracedvolume.scene import load_dataset

    block = load_dataset("concrete")
    scalars = block.GetPointData().GetScalars()
    dims = block.GetDimensions()
    cube = vtk_to_numpy(scalars).reshape(dims[2], dims[1], dims[0])  # z, y, x
    out = np.empty((n, n, n), dtype=cube.dtype)
    for z0 in range(0, n, dims[2]):
        for y0 in range(0, n, dims[1]):
            for x0 in range(0, n, dims[0]):
                part = out[z0:z0 + dims[2], y0:y0 + dims[1], x0:x0 + dims[0]]
                part[...] = cube[:part.shape[0], :part.shape[1], :part.shape[2]]
    image = vtkImageData()
    image.SetDimensions(n, n, n)
    image.SetSpacing(block.GetSpacing())
    array = numpy_to_vtk(out.reshape(-1), deep=0)
    array.SetName(scalars.GetName() or "scalars")
    image.GetPointData().SetScalars(array)
    image.keep_alive = out  # numpy_to_vtk(deep=0) borrows the buffer
    return image


def measure_one(mapper: str, n: int, size: int, later: int) -> Dict[str, float]:
    """One (mapper, n) run in this process; see the module docstring."""
    if str(ROOT / "Python") not in sys.path:
        sys.path.append(str(ROOT / "Python"))
    from pathtracedvolume.scene import Scene, paper_preset, volume_property

    image = tiled_concrete(n)
    scene = Scene(image, volume_property(paper_preset("concrete")), (size, size),
                  azimuth=30.0, elevation=10.0, mapper=mapper)
    held = status_bytes("VmRSS")
    Path("/proc/self/clear_refs").write_text("5")  # VmHWM := VmRSS
    start = time.perf_counter()
    scene.window.Render()
    first = time.perf_counter() - start
    times: List[float] = []
    for k in range(later):
        scene.view(azimuth=31.0 + k, elevation=10.0)
        start = time.perf_counter()
        scene.window.Render()
        times.append(time.perf_counter() - start)
    return {"input": float(image.GetPointData().GetScalars().GetNumberOfValues() * 2),
            "extra": float(status_bytes("VmHWM") - held), "first": first,
            "later": statistics.median(times) if times else float("nan")}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[256, 512, 768],
                        help="volume edge lengths N (default 256 512 768)")
    parser.add_argument("--view", type=int, default=512, help="view size (default 512)")
    parser.add_argument("--later", type=int, default=4,
                        help="renders after the first, camera turning (default 4)")
    parser.add_argument("--json", type=Path, help="also write the rows here")
    parser.add_argument("--one", nargs=2, metavar=("MAPPER", "N"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one:
        print(json.dumps(measure_one(args.one[0], int(args.one[1]), args.view, args.later)))
        return

    rows: List[Dict[str, float]] = []
    for n in args.sizes:
        row: Dict[str, float] = {"n": n}
        for mapper in MAPPERS:  # alternating, each in a fresh process
            command = [sys.executable, __file__, "--one", mapper, str(n), "--view",
                       str(args.view), "--later", str(args.later)]
            out = subprocess.run(command, check=True, capture_output=True, text=True).stdout
            result = json.loads(out.strip().splitlines()[-1])
            row["input"] = result["input"]
            for key in ("extra", "first", "later"):
                row[f"{mapper}_{key}"] = result[key]
        rows.append(row)
        print(f"N={n}: input {row['input'] / MIB:.0f} MiB; extra ours "
              f"{row['pathtraced_extra'] / MIB:.0f} MiB, stock {row['stock_extra'] / MIB:.0f} MiB;"
              f" first frame ours {row['pathtraced_first']:.2f} s, stock "
              f"{row['stock_first']:.2f} s; later ours {row['pathtraced_later']:.3f} s, stock "
              f"{row['stock_later']:.3f} s", flush=True)
    print("\n| N | input | ours extra | stock extra | ours first frame | stock first frame "
          "| later frames ours / stock |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['n']} | {r['input'] / MIB:.0f} MiB | {r['pathtraced_extra'] / MIB:.0f} MiB "
              f"({r['pathtraced_extra'] / r['input']:.2f}x) | {r['stock_extra'] / MIB:.0f} MiB "
              f"({r['stock_extra'] / r['input']:.2f}x) | {r['pathtraced_first']:.2f} s | "
              f"{r['stock_first']:.2f} s | {r['pathtraced_later']:.3f} / "
              f"{r['stock_later']:.3f} s |")
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
