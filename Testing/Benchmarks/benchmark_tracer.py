#!/usr/bin/env python3
"""Benchmark: 1-spp frame time of vtkPathTracedVolumeMapper vs VTK's vtkFixedPointVolumeRayCastMapper.

For every dataset and image size, both mappers render the same volume, transfer function (the
dataset's two-band preset), shading and camera in the same run. Each figure is the median of
--repeats timed rounds after one warm-up round. Our frames are forced to be fresh 1-spp frames by
changing the seed before each render (an unchanged view would only accumulate). Every figure
is taken in interleaved rounds (see measure()), so a slow spell of the shared machine slows all
of them alike, and ratios are medians of per-round ratios.

Our mapper runs with Denoise off for the comparison (the denoiser is measured by
benchmark_denoiser.py). Reported per row: whole-render time of each mapper (window.Render(), so
both include drawing), our trace time alone, samples (pixels) per second, the ratio ours/stock,
our 1- vs 2-thread trace times (scaling), the trace time of the portable baseline build
(PTV_PORTABLE_KERNELS=1) against the dispatched one, and end to end: a fresh 1-spp frame traced,
denoised (the shipped model) and displayed, as milliseconds and frames per second, with the
mapper's EdgeSamples (what a denoised frame traces) and, in the same rounds, without them.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ptvbench as pb  # noqa: E402  (appends <repo>/Python after PYTHONPATH)

from pathtracedvolume.atomic import write_text  # noqa: E402
from tqdm import tqdm  # noqa: E402


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--datasets", nargs="+", default=["head", "stent", "concrete"])
    parser.add_argument("--sizes", nargs="+", type=int, default=[256, 512, 1024])
    parser.add_argument("--repeats", type=int, default=5, help="timed renders per figure")
    parser.add_argument("--json", type=Path, default=None, help="also write the rows as JSON")
    return parser.parse_args()


def build_scene(dataset: str, size: int):
    """The dataset (paper preset, pathtracedvolume.scene's camera at azimuth 30) with the stock
    mapper on the volume, and our mapper (one frame per Render, Denoise off: the tracer against
    the stock mapper; the denoiser has its own benchmark) on the same data to swap in."""
    from pathtracedvolume import vtkPathTracedVolumeMapper
    from pathtracedvolume.scene import Scene

    scene = Scene.of_dataset(dataset, (size, size), azimuth=30, mapper="stock",
                             background=(0.3, 0.3, 0.35))
    stock = scene.mapper
    stock.SetAutoAdjustSampleDistances(0)  # full quality, as ours
    ours = vtkPathTracedVolumeMapper()
    ours.ConvergeStillRendersOff()
    ours.DenoiseOff()
    ours.SetInputData(stock.GetInput())
    return scene.window, scene.volume, ours, stock


def measure(dataset: str, size: int, repeats: int) -> dict:
    """Every figure in interleaved rounds (one warm-up round, then --repeats timed ones): per
    round the stock render, then our fresh frames with every core, 2 and 1 threads, the portable
    build and with the denoiser, so that a slow spell of the shared machine slows all of them
    alike; ratios are the median of the rounds' ratios. Each mapper renders once untimed after
    it is swapped in."""
    window, volume, ours, stock = build_scene(dataset, size)
    seed = [0]

    def render_ours(threads: int, portable: bool = False) -> dict:
        """A fresh frame; threads 0 = every core."""
        seed[0] += 1
        ours.SetSeed(seed[0])
        ours.SetNumberOfThreads(threads)
        if portable:
            os.environ["PTV_PORTABLE_KERNELS"] = "1"
        try:
            start = time.perf_counter()
            window.Render()
            whole = 1000.0 * (time.perf_counter() - start)
        finally:
            os.environ.pop("PTV_PORTABLE_KERNELS", None)
        return {"whole": whole, "trace": ours.GetStatistics().GetLastTraceTime(),
                "denoise": ours.GetStatistics().GetLastDenoiseTime()}

    keys = ("stock", "ours", "one", "two", "portable", "end_to_end", "end_to_end_plain")
    rounds: dict = {k: [] for k in keys}
    for round_ in range(repeats + 1):
        volume.SetMapper(stock)
        window.Render()
        start = time.perf_counter()
        window.Render()
        got = {"stock": {"whole": 1000.0 * (time.perf_counter() - start)}}
        volume.SetMapper(ours)
        render_ours(0)
        got["ours"] = render_ours(0)
        # 2 threads right after a render on every core, 1 thread after that: a 2-thread render
        # that follows a 1-thread one starts on a core the VM has just seen idle, and measured
        # up to 12 % slower than the every-core render of the same round (same thread count).
        got["two"] = render_ours(2)
        got["one"] = render_ours(1)
        got["portable"] = render_ours(0, portable=True)
        ours.DenoiseOn()
        got["end_to_end"] = render_ours(0)
        edge_samples = ours.GetExpertOptions().GetEdgeSamples()
        ours.GetExpertOptions().SetEdgeSamples(1)  # the same frame without EdgeSamples
        got["end_to_end_plain"] = render_ours(0)
        ours.GetExpertOptions().SetEdgeSamples(edge_samples)
        ours.DenoiseOff()
        if round_ > 0:
            for k in keys:
                rounds[k].append(got[k])

    def median(key: str, field: str) -> float:
        return statistics.median(r[field] for r in rounds[key])

    def ratio(key_a: str, field_a: str, key_b: str, field_b: str) -> float:
        return pb.paired_ratio([r[field_a] for r in rounds[key_a]],
                               [r[field_b] for r in rounds[key_b]])

    trace_all = median("ours", "trace")
    end_to_end_ms = median("end_to_end", "whole")
    return {
        "dataset": dataset, "size": size,
        "stock_ms": median("stock", "whole"), "ours_ms": median("ours", "whole"),
        "ours_trace_ms": trace_all,
        "ratio": ratio("ours", "whole", "stock", "whole"),
        "samples_per_s": size * size / (trace_all / 1000.0),
        "trace_1thread_ms": median("one", "trace"), "trace_2threads_ms": median("two", "trace"),
        "scaling_2_over_1": ratio("one", "trace", "two", "trace"),
        "trace_portable_ms": median("portable", "trace"),
        "portable_speedup": ratio("portable", "trace", "ours", "trace"),
        "kernel": ours.GetCpuKernelTarget(),
        "end_to_end_ms": end_to_end_ms, "end_to_end_fps": 1000.0 / end_to_end_ms,
        "denoise_ms": median("end_to_end", "denoise"),
        "end_to_end_trace_ms": median("end_to_end", "trace"),
        "end_to_end_plain_ms": median("end_to_end_plain", "whole"),
        "end_to_end_plain_trace_ms": median("end_to_end_plain", "trace"),
        "edge_samples": edge_samples,
    }


def main() -> int:
    args = parse_args()
    rows = []
    jobs = [(d, s) for d in args.datasets for s in args.sizes]
    for dataset, size in tqdm(jobs, desc="benchmark", unit="case"):
        rows.append(measure(dataset, size, args.repeats))
    print(f"\nmachine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores; "
          f"median of {args.repeats} interleaved rounds after a warm-up (ratios: median of the "
          f"rounds' ratios); 1 spp, shading on, two-band preset")
    header = ("dataset", "size", "stock ms", "ours ms", "ratio", "trace ms", "Msamples/s",
              "1 thr ms", "2 thr ms", "2/1 speed-up")
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for r in rows:
        print(f"| {r['dataset']} | {r['size']}² | {r['stock_ms']:.0f} | {r['ours_ms']:.0f} | "
              f"{r['ratio']:.2f} | {r['ours_trace_ms']:.0f} | {r['samples_per_s'] / 1e6:.2f} | "
              f"{r['trace_1thread_ms']:.0f} | {r['trace_2threads_ms']:.0f} | "
              f"{r['scaling_2_over_1']:.2f} |")
    kernel = rows[0]["kernel"] if rows else "?"
    print(f"\ninstruction sets and end to end (1 spp traced + denoised + displayed, every core):")
    edges = rows[0]["edge_samples"] if rows else "?"
    header = ("dataset", "size", f"trace ms ({kernel})", "trace ms (baseline)", "speed-up",
              "denoise ms", "end to end ms", "fps", f"its trace ms (EdgeSamples {edges})",
              "end to end ms, EdgeSamples 1", "its trace ms")
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for r in rows:
        print(f"| {r['dataset']} | {r['size']}² | {r['ours_trace_ms']:.0f} | "
              f"{r['trace_portable_ms']:.0f} | {r['portable_speedup']:.2f} | "
              f"{r['denoise_ms']:.0f} | {r['end_to_end_ms']:.0f} | {r['end_to_end_fps']:.1f} | "
              f"{r['end_to_end_trace_ms']:.0f} | {r['end_to_end_plain_ms']:.0f} | "
              f"{r['end_to_end_plain_trace_ms']:.0f} |")
    if args.json:
        write_text(args.json, json.dumps(rows, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
