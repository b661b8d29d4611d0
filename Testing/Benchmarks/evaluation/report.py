"""The whole report: the measuring run (every section's ``measure`` then ``render``), the header
and summary, the "Files" list, and ``--render-only`` (every section's ``render`` from
results.json, nothing measured).

results.json holds, besides the sections' keys: ``command``, ``machine``, ``args`` (every option
as its str()), ``elapsed_s``, ``load``, ``denoiser_status`` and ``run`` (``generated_utc``,
``tracer_fingerprint``, ``cache_hits``, ``cache_misses``: the rest of the header).
"""
from __future__ import annotations

import argparse
import datetime
import json
import os
import re
import shlex
import sys
import time
from pathlib import Path
from types import ModuleType
from typing import Any, Dict, List, Mapping, Sequence

from . import samples, stress, table1, temporal, timing, training
from .common import (SECTIONS, Output, decode_args, fmt, machine_info, missing_keys, num,
                     stored_args, write_json, write_text)

MODULES: Dict[str, ModuleType] = {"table1": table1, "samples": samples, "training": training,
                                  "temporal": temporal, "stress": stress, "timing": timing}
HEADER_KEYS = ("command", "machine", "args", "elapsed_s", "load", "denoiser_status",
               "run.generated_utc", "run.tracer_fingerprint", "run.cache_hits",
               "run.cache_misses")


class RenderOnlyError(RuntimeError):
    """results.json cannot be re-rendered (missing, unreadable, or written by an older
    evaluate_report.py that did not store every row the report shows)."""


def command_line(argv: Sequence[str]) -> str:
    """The command that regenerates the report (shown in its header)."""
    niceness = os.nice(0)
    return ("PYTHONPATH=build/python " + ("" if niceness == 0 else f"nice -n {niceness} ")
            + "xvfb-run -a -s \"-screen 0 2000x1200x24 "
            "-noreset\" .venv/bin/python Testing/Benchmarks/evaluate_report.py"
            + ("" if not argv else " " + shlex.join(argv)))


# --- the measuring run ----------------------------------------------------------------------
def measure(args: argparse.Namespace, argv: Sequence[str]) -> int:
    """Measure and render every section of ``args.sections``; write report.md, results.json,
    the charts, CSVs and galleries to ``args.out``."""
    from .scenes import Bench  # VTK is imported when it renders
    bench = Bench(args)
    out = Output(args.out)
    args.out.mkdir(parents=True, exist_ok=True)
    started = time.time()
    load0 = os.getloadavg()
    info = machine_info(args.model)
    results: Dict[str, Any] = {}
    body: List[str] = []
    for name in SECTIONS:
        if name in args.sections:
            module = MODULES[name]
            results.update(module.measure(bench, out, results))
            lines, derived = module.render(results, args, out)
            results.update(derived)
            body += lines
    status = bench.ours[0].status()
    elapsed = time.time() - started
    load1 = os.getloadavg()
    now = datetime.datetime.now(datetime.timezone.utc)
    data = {"command": command_line(argv), "machine": info, "args": stored_args(args),
            "elapsed_s": elapsed, "load": [load0, load1], "denoiser_status": status,
            **results,
            "run": {"generated_utc": f"{now:%Y-%m-%d %H:%M}",
                    "tracer_fingerprint": bench.fingerprint, "cache_hits": bench.cache.hits,
                    "cache_misses": bench.cache.misses}}
    write_report(out, args, data, body)
    write_json(out.root / "results.json", data)
    print(f"report: {out.root / 'report.md'} ({elapsed / 60:.1f} min)")
    return 0


# --- --render-only --------------------------------------------------------------------------
def load_results(folder: Path) -> Dict[str, Any]:
    """results.json of ``folder``, checked for every key the report's sections render."""
    path = folder / "results.json"
    try:
        data = json.loads(path.read_text())
    except FileNotFoundError:
        raise RenderOnlyError(f"{path} does not exist: run evaluate_report.py without "
                              "--render-only first (it measures and writes it)") from None
    except (OSError, ValueError) as exc:
        raise RenderOnlyError(f"cannot read {path}: {exc}") from None
    if not isinstance(data, dict):
        raise RenderOnlyError(f"{path}: not a JSON object")
    missing = missing_keys(data, HEADER_KEYS)
    if "args" in data:
        try:
            args = decode_args(data["args"])
        except (ValueError, SyntaxError) as exc:
            raise RenderOnlyError(f"{path}: unreadable \"args\" ({exc})") from None
        for name in SECTIONS:
            if name in args.sections:
                missing += MODULES[name].missing(data)
    if missing:
        raise RenderOnlyError(
            f"{path} lacks what --render-only needs: {', '.join(missing)}. It was written by "
            "an older evaluate_report.py that did not store every row of the report; run "
            "evaluate_report.py without --render-only (with the options of its \"command\") "
            "to measure them again.")
    return data


