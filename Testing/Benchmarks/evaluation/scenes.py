"""Traced images of the evaluation report: volumes and scenes from JSON-able specs, the cache of
traced images, and :class:`Bench`, the context every section's ``measure`` shares.

Traced images that do not depend on the denoiser (references, spp sweeps, the orbit and stress
references) are cached under <cache>/bench/report, keyed by their parameters and by a
fingerprint of the tracer (a tiny render's output and the tracer's source files), so a changed
tracer re-renders.
"""
from __future__ import annotations

import argparse
import hashlib
import json
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple

import numpy as np
import ptvbench as pb
from pathtracedvolume.atomic import atomic_path
from tqdm import tqdm

from .common import DATASETS, SEED_INPUT, SEED_REFERENCE, counts, median, view_spec


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


def set_edge_samples(scene: pb.BenchScene, count: int) -> None:
    """The mapper's EdgeSamples in every frame (ComputeEdgeSamples) with ``count`` > 1, else
    none (the N-spp sweep and the references)."""
    scene.mapper.GetExpertOptions().SetEdgeSamples(max(int(count), 1))
    scene.mapper.GetExpertOptions().SetComputeEdgeSamples(count > 1)


class Scenes:
    """Builds volumes, presets and BenchScenes from JSON-able specs and reuses them::

        {"volume": "head" | "stent" | "concrete" | "head_shrink<F>" | "head_padded" |
                   "procedural",
         "preset": "paper" | "translucent" | "procedural", "size": [w, h],
         "light": key-light intensity, "specular": [coefficient, power] (optional),
         "azimuth", "elevation", "dolly"}
    """

    def __init__(self, threads: int, edge_samples: int = 1) -> None:
        self.threads = threads
        self.edge_samples = edge_samples  # the denoised frame's EdgeSamples (frame())
        self._volumes: Dict[str, Any] = {}
        self._scenes: Dict[str, pb.BenchScene] = {}

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
              grab: Mapping[int, Sequence[str]], desc: str = "",
              edge_samples: int = 1) -> Dict[str, np.ndarray]:
        """Accumulate ``frames`` 1-spp frames of ``seed`` (with ``edge_samples`` > 1 the
        mapper's EdgeSamples, as in a denoised frame); ``"<pass>@<k>"`` for every pass in
        ``grab[k]``, plus ``"trace_ms"`` (each frame's trace time)."""
        scene = self.scene(spec)
        options = scene.mapper.GetExpertOptions()
        saved = options.GetEdgeSamples(), options.GetComputeEdgeSamples()
        set_edge_samples(scene, edge_samples)
        out: Dict[str, np.ndarray] = {}
        bar = tqdm(total=frames, desc=desc, unit="spp", leave=False, disable=frames < 64)

        def on_frame(k: int) -> None:
            bar.update(1)
            for name in grab.get(k, ()):
                out[f"{name}@{k}"] = scene.grab(name)
        try:
            out["trace_ms"] = np.asarray(scene.render(seed, frames, on_frame))
        finally:
            bar.close()
            # The scene's mapper keeps its own settings (a later section that denoises through
            # the mapper, "samples", sees its defaults, not this trace's).
            options.SetEdgeSamples(saved[0])
            options.SetComputeEdgeSamples(saved[1])
        return out

    def frame(self, spec: Mapping[str, Any], seed: int) -> pb.Passes:
        """Every pass of one fresh 1-spp frame as the mapper traces it for the denoiser (with
        the Coverage, Footprint and ``edge_samples`` EdgeSamples)."""
        data = self.trace(spec, seed, 1, {1: pb.PASSES}, edge_samples=self.edge_samples)
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


