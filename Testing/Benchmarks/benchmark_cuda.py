#!/usr/bin/env python3
"""Benchmark: ms per 1-spp frame at 1024² for the CPU and CUDA backends (trace) and the denoiser.

Prints "skipped: no CUDA device (<why>)" and exits 0 where this build has no CUDA path or the
machine no usable device. Median of --repeats fresh frames (the seed changes before each).
"""
from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.append(str(ROOT / "Testing" / "Benchmarks"))
sys.path.append(str(ROOT / "Python"))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dataset", default="head")
    parser.add_argument("--size", type=int, default=1024)
    parser.add_argument("--repeats", type=int, default=10)
    args = parser.parse_args()

    from pathtracedvolume import vtkPathTracedVolumeMapper
    if not vtkPathTracedVolumeMapper.GetCudaAvailable():
        print(f"skipped: no CUDA device ({vtkPathTracedVolumeMapper.GetCudaStatus()})")
        return 0
    import benchmark_tracer

    window, volume, ours, _ = benchmark_tracer.build_scene(args.dataset, args.size)
    volume.SetMapper(ours)
    print(f"CUDA: {vtkPathTracedVolumeMapper.GetCudaStatus()}")
    rows = {}
    for backend, name in ((ours.BACKEND_CPU, "CPU"), (ours.BACKEND_CUDA, "CUDA")):
        ours.SetBackend(backend)
        trace, denoise = [], []
        for denoise_on in (False, True):
            ours.SetDenoise(denoise_on)
            for i in range(args.repeats + 1):
                ours.SetSeed(1000 * (backend + 1) + 10 * i + denoise_on)
                window.Render()
                if i == 0:
                    continue  # warm-up
                (denoise if denoise_on else trace).append(
                    ours.GetStatistics().GetLastDenoiseTime() if denoise_on else ours.GetStatistics().GetLastTraceTime())
        assert ours.GetActiveBackend() == name, ours.GetActiveBackend()
        rows[name] = (statistics.median(trace), statistics.median(denoise))
    print(f"| backend | trace ms ({args.size}², 1 spp) | denoise ms |")
    print("|---|---|---|")
    for name, (t, d) in rows.items():
        print(f"| {name} | {t:.1f} | {d:.1f} |")
    print(f"CUDA trace speed-up over CPU: {rows['CPU'][0] / rows['CUDA'][0]:.1f}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
