"""Shared pieces of the benchmarks: their scene (``pathtracedvolume.scene``), our denoiser and OIDN
on the same passes, the tone map and metrics of docs/measuring.md (``pathtracedvolume.metrics``),
and timing (median of repeats, interleaved rounds).

Needs the compiled package (``PYTHONPATH=<build>/python``) and a display (Xvfb) for rendering;
the metrics and timing helpers are plain NumPy. VTK is imported lazily, so importing this module
is cheap.
"""
from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path
from typing import Any, Callable, Dict, Mapping, Optional, Sequence, Tuple, TypeVar, Union

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT / "Python") not in sys.path:
    sys.path.append(str(ROOT / "Python"))  # after PYTHONPATH: a built package wins

from pathtracedvolume import scene  # noqa: E402 (the project's scene set-up)
from pathtracedvolume.metrics import quality, tonemap  # noqa: E402,F401 (the project's metrics)

PASSES = ["Radiance", "Alpha", "Albedo", "Depth", "Position", "Normal",
          "ScatterDepth", "ScatterPosition", "ScatterNormal", "Coverage",
          "Footprint"]
BACKGROUND = scene.BACKGROUND
STAGES = ("features", "guidenet", "splat", "slice", "alpha")
SHIPPED_MODEL = ROOT / "Data" / "Models" / "guidenet.onnx"

T = TypeVar("T")
Passes = Dict[str, np.ndarray]


# --- metrics and timing -------------------------------------------------------------------


def timed(fn: Callable[[], T], repeats: int) -> Tuple[float, T]:
    """(median milliseconds of ``repeats`` calls after one warm-up, the last result)."""
    result = fn()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        result = fn()
        times.append(1000.0 * (time.perf_counter() - start))
    return statistics.median(times), result


def interleaved(calls: Mapping[str, Callable[[], Any]], repeats: int,
                after: Optional[Mapping[str, Callable[[], Dict[str, float]]]] = None
                ) -> Dict[str, Dict[str, Any]]:
    """Every call of ``calls`` once per round, one warm-up round and then ``repeats`` timed
    rounds, so that a slow spell of a shared machine slows every method alike and ratios can be
    taken round by round (:func:`paired_ratio`). ``after[name]()`` is read after each timed call
    (e.g. per-stage times). Returns per name: ``times`` (ms per round), ``extra`` (the ``after``
    dicts), ``result`` (the last call's result)."""
    out: Dict[str, Dict[str, Any]] = {n: {"times": [], "extra": [], "result": None} for n in calls}
    for round_ in range(repeats + 1):
        for name, fn in calls.items():
            start = time.perf_counter()
            result = fn()
            ms = 1000.0 * (time.perf_counter() - start)
            out[name]["result"] = result
            if round_ == 0:
                continue
            out[name]["times"].append(ms)
            if after and name in after:
                out[name]["extra"].append(after[name]())
    return out


def _cpu_ticks() -> Optional[Tuple[int, int]]:
    """(steal, all) CPU ticks of the whole machine from /proc/stat's ``cpu`` line; None where
    there is none (not Linux)."""
    try:
        with open("/proc/stat", encoding="ascii") as f:
            fields = f.readline().split()
    except OSError:
        return None
    if len(fields) < 9 or fields[0] != "cpu":
        return None
    ticks = [int(v) for v in fields[1:9]]  # user nice system idle iowait irq softirq steal
    return ticks[7], sum(ticks)


class CpuSteal:
    """Hypervisor steal over a ``with`` block: the share of this machine's CPU time that the
    host gave to other guests while ours wanted to run (/proc/stat). A virtual machine's
    2-thread timings suffer most from it (a parallel loop waits for its slowest thread), so the
    benchmarks print it beside their ratios. ``fraction`` is None where it cannot be read."""

    def __enter__(self) -> "CpuSteal":
        self.fraction: Optional[float] = None
        self._start = _cpu_ticks()
        return self

    def __exit__(self, *exc: Any) -> None:
        end = _cpu_ticks()
        if self._start is not None and end is not None and end[1] > self._start[1]:
            self.fraction = (end[0] - self._start[0]) / (end[1] - self._start[1])


def save_results(rows: Any, table: str, json_path: Optional[Path], markdown_path: Optional[Path],
                 title: str, script: str) -> None:
    """Prints ``table`` and writes ``rows`` as JSON and ``table`` as a markdown page (``title``,
    then the command that made it: ``script`` under Xvfb on an idle machine), each only where a
    path is given; both atomically."""
    import json

    from pathtracedvolume.atomic import write_text
    print(table)
    if json_path:
        write_text(json_path, json.dumps(rows, indent=1))
    if markdown_path:
        write_text(markdown_path, f"# {title}\n\nCommand (idle machine): `PYTHONPATH=build/python "
                   f"xvfb-run -a -s \"-screen 0 1024x768x24 -noreset\" .venv/bin/python "
                   f"Testing/Benchmarks/{script} --json ... --markdown ...`\n\n{table}\n")


def paired_ratio(numerator: Sequence[float], denominator: Sequence[float]) -> float:
    """Median over rounds of numerator / denominator, both timed in the same round."""
    return statistics.median(a / b for a, b in zip(numerator, denominator))