def render_only(folder: Path) -> int:
    """Rewrite report.md, the charts, the CSVs and results.json's derived keys (headlines,
    verdicts) of ``folder`` from its results.json; measures nothing, imports no VTK."""
    try:
        data = load_results(folder)
    except RenderOnlyError as exc:
        print(f"evaluate_report.py --render-only: {exc}", file=sys.stderr)
        return 2
    args = decode_args(data["args"])
    args.out = folder
    out = Output(folder)
    body: List[str] = []
    for name in SECTIONS:
        if name in args.sections:
            lines, derived = MODULES[name].render(data, args, out)
            data.update(derived)
            body += lines
    write_report(out, args, data, body)
    write_json(folder / "results.json", data)
    text = (folder / "report.md").read_text()
    absent = [link for link in re.findall(r"\]\(([^)]+)\)", text)
              if not (folder / link).is_file()]
    if absent:
        print("evaluate_report.py --render-only: the report links to files that are not in "
              f"{folder} (galleries are only drawn while measuring): {', '.join(absent)}",
              file=sys.stderr)
    print(f"report: {folder / 'report.md'} (re-rendered from results.json)")
    return 0


# --- header, summary, files -----------------------------------------------------------------
def write_report(out: Output, a: argparse.Namespace, data: Mapping[str, Any],
                 body: Sequence[str]) -> None:
    files = sorted(set(out.files))
    tail = ["## Files", "", "Every figure's numbers: " + ", ".join(
        f"[{f}]({f})" for f in files if not f.endswith(".png")) + "; `results.json` holds "
        "everything above.", ""]
    write_text(out.root / "report.md", "\n".join(header(a, data) + list(body) + tail) + "\n")


def header(a: argparse.Namespace, data: Mapping[str, Any]) -> List[str]:
    """The title, the run's facts (machine, versions, sizes, cache) and the summary."""
    info, run = data["machine"], data["run"]
    load0, load1 = data["load"]
    threads = a.threads or f"all ({info['cores']})"
    head = [
        "# PathTracedVolume evaluation report", "",
        "Generated by `Testing/Benchmarks/evaluate_report.py` "
        f"on {run['generated_utc']} UTC "
        f"in {data['elapsed_s'] / 60:.1f} min. Regenerate with:", "",
        "```sh", data["command"], "```", "",
        "| | |", "|---|---|",
        f"| machine | {info['cpu']}, {info['cores']} cores, {info['ram']} RAM, "
        f"{info['os']} |",
        f"| load average (1 min) | {load0[0]:.2f} at start, {load1[0]:.2f} at the end "
        "(the cores are shared with other work: timings include that contention) |",
        f"| software | VTK {info['vtk']}, ONNX Runtime {info['onnxruntime']}, "
        f"{info['oidn']}, Python {info['python']} |",
        f"| git commit | {info['git']} |",
        f"| denoiser | {data['denoiser_status']}; model {info['model']} |",
        f"| timings | median of {a.repeats} repeats after a warm-up, threads "
        f"{threads}; Table 1: every denoiser right after a 1-spp trace, all once per round, "
        f"median of {table1.table1_rounds(a)} rounds |",
        f"| sizes | Table 1 / temporal {a.size}², stress {a.stress_size}² (+ odd sizes), "
        f"references {a.ref_spp} spp (stress {a.stress_ref_spp}, {a.big_size} "
        f"{a.big_ref_spp}) |",
        "| protocol | docs/measuring.md: tone map clip(max(0,x)^(1/2.2),0,1); PSNR/SSIM "
        "scikit-image, data_range 1 |",
        f"| traced-image cache | {'off' if a.no_cache else a.cache} (tracer fingerprint "
        f"{run['tracer_fingerprint']}; {run['cache_hits']} hits, {run['cache_misses']} "
        "renders) |",
        "",
    ]
    if a.quick:
        head += ["**Quick mode** (`--quick`, CI smoke test): tiny images and spp; the "
                 "figures below only show that the pipeline runs.", ""]
    headlines = list(data.get("headlines", [])) + list(data.get("flicker_verdicts", []))
    fails = [r["case"] for r in data.get("stress", []) if r["failed"]]
    if headlines or "stress" in data:
        head += ["## Summary", ""] + headlines
        sp = [s for s in data.get("speedup", []) if s["method"] == "ours"]
        head += ["* quality-matched speed-up (ours; target ≥ 10×, paper ~6×): "
                 + ", ".join(f"{s['dataset']} {'>' if s['lower_bound'] else ''}"
                             f"{num(s['speedup']):.1f}× (interpolated "
                             f"{fmt(s['interp_speedup'], 1)}×)" for s in sp)] if sp else []
        if "stress" in data:
            head += [f"* stress cases where ours is worse than noisy or not finite: "
                     f"{', '.join(fails) if fails else 'none'}"]
        head += [""]
    return head
