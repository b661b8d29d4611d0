#!/usr/bin/env python3
"""Evaluation report: quality against time, the paper's tables, temporal stability, a stress suite
and where the time goes, written as Markdown + PNG charts + CSV/JSON of every figure.

Sections (docs/measuring.md protocol: images tone-mapped clip(max(0,x)^(1/2.2),0,1), PSNR/SSIM
from scikit-image with data_range 1, timings = median of --repeats after a warm-up, all methods
in the same run):

1. Paper Table 1 per dataset (head, stent, concrete; "<Dataset> Two-Band (paper)" preset),
   --views camera orbits each: the 1..256-spp sweep, 1 spp denoised by vtkPTVDenoiser (1 grid
   level and the model's levels, "ours") and by OIDN (pyoidn RT, fast and balanced, albedo + normal) on the same 1-spp
   passes, against a --ref-spp reference of an independent seed (convergence: ref/2 vs ref).
2. PSNR against time per dataset and the quality-matched speed-up.
3. Paper Tables 2-4 from the committed training studies (Training/results/), when present.
4. Temporal stability: per-pixel std over frames of different seeds (fixed view), the mapper's
   own accumulation when the camera stops, and temporal PSNR over a camera orbit.
5. Stress suite with a thumbnail gallery: translucent transfer function, fireflies, thin
   structures, exposure x0.01/x100, odd image sizes, mostly empty volume, unseen volume.
6. Where the time goes: stages, image size, volume size and thread count.

Traced images that do not depend on the denoiser (references, spp sweeps, the orbit and stress
references) are cached under <cache>/bench/report, keyed by their parameters and by a fingerprint
of the tracer's output (a tiny render), so a changed tracer re-renders; --no-cache renders all.
Timings are always measured in the run itself.
"""
from __future__ import annotations

import argparse
import csv
import datetime
import hashlib
import json
import math
import os
import platform
import shlex
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ptvbench as pb  # noqa: E402
from pathtracedvolume.atomic import atomic_path, write_text  # noqa: E402
from pathtracedvolume.metrics import flicker, tpsnr  # noqa: E402

from tqdm import tqdm  # noqa: E402

ROOT = pb.ROOT
DATASETS = ("head", "stent", "concrete")
PAPER_SPP = (1, 2, 4, 8, 16, 64, 256)
VIEWS = ((30.0, 10.0), (150.0, -20.0), (260.0, 35.0), (330.0, -5.0))  # (azimuth, elevation)
SEED_INPUT = 1          # the 1-spp input and the spp sweep (its first N frames)
SEED_REFERENCE = 100003  # the reference: an independent random stream
STRESS_METHODS = ("noisy", "ours", "OIDN fast", "ours, fixed guide", "ours, no clamp")
SECTIONS = ("table1", "training", "temporal", "stress", "timing")