# --- scenes (pathtracedvolume.scene) --------------------------------------------------------
load_dataset = scene.load_dataset
paper_preset = scene.paper_preset
make_property = scene.volume_property


class BenchScene(scene.Scene):
    """:class:`pathtracedvolume.scene.Scene` as the benchmarks use it: path traced, Denoise
    off (they denoise the passes themselves) with the Coverage and Footprint passes traced as the
    mapper traces them when it denoises with the shipped model (CoverageMarch,
    FootprintRays) and every pass kept (ScatterPasses), a view at ``azimuth`` 30 and
    ``elevation`` 10 by default, the mapper's default key light times ``light_intensity``;
    :meth:`render` starts a fresh accumulation with a seed."""

    def __init__(self, volume: Any, prop: Any, size: Tuple[int, int] = (256, 256),
                 azimuth: float = 30.0, elevation: float = 10.0, threads: int = 0,
                 light_intensity: float = 1.0, background: Sequence[float] = BACKGROUND
                 ) -> None:
        super().__init__(volume, prop, size, azimuth, elevation, denoise=False,
                         threads=threads, background=background)
        self.mapper.SetLightIntensity(float(light_intensity))
        self.mapper.GetExpertOptions().CoverageMarchOn()
        self.mapper.GetExpertOptions().FootprintRaysOn()
        self.mapper.GetExpertOptions().ScatterPassesOn()  # every pass of PASSES

    def orbit(self, azimuth: float, elevation: float = 10.0, dolly: float = 1.0) -> None:
        """Another view (:func:`pathtracedvolume.scene.place_camera`)."""
        self.view(azimuth, elevation, dolly)

    def render(self, seed: int, frames: int = 1,  # type: ignore[override]
               on_frame: Optional[Callable[[int], None]] = None) -> list:
        """Start a fresh accumulation with ``seed`` and render ``frames`` 1-spp frames; returns
        each frame's trace milliseconds; ``on_frame(k)`` after frame k (1-based)."""
        self.mapper.SetSeed(int(seed))
        self.mapper.GetExpertOptions().SetMaximumAccumulatedFrames(max(int(frames), 1))
        self.mapper.ResetAccumulation()
        return super().render(frames, on_frame)

    def grab(self, name: str = "Radiance") -> np.ndarray:
        """Pass ``name`` of the current accumulation as (H, W, C) float32, bottom row first."""
        return self.get_pass(name)

    def passes(self) -> Passes:
        """Every pass of the current accumulation."""
        return {name: self.grab(name) for name in PASSES}


def scene_for(dataset: str, size: Tuple[int, int], **kwargs: Any) -> BenchScene:
    """A :class:`BenchScene` of a bundled dataset with its paper preset."""
    return BenchScene(load_dataset(dataset), make_property(paper_preset(dataset)), size, **kwargs)


def bench_passes(dataset: str, size: int, ref_spp: int, cache: Path) -> Passes:
    """1-spp passes (seed 1) of the dataset's benchmark view plus "Reference" (``ref_spp``,
    seed 1000) and "Reference/2" (its first half), cached in ``cache`` as one .npz."""
    from pathtracedvolume.atomic import atomic_path
    from tqdm import tqdm

    target = cache / f"{dataset}_{size}_{ref_spp}.npz"
    if target.exists():
        cached = dict(np.load(target))
        if all(name in cached for name in PASSES):
            return cached  # else rendered before a pass existed: render it again
    scene = scene_for(dataset, (size, size))
    scene.render(seed=1)
    out: Passes = scene.passes()
    bar = tqdm(total=ref_spp, desc=f"reference {dataset} {size}²", unit="spp", leave=False)

    def on_frame(k: int) -> None:
        bar.update(1)
        if k == ref_spp // 2:
            out["Reference/2"] = scene.grab("Radiance")
    scene.render(seed=1000, frames=ref_spp, on_frame=on_frame)
    bar.close()
    out["Reference"] = scene.grab("Radiance")
    cache.mkdir(parents=True, exist_ok=True)
    with atomic_path(target, suffix=".tmp.npz") as tmp:
        np.savez(tmp, **out)
    return out


# --- denoisers on captured passes ---------------------------------------------------------
def model_props(path: Union[str, Path] = "") -> Dict[str, str]:
    """A model's ONNX metadata ("ptv.*"); "" = the shipped model."""
    import onnx
    model = onnx.load(str(path or SHIPPED_MODEL), load_external_data=False)
    return {p.key: p.value for p in model.metadata_props}


def model_levels(path: Union[str, Path] = "") -> int:
    """A GuideNet model's number of grid levels (its ptv.levels metadata); "" = the shipped one."""
    return len(model_props(path)["ptv.levels"].split(","))


def model_default_levels(path: Union[str, Path] = "") -> int:
    """How many levels the denoiser runs a model with by default on images above 256^2 pixels
    (its ptv.default_levels, else every level); "" = the shipped model."""
    props = model_props(path)
    return int(props.get("ptv.default_levels", len(props["ptv.levels"].split(","))))


