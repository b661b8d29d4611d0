"""Shared pieces of the evaluation report: options, constants, CSV/JSON/Markdown helpers, the
machine description, and the output folder (CSV + chart files, thumbnail strips).

Nothing here renders with VTK: the rendering side is :mod:`.scenes`.
"""
from __future__ import annotations

import argparse
import ast
import csv
import hashlib
import json
import math
import os
import platform
import statistics
import subprocess
from pathlib import Path
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple

import numpy as np
import ptvbench as pb  # beside this package (on sys.path: see __init__)
from pathtracedvolume.atomic import atomic_path, write_text

ROOT = pb.ROOT
DESCRIPTION = ("Evaluation report: quality against time, the paper's tables, temporal "
               "stability, a stress suite")
DATASETS = ("head", "stent", "concrete")
PAPER_SPP = (1, 2, 4, 8, 16, 64, 256)
VIEWS = ((30.0, 10.0), (150.0, -20.0), (260.0, 35.0), (330.0, -5.0))  # (azimuth, elevation)
SEED_INPUT = 1          # the 1-spp input and the spp sweep (its first N frames)
SEED_REFERENCE = 100003  # the reference: an independent random stream
STRESS_METHODS = ("noisy", "ours", "OIDN fast", "ours, fixed guide", "ours, no clamp")
SECTIONS = ("table1", "samples", "training", "temporal", "stress", "timing")
NOT_STORED = ("render_only",)  # options of this run only, not part of results.json "args"


# --- options ------------------------------------------------------------------------------
def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        description=DESCRIPTION, formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    p.add_argument("--out", type=Path, default=ROOT / "Testing/Benchmarks/report",
                   help="report folder (report.md, *.png, *.csv, *.json, gallery/)")
    p.add_argument("--size", type=int, default=256, help="image size (square) of sections 1, 4")
    p.add_argument("--views", type=int, default=2, help="camera views per dataset (1..4)")
    p.add_argument("--ref-spp", type=int, default=1024, help="reference samples per pixel")
    p.add_argument("--sweep", type=int, nargs="+", default=list(PAPER_SPP),
                   help="spp counts of Table 1 (the chart adds intermediate counts)")
    p.add_argument("--repeats", type=int, default=5, help="timed runs per figure (median)")
    p.add_argument("--datasets", nargs="+", default=list(DATASETS), choices=DATASETS)
    p.add_argument("--model", default="", help="GuideNet .onnx (default: the shipped one)")
    p.add_argument("--threads", type=int, default=0, help="tracer/denoiser threads (0 = all)")
    p.add_argument("--edge-samples", type=int, default=0,
                   help="EdgeSamples of the denoisers' frames (0 = the mapper's default)")
    p.add_argument("--samples-sizes", type=int, nargs="+", default=[256, 512],
                   help="image sizes of the quality-against-samples section")
    p.add_argument("--samples-frames", type=int, default=256,
                   help="frames the quality-against-samples section accumulates")
    p.add_argument("--static-frames", type=int, default=16, help="seeds of the fixed view")
    p.add_argument("--orbit-frames", type=int, default=36, help="frames of the camera orbit")
    p.add_argument("--orbit-step", type=float, default=2.0, help="orbit degrees per frame")
    p.add_argument("--orbit-ref-spp", type=int, default=32, help="spp of the converged orbit")
    p.add_argument("--orbit-datasets", nargs="+", default=["head"], choices=DATASETS)
    p.add_argument("--stress-size", type=int, default=128, help="image size of stress cases")
    p.add_argument("--stress-ref-spp", type=int, default=512)
    p.add_argument("--big-size", default="1920x1080", help="the large stress image, WxH")
    p.add_argument("--big-ref-spp", type=int, default=32,
                   help="reference spp of the large image (kept low: time)")
    p.add_argument("--scaling-sizes", type=int, nargs="+", default=[128, 256, 512, 1024])
    p.add_argument("--volume-shrink", type=int, nargs="+", default=[1, 2, 4],
                   help="head downsampling factors (vtkImageShrink3D, averaging)")
    p.add_argument("--sections", nargs="+", default=list(SECTIONS), choices=SECTIONS)
    p.add_argument("--cache", type=Path,
                   default=Path(os.environ.get("PTV_CACHE_DIR", ROOT / ".cache")) / "bench"
                   / "report", help="cache of traced references and sweeps")
    p.add_argument("--no-cache", action="store_true", help="trace everything again")
    p.add_argument("--quick", action="store_true",
                   help="tiny sizes, 1 view, few spp (CI smoke test, well under a minute)")
    p.add_argument("--render-only", action="store_true",
                   help="measure nothing (no VTK, no denoising): rewrite report.md, the charts "
                        "and the CSVs of --out from its results.json; every other option is "
                        "taken from that file (the galleries are kept as they are)")
    return p


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    p = build_parser()
    args = p.parse_args(argv)
    if args.quick:  # tiny defaults; options given explicitly still win
        quick = dict(size=24, views=1, ref_spp=32, sweep=[1, 2, 4, 8], repeats=1,
                     static_frames=4, orbit_frames=4, orbit_ref_spp=4, stress_size=16,
                     stress_ref_spp=16, big_size="64x36", big_ref_spp=4, scaling_sizes=[16, 32],
                     volume_shrink=[1, 4], samples_sizes=[24], samples_frames=4)
        for key, value in quick.items():
            if getattr(args, key) == p.get_default(key):
                setattr(args, key, value)
    args.views = max(1, min(args.views, len(VIEWS)))
    args.sweep = sorted(set(args.sweep) | {1})
    args.ref_spp = max(2, args.ref_spp)
    return args