# --- options ------------------------------------------------------------------------------
def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(
        description=__doc__.splitlines()[0],
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
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
    args = p.parse_args(argv)
    if args.quick:  # tiny defaults; options given explicitly still win
        quick = dict(size=24, views=1, ref_spp=32, sweep=[1, 2, 4, 8], repeats=1,
                     static_frames=4, orbit_frames=4, orbit_ref_spp=4, stress_size=16,
                     stress_ref_spp=16, big_size="64x36", big_ref_spp=4, scaling_sizes=[16, 32],
                     volume_shrink=[1, 4])
        for key, value in quick.items():
            if getattr(args, key) == p.get_default(key):
                setattr(args, key, value)
    args.views = max(1, min(args.views, len(VIEWS)))
    args.sweep = sorted(set(args.sweep) | {1})
    args.ref_spp = max(2, args.ref_spp)
    return args


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


def write_json(path: Path, data: Any) -> None:
    def clean(x: Any) -> Any:
        if isinstance(x, dict):
            return {str(k): clean(v) for k, v in x.items()}
        if isinstance(x, (list, tuple)):
            return [clean(v) for v in x]
        if isinstance(x, (np.floating, float)):
            return float(x) if math.isfinite(x) else None
        if isinstance(x, np.integer):
            return int(x)
        if isinstance(x, np.bool_):
            return bool(x)
        return x
    write_text(path, json.dumps(clean(data), indent=1) + "\n")


def median(values: Iterable[float]) -> float:
    return float(statistics.median(list(values)))


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


# --- traced images: scenes and the cache ---------------------------------------------------
def procedural_volume(n: int = 96) -> Any:
    """A volume unlike the training data: a torus with a noisy surface and a few blobs inside a
    mostly empty box, float32 in [0, 1] (deterministic)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData

    rng = np.random.default_rng(7)
    ax = np.linspace(-1.0, 1.0, n, dtype=np.float32)
    z, y, x = np.meshgrid(ax, ax, ax, indexing="ij")
    ring = np.sqrt(x ** 2 + y ** 2) - 0.55
    torus = np.sqrt(ring ** 2 + z ** 2)
    wobble = sum(0.04 * np.sin(f[0] * x + f[1] * y + f[2] * z + f[3])
                 for f in rng.uniform([3, 3, 3, 0], [9, 9, 9, 6], (6, 4)))
    field = np.clip(1.0 - (torus + wobble) / 0.25, 0.0, 1.0) * 0.6
    for c in rng.uniform(-0.6, 0.6, (5, 3)):
        r2 = (x - c[0]) ** 2 + (y - c[1]) ** 2 + (z - c[2]) ** 2
        field = np.maximum(field, np.exp(-r2 / (2 * 0.08 ** 2)))
    image = vtkImageData()
    image.SetDimensions(n, n, n)
    image.SetSpacing(1.0, 1.0, 1.0)
    arr = numpy_to_vtk(np.ascontiguousarray(field.reshape(-1)), deep=1)
    arr.SetName("ImageScalars")
    image.GetPointData().SetScalars(arr)
    return image


PROCEDURAL_PRESET = {
    "Name": "Procedural Two-Band", "ColorSpace": "RGB",
    "RGBPoints": [0.0, 0.9, 0.45, 0.2, 0.5, 0.9, 0.45, 0.2, 0.7, 0.3, 0.7, 1.0, 1.0, 0.3, 0.7, 1.0],
    "Points": [0.0, 0.0, 0.5, 0.0, 0.29, 0.0, 0.5, 0.0, 0.3, 0.6, 0.5, 0.0, 0.5, 0.6, 0.5, 0.0,
               0.51, 0.0, 0.5, 0.0, 0.69, 0.0, 0.5, 0.0, 0.7, 1.0, 0.5, 0.0, 1.0, 1.0, 0.5, 0.0],
}


class Scenes:
    """Builds volumes, presets and BenchScenes from JSON-able specs and reuses them::

        {"volume": "head" | "stent" | "concrete" | "head_shrink<F>" | "head_padded" |
                   "procedural",
         "preset": "paper" | "translucent" | "procedural", "size": [w, h],
         "light": key-light intensity, "specular": [coefficient, power] (optional),
         "azimuth", "elevation", "dolly"}
    """

    def __init__(self, threads: int) -> None:
        self.threads = threads
        self._volumes: Dict[str, Any] = {}
        self._scenes: Dict[str, pb.BenchScene] = {}
        self._keep: List[Any] = []

    def volume(self, name: str) -> Any:
        if name not in self._volumes:
            if name in DATASETS:
                vol = pb.load_dataset(name)
            elif name.startswith("head_shrink"):
                from vtkmodules.vtkImagingCore import vtkImageShrink3D
                f = int(name[len("head_shrink"):])
                shrink = vtkImageShrink3D()
                shrink.SetInputData(self.volume("head"))
                shrink.SetShrinkFactors(f, f, f)
                shrink.AveragingOn()
                shrink.Update()
                vol = shrink.GetOutput()
            elif name == "head_padded":
                from vtkmodules.vtkImagingCore import vtkImageConstantPad
                half = self.volume("head_shrink2")
                e = half.GetExtent()
                d = [e[2 * i + 1] - e[2 * i] + 1 for i in range(3)]
                pad = vtkImageConstantPad()
                pad.SetInputData(half)
                pad.SetConstant(-1024.0)
                pad.SetOutputWholeExtent(e[0] - d[0], e[1] + d[0], e[2] - d[1], e[3] + d[1],
                                         e[4] - d[2], e[5] + d[2])
                pad.Update()
                vol = pad.GetOutput()
            elif name == "procedural":
                vol = procedural_volume()
            else:
                raise ValueError(f"unknown volume {name!r}")
            self._volumes[name] = vol
        return self._volumes[name]

    @staticmethod
    def preset(name: str, volume: str) -> Dict[str, Any]:
        if name == "procedural":
            return dict(PROCEDURAL_PRESET)
        base = pb.paper_preset(volume.split("_")[0])
        if name == "paper":
            return base
        if name == "translucent":  # the same bands, at most 5 % opacity: nothing opaque
            pts = np.asarray(base["Points"], np.float64).reshape(-1, 4).copy()
            pts[:, 1] *= 0.05 / max(pts[:, 1].max(), 1e-9)
            return {**base, "Points": [float(v) for v in pts.reshape(-1)]}
        raise ValueError(f"unknown preset {name!r}")

    def scene(self, spec: Mapping[str, Any], threads: Optional[int] = None) -> pb.BenchScene:
        threads = self.threads if threads is None else threads
        key = json.dumps([spec["volume"], spec.get("preset", "paper"), list(spec["size"]),
                          spec.get("light", 1.0), spec.get("specular"), threads])
        if key not in self._scenes:
            prop = pb.make_property(self.preset(spec.get("preset", "paper"), spec["volume"]))
            if spec.get("specular"):
                prop.SetSpecular(spec["specular"][0])
                prop.SetSpecularPower(spec["specular"][1])
            self._scenes[key] = pb.BenchScene(
                self.volume(spec["volume"]), prop, tuple(spec["size"]), threads=threads,
                light_intensity=spec.get("light", 1.0))
        scene = self._scenes[key]
        scene.orbit(spec.get("azimuth", 30.0), spec.get("elevation", 10.0),
                    spec.get("dolly", 1.0))
        return scene

    def trace(self, spec: Mapping[str, Any], seed: int, frames: int,
              grab: Mapping[int, Sequence[str]], desc: str = "") -> Dict[str, np.ndarray]:
        """Accumulate ``frames`` 1-spp frames of ``seed``; ``"<pass>@<k>"`` for every pass in
        ``grab[k]``, plus ``"trace_ms"`` (each frame's trace time)."""
        scene = self.scene(spec)
        out: Dict[str, np.ndarray] = {}
        bar = tqdm(total=frames, desc=desc, unit="spp", leave=False, disable=frames < 64)

        def on_frame(k: int) -> None:
            bar.update(1)
            for name in grab.get(k, ()):
                out[f"{name}@{k}"] = scene.grab(name)
        out["trace_ms"] = np.asarray(scene.render(seed, frames, on_frame))
        bar.close()
        return out

    def frame(self, spec: Mapping[str, Any], seed: int) -> pb.Passes:
        """Every pass of one fresh 1-spp frame."""
        data = self.trace(spec, seed, 1, {1: pb.PASSES})
        return {name: data[f"{name}@1"] for name in pb.PASSES}

    def trace_ms(self, spec: Mapping[str, Any], repeats: int,
                 threads: Optional[int] = None) -> float:
        """Median trace milliseconds of fresh 1-spp frames (a new seed each, after a warm-up)."""
        scene = self.scene(spec, threads)
        seeds = iter(range(500000, 500000 + repeats + 2))
        scene.render(next(seeds), 1)  # warm-up
        return median(scene.render(next(seeds), 1)[0] for _ in range(max(repeats, 1)))


class Cache:
    """npz files keyed by (what, parameters, tracer fingerprint); ``root`` None = no cache."""

    def __init__(self, root: Optional[Path], fingerprint: str) -> None:
        self.root, self.fingerprint = root, fingerprint
        self.hits = self.misses = 0

    def get(self, what: str, params: Mapping[str, Any],
            compute: Callable[[], Dict[str, np.ndarray]]) -> Dict[str, np.ndarray]:
        if self.root is None:
            self.misses += 1
            return compute()
        key = hashlib.sha1(json.dumps({"what": what, "params": params, "tracer":
                                       self.fingerprint}, sort_keys=True).encode()).hexdigest()
        path = self.root / f"{what}_{key[:16]}.npz"
        if path.exists():
            try:
                with np.load(path) as f:
                    data = {k: f[k] for k in f.files}
                self.hits += 1
                return data
            except (OSError, ValueError):
                pass
        self.misses += 1
        data = compute()
        with atomic_path(path, suffix=".tmp.npz") as tmp:
            np.savez(tmp, **data)
        return data


def tracer_fingerprint(scenes: Scenes) -> str:
    """Hash of a tiny 2-spp head render: changes whenever the tracer's output changes."""
    data = scenes.trace({"volume": "head", "size": [24, 20]}, 7, 2,
                        {2: pb.PASSES})
    h = hashlib.sha1()
    for name in pb.PASSES:
        h.update(np.ascontiguousarray(data[f"{name}@2"]).tobytes())
    return h.hexdigest()[:16]


# --- the evaluation -----------------------------------------------------------------------
class Evaluation:
    def __init__(self, args: argparse.Namespace) -> None:
        self.args = args
        self.out: Path = args.out
        self.scenes = Scenes(args.threads)
        self.fingerprint = tracer_fingerprint(self.scenes)
        self.cache = Cache(None if args.no_cache else args.cache, self.fingerprint)
        self.ours = {lv: pb.Ours(lv, args.model, args.threads) for lv in (0, 1)}
        self.results: Dict[str, Any] = {}
        self.md: List[str] = []
        self.files: List[str] = []
        self._views: Dict[Tuple[str, int], Dict[str, np.ndarray]] = {}

    # helpers
    def save(self, name: str, rows: Any, fig: Any = None) -> None:
        """``name``.csv (a list of rows) or .json, and ``name``.png for a figure."""
        if isinstance(rows, list):
            write_csv(self.out / f"{name}.csv", rows)
            self.files.append(f"{name}.csv")
        else:
            write_json(self.out / f"{name}.json", rows)
            self.files.append(f"{name}.json")
        if fig is not None:
            with atomic_path(self.out / f"{name}.png", suffix=".tmp.png") as tmp:
                fig.savefig(tmp, dpi=80)
            import matplotlib.pyplot as plt
            plt.close(fig)
            self.files.append(f"{name}.png")

    def view_spec(self, dataset: str, view: int, size: Optional[int] = None) -> Dict[str, Any]:
        az, el = VIEWS[view]
        s = size or self.args.size
        return {"volume": dataset, "preset": "paper", "size": [s, s], "azimuth": az,
                "elevation": el}

    def counts(self) -> List[int]:
        """The sweep counts plus intermediate ones (chart line, speed-up)."""
        top = max(self.args.sweep)
        dense = {n for n in (1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256, 384,
                             512, 768, 1024) if n <= top}
        return sorted(dense | set(self.args.sweep))

    def reference(self, spec: Mapping[str, Any], spp: int, seed: int = SEED_REFERENCE
                  ) -> Dict[str, np.ndarray]:
        """``spp`` frames of an independent seed: "ref" and "half" (its first spp/2)."""
        def compute() -> Dict[str, np.ndarray]:
            d = self.scenes.trace(spec, seed, spp, {spp // 2: ["Radiance"], spp: ["Radiance"]},
                                  desc=f"reference {spec['volume']} {spp} spp")
            return {"ref": d[f"Radiance@{spp}"], "half": d[f"Radiance@{spp // 2}"],
                    "ref_trace_ms": d["trace_ms"]}
        return self.cache.get("reference", {"spec": dict(spec), "spp": spp, "seed": seed},
                              compute)

    def view_data(self, dataset: str, view: int) -> Dict[str, np.ndarray]:
        """1-spp passes ("<pass>@1"), the sweep ("Radiance@N"), "ref" and "half"."""
        key = (dataset, view)
        if key not in self._views:
            spec = self.view_spec(dataset, view)
            counts = self.counts()
            grab: Dict[int, List[str]] = {n: ["Radiance"] for n in counts}
            grab[1] = list(pb.PASSES)
            sweep = self.cache.get(
                "sweep", {"spec": spec, "counts": counts, "seed": SEED_INPUT},
                lambda: self.scenes.trace(spec, SEED_INPUT, max(counts), grab,
                                          desc=f"sweep {dataset} view {view}"))
            self._views[key] = {**sweep, **self.reference(spec, self.args.ref_spp)}
        return self._views[key]

    def denoise(self, passes: pb.Passes, levels: int = 0) -> np.ndarray:
        return self.ours[levels](passes)

    # 1 + 2: Table 1 and PSNR against time
    def table1(self) -> None:
        a = self.args
        counts = self.counts()
        per_view: List[Dict[str, Any]] = []
        summary: List[Dict[str, Any]] = []
        speedups: List[Dict[str, Any]] = []
        chart_rows: List[Dict[str, Any]] = []
        methods = ["ours 1 level", "ours", "OIDN fast", "OIDN balanced"]
        for ds in tqdm(a.datasets, desc="table 1", unit="dataset"):
            quality: Dict[str, List[Tuple[float, float]]] = {}
            ref_checks = []
            for v in range(a.views):
                d = self.view_data(ds, v)
                passes = {n: d[f"{n}@1"] for n in pb.PASSES}
                ref_checks.append(pb.quality(d["ref"], d["half"])[0])
                images = {f"{n} spp": d[f"Radiance@{n}"] for n in counts}
                images["ours 1 level"] = self.denoise(passes, 1)
                images["ours"] = self.denoise(passes, 0)
                images["OIDN fast"] = pb.oidn(passes, "fast")
                images["OIDN balanced"] = pb.oidn(passes, "balanced")
                for name, img in images.items():
                    q = pb.quality(d["ref"], img)
                    quality.setdefault(name, []).append(q)
                    per_view.append({"dataset": ds, "view": v, "azimuth": VIEWS[v][0],
                                     "elevation": VIEWS[v][1], "method": name, "psnr": q[0],
                                     "ssim": q[1], "finite": bool(np.isfinite(img).all())})
                if v == 0:
                    self.thumbs(f"table1_{ds}", [("1 spp", images["1 spp"]),
                                                 ("ours", images["ours"]),
                                                 ("OIDN fast", images["OIDN fast"]),
                                                 (f"{max(a.sweep)} spp",
                                                  images[f"{max(a.sweep)} spp"]),
                                                 (f"reference {a.ref_spp} spp", d["ref"])],
                                box=(200, 200))
            # timings at view 0, all methods in this run
            spec = self.view_spec(ds, 0)
            t_trace = self.scenes.trace_ms(spec, 3 * a.repeats)  # cheap; the load varies
            p0 = {n: self.view_data(ds, 0)[f"{n}@1"] for n in pb.PASSES}
            den = {m: pb.run_ours(p0, lv, a.model, a.repeats, a.threads)
                   for m, lv in (("ours 1 level", 1), ("ours", 0))}
            den.update({f"OIDN {q}": pb.run_oidn(p0, q, a.repeats) for q in ("fast", "balanced")})
            self.results.setdefault("stages", {})[ds] = {
                "trace": t_trace, **{m: {k: den[m][k] for k in pb.STAGES + ("ms",)}
                                     for m in ("ours 1 level", "ours")}}
            rows: Dict[str, Dict[str, Any]] = {}
            for name, qs in quality.items():
                spp = int(name.split()[0]) if name.endswith(" spp") else 1
                denoise_ms = den[name]["ms"] if name in den else 0.0
                rows[name] = {
                    "dataset": ds, "method": name, "spp": spp,
                    "psnr": float(np.mean([q[0] for q in qs])),
                    "ssim": float(np.mean([q[1] for q in qs])),
                    "trace_ms": spp * t_trace, "denoise_ms": denoise_ms,
                    "frame_ms": spp * t_trace + denoise_ms, "views": len(qs),
                    "in_table": name in methods or spp in a.sweep,
                }
            summary += [r for r in rows.values() if r["in_table"]]
            chart_rows += list(rows.values())
            sweep = [rows[f"{n} spp"] for n in counts]
            for m in methods:
                speedups.append({"dataset": ds, "method": m,
                                 **self.speedup(sweep, rows[m], t_trace)})
            self.results.setdefault("reference_check", {})[ds] = ref_checks
            self.psnr_time_chart(ds, sweep, {m: rows[m] for m in methods},
                                 next(s for s in speedups
                                      if s["dataset"] == ds and s["method"] == "ours"))
        self.save("table1", summary)
        self.save("table1_per_view", per_view)
        self.save("speedup", speedups)
        self.save("psnr_time", chart_rows)
        self.results.update(table1=summary, speedup=speedups)
        self.md_table1(summary, speedups)

    @staticmethod
    def speedup(sweep: Sequence[Mapping[str, Any]], method: Mapping[str, Any],
                t_trace: float) -> Dict[str, Any]:
        """Smallest swept spp whose PSNR reaches the method's, its time / the method's time;
        also the log2-interpolated equal-quality spp."""
        target = method["psnr"]
        hit = next((r for r in sweep if r["psnr"] >= target), None)
        out: Dict[str, Any] = {"psnr": target, "frame_ms": method["frame_ms"]}
        if hit is None:
            top = sweep[-1]
            out.update(matched_spp=None, lower_bound=True, matched_ms=top["frame_ms"],
                       speedup=top["frame_ms"] / method["frame_ms"], interp_spp=None,
                       interp_speedup=None)
            return out
        out.update(matched_spp=hit["spp"], lower_bound=False, matched_ms=hit["frame_ms"],
                   speedup=hit["frame_ms"] / method["frame_ms"])
        i = sweep.index(hit)
        if i == 0:
            n_eq = 1.0
        else:
            lo = sweep[i - 1]
            f = (target - lo["psnr"]) / max(hit["psnr"] - lo["psnr"], 1e-9)
            n_eq = 2 ** (math.log2(lo["spp"]) + f * (math.log2(hit["spp"]) - math.log2(lo["spp"])))
        out.update(interp_spp=n_eq, interp_speedup=n_eq * t_trace / method["frame_ms"])
        return out

    def psnr_time_chart(self, ds: str, sweep: Sequence[Mapping[str, Any]],
                        methods: Mapping[str, Mapping[str, Any]],
                        mark: Mapping[str, Any]) -> None:
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(7, 4.6))
        ax.plot([r["frame_ms"] for r in sweep], [r["psnr"] for r in sweep], "-o", color="0.4",
                ms=3, label="path tracing, N spp")
        for r in sweep:
            if r["spp"] in self.args.sweep:
                ax.annotate(f"{r['spp']}", (r["frame_ms"], r["psnr"]), fontsize=7,
                            textcoords="offset points", xytext=(-4, 6))
        styles = {"ours 1 level": ("s", "tab:blue"), "ours": ("D", "tab:green"),
                  "OIDN fast": ("^", "tab:orange"), "OIDN balanced": ("v", "tab:red")}
        for m, r in methods.items():
            mk, c = styles[m]
            ax.plot([r["frame_ms"]], [r["psnr"]], mk, color=c, ms=8, label=f"1 spp + {m}")
        if mark.get("matched_ms"):
            ax.plot([mark["frame_ms"], mark["matched_ms"]], [mark["psnr"]] * 2, "--",
                    color="tab:green", lw=1)
            tag = ">" if mark["lower_bound"] else ""
            ax.annotate(f"{tag}{mark['speedup']:.1f}× (quality-matched)",
                        (math.sqrt(mark["frame_ms"] * mark["matched_ms"]), mark["psnr"]),
                        textcoords="offset points", xytext=(0, -12), ha="center", fontsize=8,
                        color="tab:green")
        ax.set_xscale("log")
        ax.set_xlabel("time per frame [ms] (log; N spp = N × measured 1-spp trace)")
        ax.set_ylabel("PSNR [dB] (mean over views)")
        ax.set_title(f"{ds}, {self.args.size}², {self.args.views} view(s), reference "
                     f"{self.args.ref_spp} spp")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8, loc="lower right")
        fig.tight_layout()
        rows = [dict(r) for r in sweep] + [dict(r) for r in methods.values()]
        self.save(f"psnr_time_{ds}", rows, fig)

    def md_table1(self, summary: Sequence[Mapping[str, Any]],
                  speedups: Sequence[Mapping[str, Any]]) -> None:
        a = self.args
        md = self.md
        md += ["## 1. Paper Table 1: quality and time per dataset", "",
               f"{a.size}² pixels, {a.views} view(s) per dataset (camera azimuth/elevation "
               f"{', '.join(f'{VIEWS[v][0]:.0f}°/{VIEWS[v][1]:.0f}°' for v in range(a.views))}),"
               f" PSNR/SSIM = mean over the views against a {a.ref_spp}-spp reference of an "
               f"independent seed. Time per frame: N spp = N × the median 1-spp trace time; "
               f"denoisers = 1-spp trace + the median denoise time (ours: vtkPTVDenoiser "
               f"with the shipped model; OIDN: pyoidn RT filter, HDR colour + albedo + normal), "
               f"all on the same 1-spp passes, view 0, median of {a.repeats} after a warm-up "
               f"(the trace: median of {3 * a.repeats} fresh frames).",
               ""]
        checks = self.results.get("reference_check", {})
        md += ["Reference convergence: PSNR of the first half (ref/2 spp) against the full "
               "reference, per view: " + "; ".join(
                   f"{ds} {', '.join(f'{c:.1f}' for c in v)} dB" for ds, v in checks.items())
               + ". The reference's own noise bounds the PSNR a method can show to about "
               "this figure + 3 dB.", ""]
        for ds in a.datasets:
            rows = [r for r in summary if r["dataset"] == ds]
            md += [f"### {ds}", ""]
            md += md_table(["method", "PSNR [dB]", "SSIM", "ms / frame", "of which denoise"],
                           [[r["method"] if r["method"].endswith("spp") else
                             f"1 spp + {r['method']}", fmt(r["psnr"]), fmt(r["ssim"], 4),
                             fmt(r["frame_ms"], 1), fmt(r["denoise_ms"], 1)] for r in rows])
            md += ["", f"![PSNR against time, {ds}](psnr_time_{ds}.png)", "",
                   f"![{ds}: 1 spp, ours, OIDN fast, {max(a.sweep)} spp, reference]"
                   f"(gallery/table1_{ds}.png)", ""]
        md += ["## 2. PSNR against time: the quality-matched speed-up", "",
               "The charts above (one per dataset) put every method at its time per frame; "
               "the dashed line marks the speed-up of ours (the model's levels). Target: ≥ 10×; the "
               "paper reports about 6×.", "",
               "Time of the smallest spp count (from the sweep and intermediate counts "
               f"{', '.join(map(str, self.counts()))}) whose PSNR reaches the denoised PSNR, "
               "divided by the time of 1 spp + denoising; the interpolated column takes the "
               "equal-quality spp by linear interpolation of PSNR in log2(spp). A '>' marks "
               "a lower bound (no swept count reached the denoised PSNR).", ""]
        md += md_table(["dataset", "method", "PSNR [dB]", "matched spp", "speed-up",
                        "interp. spp", "interp. speed-up"],
                       [[s["dataset"], s["method"], fmt(s["psnr"]),
                         f">{max(self.counts())}" if s["lower_bound"] else s["matched_spp"],
                         (">" if s["lower_bound"] else "") + fmt(s["speedup"], 1) + "×",
                         fmt(s["interp_spp"], 1),
                         fmt(s["interp_speedup"], 1) + ("×" if s["interp_speedup"] else "")]
                        for s in speedups])
        md += [""]
        lines = []
        for ds in a.datasets:
            r = {x["method"]: x for x in summary if x["dataset"] == ds}
            o, f = r["ours"], r["OIDN fast"]
            at = {n: fmt(r[f"{n} spp"]["psnr"]) if f"{n} spp" in r else "n/a" for n in (8, 16)}
            lines.append(
                f"* {ds}: 1 spp + ours {o['psnr']:.2f} dB vs 8 spp {at[8]} dB and "
                f"16 spp {at[16]} dB (1 spp {r['1 spp']['psnr']:.2f} dB); OIDN fast "
                f"takes {f['denoise_ms'] / o['denoise_ms']:.1f}× our denoise time, PSNR ours − "
                f"OIDN fast = {o['psnr'] - f['psnr']:+.2f} dB (balanced: "
                f"{o['psnr'] - r['OIDN balanced']['psnr']:+.2f} dB).")
        md += ["Headlines:", ""] + lines + [""]
        self.results["headlines"] = lines

    # 3: the training studies
    def training(self) -> None:
        md = self.md
        md += ["## 3. Paper Tables 2, 3, 4: training studies", "",
               "Read from the results of the training studies (issue #5) in "
               "`Training/results/` when present (committed unless marked); not re-measured "
               "by this script.", ""]
        found = {}

        def tracked(path: Path) -> str:
            """'' when git tracks ``path`` unchanged, else a note saying it is not committed."""
            ok = subprocess.run(["git", "ls-files", "--error-unmatch", str(path)], cwd=ROOT,
                                capture_output=True).returncode == 0 and subprocess.run(
                ["git", "diff", "--quiet", "HEAD", "--", str(path)], cwd=ROOT).returncode == 0
            return "" if ok else " (working copy, not committed at this commit)"
        for table, stem, title in (("Table 2", "unet", "autoencoder (U-Net) baseline vs ours"),
                                   ("Table 3", "loo", "leave-one-out generalization"),
                                   ("Table 4", "ablation", "auxiliary-feature ablation")):
            md += [f"### {table}: {title}", ""]
            mdfile = ROOT / "Training/results" / f"{stem}.md"
            jsfile = ROOT / "Training/results" / f"{stem}.json"
            if mdfile.exists():
                text = mdfile.read_text().strip().splitlines()
                text = [("#### " + t.lstrip("# ")) if t.startswith("#") else t for t in text]
                md += [f"From `Training/results/{stem}.md`{tracked(mdfile)}:", ""] + text + [""]
                found[stem] = str(mdfile.relative_to(ROOT))
            elif jsfile.exists():
                md += [f"From `Training/results/{stem}.json`{tracked(jsfile)} (no Markdown "
                       "version):", "",
                       "```json", jsfile.read_text()[:4000].strip(), "```", ""]
                found[stem] = str(jsfile.relative_to(ROOT))
            else:
                md += [f"Not available: `Training/results/{stem}.md` / `.json` do not exist "
                       "at this commit.", ""]
                found[stem] = None
        self.results["training"] = found

    # 4: temporal stability
    def temporal(self) -> None:
        a = self.args
        static_rows: List[Dict[str, Any]] = []
        for ds in tqdm(a.datasets, desc="temporal (static)", unit="dataset"):
            spec = self.view_spec(ds, 0)
            ref = self.view_data(ds, 0)["ref"]
            seqs: Dict[str, List[np.ndarray]] = {}
            for i in range(a.static_frames):
                p = self.scenes.frame(spec, 2000 + i)
                seqs.setdefault("noisy 1 spp", []).append(p["Radiance"])
                seqs.setdefault("ours", []).append(self.denoise(p))
                seqs.setdefault("OIDN fast", []).append(pb.oidn(p, "fast"))
            # the mapper's own behaviour when the camera stops: the k-th frame shows the
            # denoised mean of k spp (one seed)
            scene = self.scenes.scene(spec)
            acc, acc_noisy = [], []

            def grab(k: int) -> None:
                p = scene.passes()
                acc_noisy.append(p["Radiance"])
                acc.append(self.denoise(p))
            scene.render(3000, a.static_frames, grab)
            seqs["noisy accumulation"] = acc_noisy
            seqs["ours + accumulation"] = acc
            for m, frames in seqs.items():
                tm = [pb.tonemap(f) for f in frames]
                tp = tpsnr(tm)
                static_rows.append({
                    "dataset": ds, "method": m, "frames": len(frames),
                    "flicker_std": flicker(tm), "tpsnr_mean": float(np.mean(tp)),
                    "psnr_mean": float(np.mean([pb.quality(ref, f)[0] for f in frames])),
                    "finite": bool(all(np.isfinite(f).all() for f in frames))})
            by = {r["method"]: r for r in static_rows if r["dataset"] == ds}
            for r in static_rows:
                if r["dataset"] == ds:
                    r["ratio_to_noisy"] = r["flicker_std"] / by["noisy 1 spp"]["flicker_std"]
                    r["ratio_to_oidn"] = r["flicker_std"] / by["OIDN fast"]["flicker_std"]
        orbit_rows: List[Dict[str, Any]] = []
        series: Dict[str, Dict[str, List[float]]] = {}
        for ds in tqdm(a.orbit_datasets, desc="temporal (orbit)", unit="dataset"):
            seqs = {}
            for i in range(a.orbit_frames):
                spec = self.view_spec(ds, 0)
                spec["azimuth"] += i * a.orbit_step
                p = self.scenes.frame(spec, 4000 + i)
                seqs.setdefault("noisy 1 spp", []).append(p["Radiance"])
                seqs.setdefault("ours", []).append(self.denoise(p))
                seqs.setdefault("OIDN fast", []).append(pb.oidn(p, "fast"))
                seqs.setdefault(f"converged ({a.orbit_ref_spp} spp)", []).append(
                    self.reference(spec, a.orbit_ref_spp, 6000 + i)["ref"])
            conv = [pb.tonemap(f) for f in seqs[f"converged ({a.orbit_ref_spp} spp)"]]
            for m, frames in seqs.items():
                tm = [pb.tonemap(f) for f in frames]
                tp = tpsnr(tm)
                series.setdefault(ds, {})[m] = tp
                orbit_rows.append({
                    "dataset": ds, "method": m, "frames": len(frames),
                    "tpsnr_mean": float(np.mean(tp)), "tpsnr_min": float(np.min(tp)),
                    "psnr_vs_converged": float(np.mean([
                        10 * math.log10(1 / max(float(np.mean((x - c) ** 2)), 1e-10))
                        for x, c in zip(tm, conv)]))})
        self.results["temporal"] = {"static": static_rows, "orbit": orbit_rows}
        self.temporal_charts(static_rows, series)
        self.md_temporal(static_rows, orbit_rows)

    def temporal_charts(self, static_rows: Sequence[Mapping[str, Any]],
                        series: Mapping[str, Mapping[str, Sequence[float]]]) -> None:
        import matplotlib.pyplot as plt
        methods = list(dict.fromkeys(r["method"] for r in static_rows))
        fig, ax = plt.subplots(figsize=(7, 3.8))
        width = 0.8 / max(len(methods), 1)
        for j, m in enumerate(methods):
            vals = [next(r["flicker_std"] for r in static_rows
                         if r["dataset"] == ds and r["method"] == m) for ds in self.args.datasets]
            ax.bar(np.arange(len(vals)) + j * width, vals, width, label=m)
        ax.set_xticks(np.arange(len(self.args.datasets)) + 0.4 - width / 2)
        ax.set_xticklabels(self.args.datasets)
        ax.set_ylabel("mean per-pixel std (tone-mapped)")
        ax.set_title(f"fixed view, {self.args.static_frames} frames")
        ax.legend(fontsize=8)
        fig.tight_layout()
        self.save("temporal_static", list(static_rows), fig)
        fig, ax = plt.subplots(figsize=(7, 3.8))
        rows = []
        for ds, per in series.items():
            for m, tp in per.items():
                ax.plot(np.arange(1, len(tp) + 1), tp, label=f"{ds}: {m}")
                rows += [{"dataset": ds, "method": m, "pair": i + 1, "tpsnr": v}
                         for i, v in enumerate(tp)]
        ax.set_xlabel(f"frame pair (camera moves {self.args.orbit_step}° per frame)")
        ax.set_ylabel("temporal PSNR [dB]")
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
        fig.tight_layout()
        self.save("temporal_orbit", rows, fig)

    def md_temporal(self, static_rows: Sequence[Mapping[str, Any]],
                    orbit_rows: Sequence[Mapping[str, Any]]) -> None:
        a = self.args
        self.md += [
            "## 4. Temporal stability", "",
            f"**Fixed view** (view 0, {a.size}²): {a.static_frames} independent 1-spp frames "
            "(seeds differ), each shown noisy, denoised by ours (the model's levels) and by OIDN "
            "fast; plus the mapper's own behaviour when the camera stops: the k-th frame shows "
            "the (denoised) mean of k spp of one seed. Flicker = per-pixel standard deviation "
            "over the frames of the tone-mapped images, averaged over the image; tPSNR = PSNR "
            "between consecutive frames (higher = steadier); PSNR against the reference.", ""]
        self.md += md_table(
            ["dataset", "method", "flicker (std)", "÷ noisy", "÷ OIDN", "tPSNR [dB]",
             "PSNR [dB]", "finite"],
            [[r["dataset"], r["method"], fmt(r["flicker_std"], 4), fmt(r["ratio_to_noisy"], 3),
              fmt(r["ratio_to_oidn"], 3), fmt(r["tpsnr_mean"]), fmt(r["psnr_mean"]),
              r["finite"]] for r in static_rows])
        verdicts = []
        for ds in a.datasets:
            by = {r["method"]: r for r in static_rows if r["dataset"] == ds}
            o = by["ours"]
            verdicts.append(
                f"* {ds}: ours / noisy = {o['ratio_to_noisy']:.3f} (target ≤ 0.25: "
                f"{'met' if o['ratio_to_noisy'] <= 0.25 else 'NOT met'}), ours / OIDN = "
                f"{o['ratio_to_oidn']:.3f} ({'below' if o['ratio_to_oidn'] < 1 else 'NOT below'}"
                f" OIDN); with accumulation {by['ours + accumulation']['ratio_to_noisy']:.3f} of "
                "the noisy flicker.")
        self.results["flicker_verdicts"] = verdicts
        self.md += ["", "![flicker](temporal_static.png)", ""] + verdicts + [""]
        self.md += [
            f"**Camera orbit** ({', '.join(a.orbit_datasets)}): {a.orbit_frames} frames, "
            f"{a.orbit_step}° of azimuth per frame, one fresh 1-spp frame per view (a new seed "
            "each), denoised per frame with no temporal filtering. The converged row "
            f"({a.orbit_ref_spp} spp per view) is what the camera motion alone costs in tPSNR.",
            ""]
        self.md += md_table(["dataset", "method", "mean tPSNR [dB]", "min tPSNR [dB]",
                             "PSNR vs converged [dB]"],
                            [[r["dataset"], r["method"], fmt(r["tpsnr_mean"]),
                              fmt(r["tpsnr_min"]), fmt(r["psnr_vs_converged"])]
                             for r in orbit_rows])
        self.md += ["", "![orbit tPSNR](temporal_orbit.png)", ""]
        self.md_temporal_reuse()

    def md_temporal_reuse(self) -> None:
        """The mapper's temporal reuse (TemporalReprojection), read from the results of
        Testing/Benchmarks/temporal_reuse.py (not re-measured here: it runs for ~15 min)."""
        path = ROOT / "Testing/Benchmarks/results/temporal_reuse.json"
        self.md += ["### Camera motion with temporal reuse", ""]
        if not path.exists():
            self.md += [f"Not available: `{path.relative_to(ROOT)}` does not exist.", ""]
            self.results["temporal_reuse"] = None
            return
        data = json.loads(path.read_text())
        rows, m = data["rows"], data["args"]["default_history"]
        self.md += [
            f"From `{path.relative_to(ROOT)}` (`{data['command']}`; its tables and chart: "
            "`results/temporal_reuse.md`): what the mapper shows while the camera moves, "
            f"{data['args']['size']}², {data['args']['frames']} views "
            f"{data['args']['step']}° apart, with TemporalReprojection on (MaximumHistory {m}) "
            "and off.", ""]
        reuse = f"ours + reprojection (M={m})"
        table = [[r["dataset"], r["case"], r["method"], fmt(r["tpsnr_mean"]),
                  "n/a" if r["method"].startswith("converged") else fmt(r["psnr_mean"]),
                  fmt(r.get("never_below"))]
                 for r in rows if r["method"] in (reuse, "ours per frame, new seed (report)",
                                                  "OIDN fast per frame")
                 or r["method"].startswith("converged")]
        self.md += md_table(["dataset", "case", "method", "mean tPSNR [dB]",
                             "PSNR vs converged [dB]", "worst frame vs no history [dB]"], table)
        verdicts = []
        for ds in dict.fromkeys(r["dataset"] for r in rows if r["case"] == "orbit"):
            by = {r["method"]: r for r in rows if r["dataset"] == ds and r["case"] == "orbit"}
            ours, today = by[reuse], by["ours per frame, new seed (report)"]
            conv = next(r for k, r in by.items() if k.startswith("converged"))
            oidn = by["OIDN fast per frame"]
            steady_conv = ours["tpsnr_mean"] >= conv["tpsnr_mean"]
            steady_oidn = ours["tpsnr_mean"] >= oidn["tpsnr_mean"]
            verdicts.append(
                f"* {ds} orbit: tPSNR {ours['tpsnr_mean']:.2f} dB vs converged "
                f"{conv['tpsnr_mean']:.2f} ({'met' if steady_conv else 'NOT met'})"
                f" and OIDN fast {oidn['tpsnr_mean']:.2f} "
                f"({'met' if steady_oidn else 'NOT met'}); PSNR "
                f"{ours['psnr_mean']:.2f} dB vs {today['psnr_mean']:.2f} per frame "
                f"({ours['psnr_mean'] - today['psnr_mean']:+.2f} dB; target +2: "
                f"{'met' if ours['psnr_mean'] - today['psnr_mean'] >= 2 else 'NOT met'}).")
        shares = [c["reproject_ms"] / c["render_ms"] for c in data["cost"]]
        if shares:
            typical, worst = statistics.median(shares), max(shares)
            verdicts.append(
                f"* reprojection cost: {100 * typical:.1f} % of the render (median of "
                f"{len(shares)} runs; target ≤ 5 %: {'met' if typical <= 0.05 else 'NOT met'}), "
                f"at most {100 * worst:.1f} % in one run.")
        flick = [r for r in data["static_flicker"] if r["method"].startswith("mapper")]
        verdicts += [f"* {r['dataset']} still view: flicker {r['ratio_to_oidn']:.3f} of OIDN "
                     "fast's (the mapper accumulates while the camera rests)." for r in flick]
        self.md += [""] + verdicts + [""]
        self.results["temporal_reuse"] = {"source": str(path.relative_to(ROOT)),
                                          "verdicts": verdicts}

    # 5: stress suite
    def stress_cases(self) -> List[Dict[str, Any]]:
        s = self.args.stress_size
        bw, bh = (int(v) for v in self.args.big_size.lower().split("x"))
        base = {"volume": "head", "preset": "paper", "size": [s, s], "azimuth": 30.0,
                "elevation": 10.0}
        r = self.args.stress_ref_spp
        return [
            {"name": "baseline", "spec": base, "ref_spp": r,
             "what": "head, two-band preset, for comparison"},
            {"name": "translucent", "spec": {**base, "preset": "translucent"}, "ref_spp": r,
             "what": "the head's bands at ≤5 % opacity: no opaque surface, deep scattering"},
            {"name": "strong light", "spec": {**base, "light": 20.0, "specular": [1.0, 80.0]},
             "ref_spp": r, "exposure": 0.05,
             "what": "key light ×20 (LightIntensity 20), specular 1 / power 80, radiance "
                     "×0.05 so the image is not clipped"},
            {"name": "fireflies", "spec": base, "ref_spp": r, "fireflies": [0.002, 100.0],
             "what": "synthetic unbiased fireflies: 0.2 % of the pixels ×100, the rest "
                     "×0.8 (the expectation is unchanged)"},
            {"name": "thin (stent)", "spec": {**base, "volume": "stent", "dolly": 0.7},
             "ref_spp": r, "what": "stent struts zoomed out to 1-2 pixels"},
            {"name": "exposure ×0.01", "spec": base, "ref_spp": r, "exposure": 0.01,
             "what": "radiance ×0.01 (input and reference; = light and environment ×0.01)"},
            {"name": "exposure ×100", "spec": base, "ref_spp": r, "exposure": 100.0,
             "what": "radiance ×100 (input and reference; = light and environment ×100)"},
            {"name": "8×8", "spec": {**base, "size": [8, 8]}, "ref_spp": r,
             "what": "tiny image (smaller than the coarsest grid cell)"},
            {"name": "1000×7", "spec": {**base, "size": [1000, 7]}, "ref_spp": r,
             "what": "extreme aspect ratio"},
            {"name": f"{bw}×{bh}", "spec": {**base, "size": [bw, bh]},
             "ref_spp": self.args.big_ref_spp,
             "what": f"large image; reference only {self.args.big_ref_spp} spp (time)"},
            {"name": "mostly empty", "spec": {**base, "volume": "head_padded"}, "ref_spp": r,
             "what": "head (2× downsampled) in a 3× larger air volume: 96 % empty voxels, "
                     "head small in the image"},
            {"name": "unseen volume", "spec": {**base, "volume": "procedural",
                                               "preset": "procedural", "elevation": 25.0},
             "ref_spp": r, "what": "procedural torus + blobs, 96³ float, new colours"},
        ]

    def stress(self) -> None:
        rows: List[Dict[str, Any]] = []
        (self.out / "gallery").mkdir(exist_ok=True)
        for case in tqdm(self.stress_cases(), desc="stress", unit="case"):
            spec, f = case["spec"], case.get("exposure", 1.0)
            p = self.scenes.frame(spec, SEED_INPUT)
            ref = self.reference(spec, case["ref_spp"])
            p["Radiance"] = p["Radiance"] * f
            if case.get("fireflies"):
                prob, gain = case["fireflies"]
                hit = np.random.default_rng(11).random(p["Radiance"].shape[:2]) < prob
                w = np.where(hit, gain, (1 - prob * gain) / (1 - prob)).astype(np.float32)
                p["Radiance"] = p["Radiance"] * w[..., None]
            reference = ref["ref"] * f
            images = {"noisy": p["Radiance"]}
            start = time.perf_counter()
            images["ours"] = self.denoise(p)
            ours_ms = 1000 * (time.perf_counter() - start)
            images["OIDN fast"] = pb.oidn(p, "fast")
            fixed = pb.Ours(0, self.args.model, self.args.threads)
            fixed.den.UseNetworkOff()
            images["ours, fixed guide"] = fixed(p)
            noclamp = pb.Ours(0, self.args.model, self.args.threads)
            noclamp.den.SetClamp(0.0)
            images["ours, no clamp"] = noclamp(p)
            row: Dict[str, Any] = {"case": case["name"], "what": case["what"],
                                   "size": "×".join(map(str, spec["size"])),
                                   "ref_spp": case["ref_spp"],
                                   "ref_check_psnr": pb.quality(ref["ref"], ref["half"])[0]}
            for k, img in images.items():
                q = pb.quality(reference, img)
                row[f"{k} psnr"], row[f"{k} ssim"] = q
                row[f"{k} finite"] = bool(np.isfinite(img).all())
            row["ours ms"] = ours_ms
            row["status"] = self.ours[0].status()
            row["lit fraction"] = float(np.mean(p["Alpha"] > 0))
            lum = p["Radiance"].mean(axis=-1)[p["Alpha"][..., 0] > 0]
            row["peak/mean"] = float(lum.max() / max(lum.mean(), 1e-30)) if lum.size else 0.0
            row["failed"] = bool(not row["ours finite"] or row["ours psnr"] < row["noisy psnr"])
            row["analysis"] = self.analyse(row)
            rows.append(row)
            safe = "".join(c if c.isalnum() else "_" for c in case["name"])
            self.thumbs(f"stress_{safe}", [("noisy", images["noisy"]), ("ours", images["ours"]),
                                           ("OIDN fast", images["OIDN fast"]),
                                           (f"ref {case['ref_spp']} spp", reference)])
            row["gallery"] = f"gallery/stress_{safe}.png"
        self.results["stress"] = rows
        self.stress_chart(rows)
        self.md_stress(rows)

    @staticmethod
    def analyse(row: Mapping[str, Any]) -> str:
        """A measured diagnosis: which variant recovers where ours loses to the noisy input."""
        notes = []
        if not row["ours finite"]:
            notes.append("non-finite output from our denoiser")
        if not row["noisy finite"]:
            notes.append("the traced input itself holds non-finite values")
        gain = row["ours psnr"] - row["noisy psnr"]
        if gain < 0:
            alt = {k: row[f"{k} psnr"] - row["noisy psnr"]
                   for k in ("ours, fixed guide", "ours, no clamp", "OIDN fast")}
            good = [f"{k} {v:+.2f} dB" for k, v in alt.items()]
            cause = []
            if alt["ours, no clamp"] > gain + 0.5:
                cause.append("the outlier clamp removes real energy (the clamp limits each "
                             "channel to 8× the mean; bright light is clipped)")
            if alt["ours, fixed guide"] > gain + 0.5:
                cause.append("the learned guide is worse than the fixed albedo/depth/normal "
                             "guide here (outside the training distribution)")
            if row["ref_check_psnr"] < row["noisy psnr"] + 6:
                cause.append("the reference is itself noisy (ref/2 vs ref "
                             f"{row['ref_check_psnr']:.1f} dB), which bounds any gain")
            if not cause:
                cause.append("over-blurring: the grid averages detail the reference keeps")
            notes.append(f"denoised loses {-gain:.2f} dB to the noisy input; variants vs noisy: "
                         f"{', '.join(good)}; likely cause: {'; '.join(cause)}")
        return "; ".join(notes) if notes else "ok"

    def stress_chart(self, rows: Sequence[Mapping[str, Any]]) -> None:
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(9, 4))
        keys = ("noisy", "ours", "OIDN fast", "ours, fixed guide")
        width = 0.8 / len(keys)
        for j, k in enumerate(keys):
            ax.bar(np.arange(len(rows)) + j * width, [r[f"{k} psnr"] for r in rows], width,
                   label=k)
        ax.set_xticks(np.arange(len(rows)) + 0.4 - width / 2)
        ax.set_xticklabels([r["case"] for r in rows], rotation=30, ha="right", fontsize=8)
        ax.set_ylabel("PSNR [dB]")
        ax.legend(fontsize=8, ncol=4)
        ax.grid(axis="y", alpha=0.3)
        fig.tight_layout()
        self.save("stress", [{k: v for k, v in r.items()} for r in rows], fig)

    def md_stress(self, rows: Sequence[Mapping[str, Any]]) -> None:
        a = self.args
        self.md += [
            "## 5. Stress suite", "",
            f"Head view 0 unless stated, {a.stress_size}² unless stated, one 1-spp frame "
            f"(seed {SEED_INPUT}) against a {a.stress_ref_spp}-spp reference of another seed "
            "(unless stated). Ours = the model's levels; the two variants (fixed guide = no "
            "network; no clamp = outlier clamp off) locate the cause where ours loses. "
            "'finite' = every output pixel finite (np.isfinite).", ""]
        self.md += md_table(
            ["case", "what", "size", "lit %", "peak / mean", "noisy PSNR", "ours PSNR",
             "OIDN fast", "fixed guide", "no clamp", "ours SSIM", "all finite", "verdict"],
            [[r["case"], r["what"], r["size"], fmt(100 * r["lit fraction"], 0),
              fmt(r["peak/mean"], 1), fmt(r["noisy psnr"]), fmt(r["ours psnr"]),
              fmt(r["OIDN fast psnr"]), fmt(r["ours, fixed guide psnr"]),
              fmt(r["ours, no clamp psnr"]), fmt(r["ours ssim"], 3),
              all(r[f"{k} finite"] for k in STRESS_METHODS),
              "**FAILED**" if r["failed"] else "ok"] for r in rows])
        failed = [r for r in rows if r["failed"] or r["analysis"] != "ok"]
        self.md += ["", "![stress](stress.png)", ""]
        if failed:
            self.md += ["Cases where the denoised image is worse than the noisy input or not "
                        "finite (measured diagnosis):", ""]
            self.md += [f"* **{r['case']}**: {r['analysis']}" for r in failed]
        else:
            self.md += ["No case made the denoised image worse than the noisy input, and every "
                        "output is finite."]
        self.md += ["", "Gallery (noisy | ours | OIDN fast | reference):", ""]
        self.md += [f"* {r['case']}: ![{r['case']}]({r['gallery']})" for r in rows]
        self.md += [""]

    # 6: where the time goes
    def timing(self) -> None:
        import matplotlib.pyplot as plt
        a = self.args
        stage_rows = []
        for ds, st in self.results.get("stages", {}).items():
            for m in ("ours 1 level", "ours"):
                stage_rows.append({"dataset": ds, "method": m, "trace": st["trace"],
                                   **{k: st[m][k] for k in pb.STAGES},
                                   "denoise_total": st[m]["ms"]})
        size_rows = []
        for s in tqdm(a.scaling_sizes, desc="timing: image size", unit="size"):
            spec = self.view_spec("head", 0, s)
            t = self.scenes.trace_ms(spec, a.repeats)
            p = self.scenes.frame(spec, SEED_INPUT)
            o = pb.run_ours(p, 0, a.model, a.repeats, a.threads)
            f = pb.run_oidn(p, "fast", a.repeats)
            size_rows.append({"size": s, "pixels": s * s, "trace": t,
                              **{k: o[k] for k in pb.STAGES}, "denoise": o["ms"],
                              "oidn_fast": f["ms"]})
        vol_rows = []
        for f in tqdm(a.volume_shrink, desc="timing: volume size", unit="volume"):
            name = "head" if f == 1 else f"head_shrink{f}"
            spec = {**self.view_spec("head", 0), "volume": name}
            dims = self.scenes.volume(name).GetDimensions()
            vol_rows.append({"shrink": f, "dims": "×".join(map(str, dims)),
                             "voxels": int(np.prod(dims)),
                             "trace": self.scenes.trace_ms(spec, a.repeats)})
        thread_rows = []
        spec = self.view_spec("head", 0)
        p = self.scenes.frame(spec, SEED_INPUT)
        for th in (1, 2):
            o = pb.run_ours(p, 0, a.model, a.repeats, th)
            thread_rows.append({"threads": th, "trace": self.scenes.trace_ms(spec, a.repeats, th),
                                **{k: o[k] for k in pb.STAGES}, "denoise": o["ms"]})
        self.results["timing"] = {"stages": stage_rows, "image_size": size_rows,
                                  "volume_size": vol_rows, "threads": thread_rows}
        if stage_rows:
            fig, ax = plt.subplots(figsize=(7, 3.6))
            labels = [f"{r['dataset']}\n{r['method'].replace('ours ', '')}" for r in stage_rows]
            bottom = np.zeros(len(stage_rows))
            for k in ("trace",) + pb.STAGES:
                vals = np.array([r[k] for r in stage_rows])
                ax.bar(labels, vals, bottom=bottom, label=k)
                bottom += vals
            ax.set_ylabel("ms (median)")
            ax.set_title(f"1 spp + denoise, {a.size}²")
            ax.legend(fontsize=8)
            fig.tight_layout()
            self.save("timing_stages", stage_rows, fig)
        fig, axes = plt.subplots(1, 3, figsize=(11, 3.6))
        ax = axes[0]
        px = [r["pixels"] for r in size_rows]
        for k in ("trace", "denoise", "oidn_fast") + pb.STAGES:
            ax.plot(px, [r[k] for r in size_rows], "-o", ms=3, label=k,
                    lw=2 if k in ("trace", "denoise", "oidn_fast") else 0.8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("pixels")
        ax.set_ylabel("ms")
        ax.set_title("image size (head)")
        ax.legend(fontsize=7)
        ax = axes[1]
        ax.plot([r["voxels"] for r in vol_rows], [r["trace"] for r in vol_rows], "-o")
        ax.set_xscale("log")
        ax.set_xlabel("voxels")
        ax.set_ylabel("trace ms")
        ax.set_title(f"volume size ({a.size}²)")
        ax = axes[2]
        x = np.arange(2)
        ax.bar(x - 0.2, [r["trace"] for r in thread_rows], 0.4, label="trace")
        ax.bar(x + 0.2, [r["denoise"] for r in thread_rows], 0.4, label="denoise")
        ax.set_xticks(x)
        ax.set_xticklabels(["1 thread", "2 threads"])
        ax.set_ylabel("ms")
        ax.set_title(f"threads ({a.size}²)")
        ax.legend(fontsize=8)
        fig.tight_layout()
        self.save("timing_scaling", {"image_size": size_rows, "volume_size": vol_rows,
                                     "threads": thread_rows}, fig)
        write_csv(self.out / "timing_image_size.csv", size_rows)
        write_csv(self.out / "timing_volume_size.csv", vol_rows)
        write_csv(self.out / "timing_threads.csv", thread_rows)
        self.files += ["timing_image_size.csv", "timing_volume_size.csv", "timing_threads.csv"]
        self.md_timing(stage_rows, size_rows, vol_rows, thread_rows)

    def md_timing(self, stage_rows: Sequence[Mapping[str, Any]],
                  size_rows: Sequence[Mapping[str, Any]], vol_rows: Sequence[Mapping[str, Any]],
                  thread_rows: Sequence[Mapping[str, Any]]) -> None:
        a = self.args
        md = self.md
        md += ["## 6. Where the time goes", "",
               f"Median of {a.repeats} after a warm-up, milliseconds. Trace = the mapper's "
               "`GetLastTraceTime()` of a fresh 1-spp frame; features, GuideNet, splat "
               "(incl. demodulation and clamp) and slice = `vtkPTVDenoiser::GetLast*Time()`; "
               "denoise = the whole `Execute()` call.", ""]
        if stage_rows:
            md += [f"**Per stage** ({a.size}², view 0):", ""]
            md += md_table(["dataset", "levels", "trace", "features", "GuideNet", "splat",
                            "slice", "denoise total", "denoise ÷ trace"],
                           [[r["dataset"], "model's" if r["method"] == "ours" else r["method"].replace("ours ", ""),
                             fmt(r["trace"], 1)]
                            + [fmt(r[k], 1) for k in pb.STAGES]
                            + [fmt(r["denoise_total"], 1),
                               fmt(r["denoise_total"] / r["trace"], 2)] for r in stage_rows])
            md += ["", "![stages](timing_stages.png)", ""]
        md += ["**Image size** (head, view 0; denoise with the model's levels):", ""]
        md += md_table(["size", "trace", "features", "GuideNet", "splat", "slice", "denoise",
                        "OIDN fast", "ns / pixel (trace + denoise)"],
                       [[f"{r['size']}²", fmt(r["trace"], 1)]
                        + [fmt(r[k], 1) for k in pb.STAGES]
                        + [fmt(r["denoise"], 1), fmt(r["oidn_fast"], 1),
                           fmt(1e6 * (r["trace"] + r["denoise"]) / r["pixels"], 0)]
                        for r in size_rows])
        md += ["", "**Volume size** (head downsampled by vtkImageShrink3D with averaging, "
               f"{a.size}²; the denoiser does not see the volume):", ""]
        md += md_table(["shrink", "voxels", "dims", "trace ms"],
                       [[r["shrink"], r["voxels"], r["dims"], fmt(r["trace"], 1)]
                        for r in vol_rows])
        md += ["", f"**Threads** (head, {a.size}²; `NumberOfThreads` of mapper and denoiser):",
               ""]
        md += md_table(["threads", "trace", "features", "GuideNet", "splat", "slice",
                        "denoise"],
                       [[r["threads"], fmt(r["trace"], 1)] + [fmt(r[k], 1) for k in pb.STAGES]
                        + [fmt(r["denoise"], 1)] for r in thread_rows])
        if len(thread_rows) == 2:
            t1, t2 = thread_rows
            md += ["", f"2 threads vs 1: trace {t1['trace'] / t2['trace']:.2f}×, denoise "
                   f"{t1['denoise'] / t2['denoise']:.2f}× (on a 2-core machine shared with "
                   "other work, see the load average in the header: a second thread only helps "
                   "when a core is free; `results/tracer.md` has the tracer's 1- vs 2-thread "
                   "times from a quieter run)."]
        md += ["", "![scaling](timing_scaling.png)", ""]

    # gallery
    def thumbs(self, name: str, panels: Sequence[Tuple[str, np.ndarray]],
               box: Tuple[int, int] = (150, 110)) -> None:
        """One PNG strip of tone-mapped thumbnails (nearest neighbour, aspect kept within
        ``box``, at least 6 pixels tall), captioned."""
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
        (self.out / "gallery").mkdir(exist_ok=True)
        with atomic_path(self.out / "gallery" / f"{name}.png", suffix=".tmp.png") as tmp:
            fig.savefig(tmp, dpi=100)
        plt.close(fig)
        self.files.append(f"gallery/{name}.png")

    # the report
    def run(self, argv: Sequence[str]) -> int:
        a = self.args
        self.out.mkdir(parents=True, exist_ok=True)
        started = time.time()
        load0 = os.getloadavg()
        info = machine_info(a.model)
        body_start = len(self.md)
        steps = {"table1": self.table1, "training": self.training, "temporal": self.temporal,
                 "stress": self.stress, "timing": self.timing}
        for name in SECTIONS:
            if name in a.sections:
                steps[name]()
        body = self.md[body_start:]
        status = self.ours[0].status()
        elapsed = time.time() - started
        load1 = os.getloadavg()
        niceness = os.nice(0)
        command = ("PYTHONPATH=build/python " + ("" if niceness == 0 else f"nice -n {niceness} ")
                   + "xvfb-run -a -s \"-screen 0 2000x1200x24 "
                   "-noreset\" .venv/bin/python Testing/Benchmarks/evaluate_report.py"
                   + ("" if not argv else " " + shlex.join(argv)))
        head = [
            "# PathTracedVolume evaluation report", "",
            "Generated by `Testing/Benchmarks/evaluate_report.py` "
            f"on {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC "
            f"in {elapsed / 60:.1f} min. Regenerate with:", "",
            "```sh", command, "```", "",
            "| | |", "|---|---|",
            f"| machine | {info['cpu']}, {info['cores']} cores, {info['ram']} RAM, "
            f"{info['os']} |",
            f"| load average (1 min) | {load0[0]:.2f} at start, {load1[0]:.2f} at the end "
            "(the cores are shared with other work: timings include that contention) |",
            f"| software | VTK {info['vtk']}, ONNX Runtime {info['onnxruntime']}, "
            f"{info['oidn']}, Python {info['python']} |",
            f"| git commit | {info['git']} |",
            f"| denoiser | {status}; model {info['model']} |",
            f"| timings | median of {a.repeats} repeats after a warm-up, threads "
            f"{a.threads or f'all ({os.cpu_count()})'}; 1-spp trace times of Table 1: median "
            f"of {3 * a.repeats} |",
            f"| sizes | Table 1 / temporal {a.size}², stress {a.stress_size}² (+ odd sizes), "
            f"references {a.ref_spp} spp (stress {a.stress_ref_spp}, {a.big_size} "
            f"{a.big_ref_spp}) |",
            "| protocol | docs/measuring.md: tone map clip(max(0,x)^(1/2.2),0,1); PSNR/SSIM "
            "scikit-image, data_range 1 |",
            f"| traced-image cache | {'off' if a.no_cache else a.cache} (tracer fingerprint "
            f"{self.fingerprint}; {self.cache.hits} hits, {self.cache.misses} renders) |",
            "",
        ]
        if a.quick:
            head += ["**Quick mode** (`--quick`, CI smoke test): tiny images and spp; the "
                     "figures below only show that the pipeline runs.", ""]
        headlines = self.results.get("headlines", []) + self.results.get("flicker_verdicts", [])
        fails = [r["case"] for r in self.results.get("stress", []) if r["failed"]]
        if headlines or "stress" in self.results:
            head += ["## Summary", ""] + headlines
            sp = [s for s in self.results.get("speedup", []) if s["method"] == "ours"]
            head += ["* quality-matched speed-up (ours; target ≥ 10×, paper ~6×): "
                     + ", ".join(f"{s['dataset']} {'>' if s['lower_bound'] else ''}"
                                 f"{s['speedup']:.1f}× (interpolated "
                                 f"{fmt(s['interp_speedup'], 1)}×)" for s in sp)] if sp else []
            if "stress" in self.results:
                head += [f"* stress cases where ours is worse than noisy or not finite: "
                         f"{', '.join(fails) if fails else 'none'}"]
            head += [""]
        files = sorted(set(self.files))
        tail = ["## Files", "", "Every figure's numbers: " + ", ".join(
            f"[{f}]({f})" for f in files if not f.endswith(".png")) + "; `results.json` holds "
            "everything above.", ""]
        write_text(self.out / "report.md", "\n".join(head + body + tail) + "\n")
        write_json(self.out / "results.json", {"command": command, "machine": info,
                                               "args": {k: str(v) for k, v in vars(a).items()},
                                               "elapsed_s": elapsed, "load": [load0, load1],
                                               "denoiser_status": status, **self.results})
        print(f"report: {self.out / 'report.md'} ({elapsed / 60:.1f} min)")
        return 0


def main(argv: Optional[Sequence[str]] = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    args = parse_args(argv)
    return Evaluation(args).run(argv)


if __name__ == "__main__":
    sys.exit(main())