class Ours:
    """vtkPTVDenoiser (the shipped model unless ``model``) with ``levels`` grid levels; with
    ``alpha`` (default) as the mapper runs it, the opacity too (DenoiseAlpha: the colour is 0
    where the denoised opacity is 0), without it the colour alone (OIDN's task)."""

    def __init__(self, levels: int = 0, model: str = "", threads: int = 0,
                 portable: bool = False, alpha: bool = True) -> None:
        from pathtracedvolume import vtkPTVDenoiser
        self.den = vtkPTVDenoiser()
        self.den.SetDenoiseAlpha(bool(alpha))
        self.den.SetModelFile(model)
        self.den.SetNumberOfLevels(int(levels))
        self.den.SetNumberOfThreads(int(threads))
        self.den.SetPortableKernels(bool(portable))
        self._keep: list = []

    def set_passes(self, passes: Passes) -> None:
        self._keep = [scene.numpy_to_image(passes[name], name) for name in PASSES]
        for name, image in zip(PASSES, self._keep):
            self.den.SetImage(name, image)

    def execute(self, copy: bool = True) -> np.ndarray:
        """Denoise; the result as a new array, or (``copy=False``, for timing) as a view of the
        output array the denoiser writes in place and overwrites on the next call. The C++
        denoiser (and the mapper) reuse that array; copying it into a fresh 12 MB array at
        1024² cost Python about 1 ms of page faults per call, which is not the denoiser's."""
        from vtkmodules.util.numpy_support import vtk_to_numpy
        if not self.den.Execute():
            raise RuntimeError("vtkPTVDenoiser failed")
        out = self.den.GetOutput()
        w, h, _ = out.GetDimensions()
        view = vtk_to_numpy(out.GetPointData().GetArray("Denoised")).reshape(h, w, 3)
        return np.array(view) if copy else view

    def stages(self) -> Dict[str, float]:
        """Milliseconds of the last Execute() per stage."""
        d = self.den
        return {"features": d.GetLastFeatureTime(), "guidenet": d.GetLastGuideNetTime(),
                "splat": d.GetLastSplatTime(), "slice": d.GetLastSliceTime(),
                "alpha": d.GetLastAlphaTime()}

    def __call__(self, passes: Passes) -> np.ndarray:
        self.set_passes(passes)
        return self.execute()

    def status(self) -> str:
        return str(self.den.GetStatus())

    def kernel_target(self) -> str:
        """The grid's CPU instruction set in the last Execute() ("AVX3", ..., "SCALAR")."""
        return str(self.den.GetKernelTarget())


def run_ours(passes: Passes, levels: int, model: str, repeats: int,
             threads: int = 0, portable: bool = False, alpha: bool = True) -> Dict[str, Any]:
    """Our denoiser on ``passes``: median ms (and per stage) of ``repeats`` after a warm-up."""
    ours = Ours(levels, model, threads, portable, alpha)
    ours.set_passes(passes)
    stages: Dict[str, list] = {k: [] for k in STAGES}

    def once() -> np.ndarray:
        out = ours.execute(copy=False)
        for k, v in ours.stages().items():
            stages[k].append(v)
        return out

    ms, out = timed(once, repeats)
    row: Dict[str, Any] = {k: statistics.median(v[1:]) for k, v in stages.items()}
    row.update(ms=ms, image=out.copy(), status=ours.status(), kernels=ours.kernel_target())
    return row


def oidn(passes: Passes, quality_name: str = "fast") -> np.ndarray:
    """pyoidn's RT filter: HDR colour + albedo + normal (the 1-spp auxiliary passes)."""
    import pyoidn
    color = np.ascontiguousarray(np.maximum(np.nan_to_num(passes["Radiance"]), 0), np.float32)
    albedo = np.ascontiguousarray(np.clip(passes["Albedo"], 0, 1), np.float32)
    normal = np.ascontiguousarray(np.clip(np.nan_to_num(passes["Normal"]), -1, 1), np.float32)
    return pyoidn.denoise(color, albedo, normal, hdr=True, quality=quality_name)


def run_oidn(passes: Passes, quality_name: str, repeats: int) -> Dict[str, Any]:
    """OIDN on ``passes``: median ms of ``repeats`` after a warm-up."""
    ms, out = timed(lambda: oidn(passes, quality_name), repeats)
    return {"ms": ms, "image": out}


def as_png(image: np.ndarray, path: Union[str, Path], width: Optional[int] = None) -> None:
    """Tone-mapped (H, W, 3) VTK-order image (bottom row first) to an 8-bit PNG, optionally
    resized to ``width`` pixels (nearest neighbour, keeps the aspect)."""
    import matplotlib.image as mpimg
    img = tonemap(image)[::-1]
    if width is not None and img.shape[1] != width:
        h, w = img.shape[:2]
        height = max(1, round(h * width / w))
        rows = np.minimum((np.arange(height) + 0.5) * h / height, h - 1).astype(int)
        cols = np.minimum((np.arange(width) + 0.5) * w / width, w - 1).astype(int)
        img = img[rows][:, cols]
    mpimg.imsave(str(path), (img * 255 + 0.5).astype(np.uint8))