def stored_args(args: argparse.Namespace) -> Dict[str, str]:
    """The options as results.json stores them ("args": every value as its str())."""
    return {k: str(v) for k, v in vars(args).items() if k not in NOT_STORED}


def decode_args(stored: Mapping[str, str]) -> argparse.Namespace:
    """The inverse of :func:`stored_args` (types from the parser's defaults; an option that
    ``stored`` lacks keeps its default)."""
    args = build_parser().parse_args([])
    for key, default in vars(args).items():
        if key not in stored or key in NOT_STORED:
            continue
        text = stored[key]
        if isinstance(default, Path):
            value: Any = Path(text)
        elif isinstance(default, str):
            value = text
        else:
            value = ast.literal_eval(text)
        setattr(args, key, value)
    return args


def counts(args: argparse.Namespace) -> List[int]:
    """The sweep counts plus intermediate ones (chart line, speed-up)."""
    top = max(args.sweep)
    dense = {n for n in (1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256, 384,
                         512, 768, 1024) if n <= top}
    return sorted(dense | set(args.sweep))


def view_spec(args: argparse.Namespace, dataset: str, view: int,
              size: Optional[int] = None) -> Dict[str, Any]:
    az, el = VIEWS[view]
    s = size or args.size
    return {"volume": dataset, "preset": "paper", "size": [s, s], "azimuth": az,
            "elevation": el}


