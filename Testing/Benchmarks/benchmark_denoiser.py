#!/usr/bin/env python3
"""Benchmark: our denoiser (1 and 3 grid levels) against Intel Open Image Denoise on the same 1-spp inputs.

For each dataset and size: the 1-spp passes and a high-spp reference of one view are rendered
with vtkPathTracedVolumeMapper (Denoise off) and cached in <cache>/bench; then, in the same run,
vtkPTVDenoiser (the shipped model, 1 and 3 levels) and pyoidn's RT filter (quality fast and
balanced, HDR colour + albedo + normal) denoise the same radiance. Times are medians of
--repeats runs after a warm-up; ours is split into features, GuideNet, splat (incl.
demodulation) and slice. PSNR/SSIM (scikit-image, data_range 1) against the reference, all images
tone-mapped clip(max(0,x)^(1/2.2),0,1).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.append(str(ROOT / "Python"))  # after PYTHONPATH: a built package wins

from tqdm import tqdm  # noqa: E402

PASSES = ["Radiance", "Alpha", "Albedo", "Depth", "Position", "Normal",
          "ScatterDepth", "ScatterPosition", "ScatterNormal"]


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--datasets", nargs="+", default=["head"])
    parser.add_argument("--sizes", nargs="+", type=int, default=[512, 1024])
    parser.add_argument("--ref-spp", type=int, default=512,
                        help="reference samples per pixel (default 512)")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--model", default="", help="GuideNet .onnx (default: shipped)")
    parser.add_argument("--json", type=Path, default=None)
    parser.add_argument("--cache", type=Path,
                        default=Path(os.environ.get("PTV_CACHE_DIR", ROOT / ".cache")) / "bench")
    return parser.parse_args()


def tonemap(x: np.ndarray) -> np.ndarray:
    return np.clip(np.power(np.maximum(x, 0.0), 1.0 / 2.2), 0.0, 1.0)


def render(dataset: str, size: int, ref_spp: int, cache: Path) -> dict[str, np.ndarray]:
    """1-spp passes plus "Reference" (ref_spp) and "Reference/2" (ref_spp/2), cached."""
    target = cache / f"{dataset}_{size}_{ref_spp}.npz"
    if target.exists():
        return dict(np.load(target))
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkIOXML import vtkXMLImageDataReader
    from vtkmodules.vtkRenderingCore import (vtkRenderer, vtkRenderWindow, vtkVolume,
                                             vtkVolumeProperty)
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
    from pathtracedvolume import vtkPathTracedVolumeMapper
    from pathtracedvolume.datasets import dataset_path
    from pathtracedvolume.presets import apply_preset, find_preset

    reader = vtkXMLImageDataReader()
    reader.SetFileName(str(dataset_path(dataset)))
    prop = vtkVolumeProperty()
    apply_preset(find_preset(f"{dataset.capitalize()} Two-Band (paper)"), prop)
    prop.ShadeOn()
    prop.SetInterpolationTypeToLinear()
    mapper = vtkPathTracedVolumeMapper()
    mapper.SetInputConnection(reader.GetOutputPort())
    mapper.DenoiseOff()
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    renderer = vtkRenderer()
    renderer.AddVolume(volume)
    renderer.SetBackground(0.32, 0.34, 0.43)
    camera = renderer.GetActiveCamera()
    camera.SetPosition(0, -1, 0)
    camera.SetFocalPoint(0, 0, 0)
    camera.SetViewUp(0, 0, 1)
    camera.Azimuth(30)
    camera.Elevation(10)
    renderer.ResetCamera()
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(size, size)
    window.AddRenderer(renderer)

    def grab(name: str) -> np.ndarray:
        image = vtkImageData()
        mapper.GetPass(name, image)
        return vtk_to_numpy(image.GetPointData().GetArray(name)).reshape(size, size, -1).copy()

    out: dict[str, np.ndarray] = {}
    mapper.SetSeed(1)
    mapper.SetMaximumAccumulatedFrames(1)
    window.Render()
    for name in PASSES:
        out[name] = grab(name)
    mapper.SetSeed(1000)
    mapper.SetMaximumAccumulatedFrames(ref_spp)
    for i in tqdm(range(ref_spp), desc=f"reference {dataset} {size}²", unit="spp", leave=False):
        window.Render()
        if i + 1 == ref_spp // 2:
            out["Reference/2"] = grab("Radiance")
    out["Reference"] = grab("Radiance")
    cache.mkdir(parents=True, exist_ok=True)
    tmp = target.with_suffix(".tmp.npz")
    np.savez(tmp, **out)
    tmp.replace(target)
    return out


def timed(fn, repeats: int):
    fn()
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = fn()
        times.append(1000.0 * (time.perf_counter() - start))
    return statistics.median(times), result


def run_ours(passes: dict[str, np.ndarray], levels: int, model: str, repeats: int) -> dict:
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from pathtracedvolume import vtkPTVDenoiser

    den = vtkPTVDenoiser()
    den.SetModelFile(model)
    den.SetNumberOfLevels(levels)
    h, w = passes["Radiance"].shape[:2]
    keep = []
    for name in PASSES:
        a = np.ascontiguousarray(passes[name], dtype=np.float32)
        arr = numpy_to_vtk(a.reshape(h * w, -1), deep=1)
        arr.SetName(name)
        image = vtkImageData()
        image.SetDimensions(w, h, 1)
        image.GetPointData().SetScalars(arr)
        keep.append(image)
        den.SetImage(name, image)
    stages: dict[str, list[float]] = {k: [] for k in ("features", "guidenet", "splat", "slice")}

    def once():
        if not den.Execute():
            raise RuntimeError("vtkPTVDenoiser failed")
        stages["features"].append(den.GetLastFeatureTime())
        stages["guidenet"].append(den.GetLastGuideNetTime())
        stages["splat"].append(den.GetLastSplatTime())
        stages["slice"].append(den.GetLastSliceTime())
        return vtk_to_numpy(den.GetOutput().GetPointData().GetArray("Denoised")).reshape(h, w, 3)

    ms, out = timed(once, repeats)
    row = {k: statistics.median(v[1:]) for k, v in stages.items()}
    row.update(ms=ms, image=out.copy(), status=den.GetStatus())
    return row


def run_oidn(passes: dict[str, np.ndarray], quality: str, repeats: int) -> dict:
    import pyoidn
    color = np.ascontiguousarray(np.maximum(np.nan_to_num(passes["Radiance"]), 0), np.float32)
    albedo = np.ascontiguousarray(np.clip(passes["Albedo"], 0, 1), np.float32)
    normal = np.ascontiguousarray(passes["Normal"], np.float32)
    ms, out = timed(lambda: pyoidn.denoise(color, albedo, normal, hdr=True, quality=quality),
                    repeats)
    return {"ms": ms, "image": out}


def main() -> int:
    args = parse_args()
    from skimage.metrics import peak_signal_noise_ratio, structural_similarity

    rows = []
    for dataset in args.datasets:
        for size in args.sizes:
            p = render(dataset, size, args.ref_spp, args.cache)
            ref = tonemap(p["Reference"])

            def quality(img: np.ndarray) -> tuple[float, float]:
                t = tonemap(img)
                return (peak_signal_noise_ratio(ref, t, data_range=1.0),
                        structural_similarity(ref, t, data_range=1.0, channel_axis=2))

            check = peak_signal_noise_ratio(ref, tonemap(p["Reference/2"]), data_range=1.0)
            methods = {"noisy 1 spp": {"ms": 0.0, "image": p["Radiance"]}}
            for levels in (1, 3):
                methods[f"ours {levels} level{'s' if levels > 1 else ''}"] = run_ours(
                    p, levels, args.model, args.repeats)
            for q in ("fast", "balanced"):
                methods[f"OIDN RT {q}"] = run_oidn(p, q, args.repeats)
            for name, m in methods.items():
                psnr, ssim = quality(m["image"])
                rows.append({"dataset": dataset, "size": size, "method": name,
                             "ms": m["ms"], "psnr": psnr, "ssim": ssim,
                             **{k: m[k] for k in ("features", "guidenet", "splat", "slice",
                                                  "status") if k in m},
                             "reference_spp": args.ref_spp,
                             "reference_half_vs_full_psnr": check})
    print(f"\n{os.cpu_count()} cores; median of {args.repeats} after a warm-up; reference "
          f"{args.ref_spp} spp; model: {rows[1].get('status', '?')}")
    print("| dataset | size | method | ms | features | GuideNet | splat | slice | PSNR | SSIM |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        st = [f"{r[k]:.1f}" if k in r else "" for k in ("features", "guidenet", "splat", "slice")]
        print(f"| {r['dataset']} | {r['size']}² | {r['method']} | {r['ms']:.1f} | "
              f"{' | '.join(st)} | {r['psnr']:.2f} | {r['ssim']:.4f} |")
    for dataset in args.datasets:
        for size in args.sizes:
            sel = {r["method"]: r for r in rows if r["dataset"] == dataset and r["size"] == size}
            ours, oidn = sel["ours 3 levels"], sel["OIDN RT fast"]
            print(f"{dataset} {size}²: OIDN fast / ours (3 levels) time = "
                  f"{oidn['ms'] / ours['ms']:.1f}x, PSNR gap ours - OIDN fast = "
                  f"{ours['psnr'] - oidn['psnr']:+.2f} dB; reference check "
                  f"(ref/2 vs ref) {ours['reference_half_vs_full_psnr']:.1f} dB")
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        tmp = args.json.with_suffix(".tmp")
        tmp.write_text(json.dumps(rows, indent=2))
        tmp.replace(args.json)
    return 0


if __name__ == "__main__":
    sys.exit(main())