# What decides a traced image: the kernels and the frame's inputs, tracing and accumulation. A
# tiny render alone can miss a change (the step-corrected opacity tables left a 24x20 image
# bit-identical while 256² images moved by 1e-5).
TRACER_SOURCES = ("Rendering/Kernels/*.h", "Rendering/Trace/ptvFrameInputs*",
                  "Rendering/Frame/ptvFrameLoop.*", "Rendering/Trace/ptvSceneToKernel.*",
                  "Rendering/Trace/ptvCpuTracer.*", "Rendering/Trace/ptvTracerRunner.*",
                  "Rendering/Accumulate/ptvPassBuffers.*", "Rendering/Accumulate/ptvReprojection*",
                  "Rendering/Trace/ptvEdgeSamples.*")


def edge_samples(args: argparse.Namespace) -> int:
    """--edge-samples, or the mapper's default EdgeSamples (what a denoised frame traces)."""
    if getattr(args, "edge_samples", None):
        return int(args.edge_samples)
    from pathtracedvolume import vtkPathTracedVolumeMapper
    return int(vtkPathTracedVolumeMapper().GetExpertOptions().GetEdgeSamples())


def tracer_fingerprint(scenes: Scenes) -> str:
    """Hash of a tiny 2-spp head render and of the tracer's sources (TRACER_SOURCES)."""
    data = scenes.trace({"volume": "head", "size": [24, 20]}, 7, 2,
                        {2: pb.PASSES})
    h = hashlib.sha1()
    for name in pb.PASSES:
        h.update(np.ascontiguousarray(data[f"{name}@2"]).tobytes())
    for pattern in TRACER_SOURCES:
        for path in sorted(pb.ROOT.glob(pattern)):
            h.update(path.name.encode())
            h.update(path.read_bytes())
    return h.hexdigest()[:16]


class Bench:
    """What the sections' ``measure`` steps share: the scenes, the traced-image cache, our
    denoiser (model's levels = 0, one level = 1) and the traced data of each Table-1 view."""

    def __init__(self, args: argparse.Namespace) -> None:
        self.args = args
        self.scenes = Scenes(args.threads, edge_samples(args))
        self.fingerprint = tracer_fingerprint(self.scenes)
        self.cache = Cache(None if args.no_cache else args.cache, self.fingerprint)
        # 0: the model's default level count; every level of the model (Table 1's second row)
        self.ours = {lv: pb.Ours(lv, args.model, args.threads)
                     for lv in (0, pb.model_levels(args.model))}
        self._views: Dict[Tuple[str, int], Dict[str, np.ndarray]] = {}

    def view_spec(self, dataset: str, view: int, size: Optional[int] = None) -> Dict[str, Any]:
        return view_spec(self.args, dataset, view, size)

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
        """1-spp passes ("<pass>@1"), the denoisers' frame of the same seed with EdgeSamples
        ("<pass>@frame", Scenes.frame), the sweep ("Radiance@N"), "ref" and "half"."""
        key = (dataset, view)
        if key not in self._views:
            spec = self.view_spec(dataset, view)
            sweep_counts = counts(self.args)
            grab: Dict[int, List[str]] = {n: ["Radiance"] for n in sweep_counts}
            grab[1] = list(pb.PASSES)
            sweep = self.cache.get(
                "sweep", {"spec": spec, "counts": sweep_counts, "seed": SEED_INPUT},
                lambda: self.scenes.trace(spec, SEED_INPUT, max(sweep_counts), grab,
                                          desc=f"sweep {dataset} view {view}"))
            k = self.scenes.edge_samples
            frame = self.cache.get(
                "frame", {"spec": spec, "seed": SEED_INPUT, "edge_samples": k},
                lambda: self.scenes.trace(spec, SEED_INPUT, 1, {1: list(pb.PASSES)},
                                          edge_samples=k))
            frame = {f"{n}@frame": frame[f"{n}@1"] for n in pb.PASSES}
            self._views[key] = {**sweep, **frame, **self.reference(spec, self.args.ref_spp)}
        return self._views[key]

    def denoise(self, passes: pb.Passes, levels: int = 0) -> np.ndarray:
        return self.ours[levels](passes)