# --- small utilities ------------------------------------------------------------------------
def write_csv(path: Path, rows: Sequence[Mapping[str, Any]]) -> None:
    """Rows (dicts) as CSV with the union of their keys as the header, floats rounded."""
    keys: List[str] = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    with atomic_path(path) as tmp, open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def json_clean(x: Any) -> Any:
    """Plain JSON values: NumPy scalars as Python ones, non-finite floats as None."""
    if isinstance(x, dict):
        return {str(k): json_clean(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [json_clean(v) for v in x]
    if isinstance(x, (np.floating, float)):
        return float(x) if math.isfinite(x) else None
    if isinstance(x, np.integer):
        return int(x)
    if isinstance(x, np.bool_):
        return bool(x)
    return x


def write_json(path: Path, data: Any) -> None:
    write_text(path, json.dumps(json_clean(data), indent=1) + "\n")


def median(values: Iterable[float]) -> float:
    return float(statistics.median(list(values)))


def num(x: Any) -> Any:
    """A measured number for arithmetic and charts: None (a non-finite value as results.json
    stores it) becomes NaN, so a re-rendered report prints and plots it as the measuring run
    did."""
    return float("nan") if x is None else x


def fmt(x: Any, digits: int = 2) -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "n/a"
    if isinstance(x, float):
        return f"{x:.{digits}f}"
    return str(x)


def md_table(header: Sequence[str], rows: Iterable[Sequence[Any]]) -> List[str]:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return lines


def missing_keys(results: Mapping[str, Any], paths: Iterable[str]) -> List[str]:
    """The dotted key paths (``"temporal.orbit_tpsnr"``) that ``results`` lacks."""
    out = []
    for path in paths:
        node: Any = results
        for part in path.split("."):
            if not isinstance(node, Mapping) or part not in node:
                out.append(path)
                break
            node = node[part]
    return out


def machine_info(model: str) -> Dict[str, str]:
    def read(path: str) -> str:
        try:
            return Path(path).read_text()
        except OSError:
            return ""
    cpu = next((line.split(":", 1)[1].strip() for line in read("/proc/cpuinfo").splitlines()
                if line.startswith("model name")), platform.processor() or platform.machine())
    mem = next((int(line.split()[1]) for line in read("/proc/meminfo").splitlines()
                if line.startswith("MemTotal")), 0)
    osname = next((line.split("=", 1)[1].strip().strip('"')
                   for line in read("/etc/os-release").splitlines()
                   if line.startswith("PRETTY_NAME")), platform.platform())

    def run(*cmd: str) -> str:
        try:
            return subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True,
                                  check=True).stdout.strip()
        except (OSError, subprocess.CalledProcessError):
            return "unknown"
    commit = run("git", "rev-parse", "--short=12", "HEAD")
    dirty = run("git", "status", "--porcelain", "--untracked-files=no")
    import importlib.metadata as meta

    def version(pkg: str) -> str:
        try:
            return meta.version(pkg)
        except meta.PackageNotFoundError:
            return "not installed"
    from vtkmodules.vtkCommonCore import vtkVersion
    model_path = Path(model) if model else ROOT / "Data/Models/guidenet.onnx"
    model_sha = (hashlib.sha256(model_path.read_bytes()).hexdigest()[:16]
                 if model_path.exists() else "missing")
    shown = model_path.relative_to(ROOT) if model_path.is_relative_to(ROOT) else model_path
    model_commit = run("git", "log", "-1", "--format=%h %cd", "--date=format:%Y-%m-%d %H:%M",
                       "--", str(model_path))
    return {
        "cpu": cpu, "cores": str(os.cpu_count()), "ram": f"{mem / 1024 / 1024:.1f} GiB",
        "os": osname, "python": platform.python_version(),
        "vtk": vtkVersion.GetVTKVersion(), "onnxruntime": version("onnxruntime"),
        "oidn": f"pyoidn {version('pyoidn')}",
        "git": commit + (" (with uncommitted changes in tracked files)" if dirty else ""),
        "model": f"{shown} sha256 {model_sha}… (last commit {model_commit or 'none'})",
    }


# --- the output folder ------------------------------------------------------------------------
class Output:
    """The report folder; remembers every file written (the report's "Files" list)."""

    def __init__(self, root: Path) -> None:
        self.root = root
        self.files: List[str] = []

    def save(self, name: str, rows: Any, fig: Any = None) -> None:
        """``name``.csv (a list of rows) or .json, and ``name``.png for a figure."""
        if isinstance(rows, list):
            self.csv(name, rows)
        else:
            write_json(self.root / f"{name}.json", rows)
            self.files.append(f"{name}.json")
        if fig is not None:
            with atomic_path(self.root / f"{name}.png", suffix=".tmp.png") as tmp:
                fig.savefig(tmp, dpi=80)
            import matplotlib.pyplot as plt
            plt.close(fig)
            self.files.append(f"{name}.png")

    def csv(self, name: str, rows: Sequence[Mapping[str, Any]]) -> None:
        write_csv(self.root / f"{name}.csv", rows)
        self.files.append(f"{name}.csv")

    def thumbs(self, name: str, panels: Sequence[Tuple[str, np.ndarray]],
               box: Tuple[int, int] = (150, 110)) -> None:
        """gallery/``name``.png: one strip of tone-mapped thumbnails (nearest neighbour, aspect
        kept within ``box``, at least 6 pixels tall), captioned. Written while measuring: it
        needs the images, which results.json does not hold."""
        import matplotlib.pyplot as plt
        tms = [pb.tonemap(img)[::-1] for _, img in panels]
        h, w = tms[0].shape[:2]
        if w > 4 * h:  # extreme aspect: crop to the columns with content (plus a margin)
            cols = np.flatnonzero(np.max(np.stack([t.max(axis=(0, 2)) for t in tms]), 0) > 0.02)
            if cols.size:
                lo = max(0, cols[0] - 2 * h)
                hi = min(w, max(cols[-1] + 1 + 2 * h, lo + 4 * h))
                tms = [t[:, lo:hi] for t in tms]
        imgs = []
        for t in tms:
            h, w = t.shape[:2]
            scale = min(box[0] / w, box[1] / h)
            tw, th = max(1, round(w * scale)), max(6, round(h * scale))
            rows = np.minimum(((np.arange(th) + 0.5) * h / th).astype(int), h - 1)
            cols = np.minimum(((np.arange(tw) + 0.5) * w / tw).astype(int), w - 1)
            imgs.append(t[rows][:, cols])
        top = max(t.shape[0] for t in imgs)
        fig, axes = plt.subplots(1, len(panels), dpi=100, figsize=(
            (box[0] + 10) / 100 * len(panels), (top + 20) / 100))
        fig.subplots_adjust(left=0.005, right=0.995, bottom=0.0, top=top / (top + 20),
                            wspace=0.05)
        for ax, (label, _), t in zip(np.atleast_1d(axes), panels, imgs):
            ax.imshow(t, interpolation="nearest")
            ax.set_title(label, fontsize=7)
            ax.axis("off")
        (self.root / "gallery").mkdir(exist_ok=True)
        with atomic_path(self.root / "gallery" / f"{name}.png", suffix=".tmp.png") as tmp:
            fig.savefig(tmp, dpi=100)
        plt.close(fig)
        self.files.append(f"gallery/{name}.png")
