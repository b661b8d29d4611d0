"""Study: joint-bilateral instead of bilinear upsampling of GuideNet's half-resolution guides.

The shipped model runs at 1/2 resolution and its guides and blend weights are upsampled
bilinearly (``Training/ptv_training/guidenet.py``). Would guides made sharper at silhouettes
help thin structures (the stent)? On the benchmark frames (``ptvbench.bench_passes``, 1 spp,
64-spp reference) the network's outputs are computed with ONNX Runtime on the 2x2-averaged
features, upsampled (a) bilinearly, as the C++ does, and (b) with joint-bilateral weights --
each of the four bilinear weights times exp(-|f(p) - f(q)|^2 / (2 sigma^2)) + 1e-4, f the
pixel's 1-spp hit mask (and depth feature) and f(q) its 2x2 block's mean -- and given to
``vtkPTVDenoiser`` as ``Guides`` / ``BlendWeights``. (a) must reproduce the denoiser's own output.
Quality only, no timing. Results: Training/README.md ("The dark pinholes").

    PYTHONPATH=build/python xvfb-run -a .venv/bin/python research/benchmarks/guide_upsampling.py
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Optional, Tuple

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.append(str(HERE.parents[1] / "Training"))

import ptvbench as pb  # noqa: E402


def _taps(n_out: int, n_in: int, s: int) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Bilinear taps (align_corners=False, edge clamped): first index, second index, weight."""
    x = np.clip((np.arange(n_out) + 0.5) / s - 0.5, 0, None)
    i0 = np.minimum(np.floor(x).astype(int), n_in - 1)
    i1 = np.minimum(i0 + 1, n_in - 1)
    f = np.where(i0 == n_in - 1, 0.0, x - np.floor(x))
    return i0, i1, f


def block_mean(x: np.ndarray, s: int) -> np.ndarray:
    """(C, H, W) -> s x s block means, the image edge replicated (GuideNet's pooling)."""
    c, h, w = x.shape
    x = np.pad(x, ((0, 0), (0, (-h) % s), (0, (-w) % s)), mode="edge")
    return x.reshape(c, x.shape[1] // s, s, x.shape[2] // s, s).mean((2, 4))


def upsample(low: np.ndarray, h: int, w: int, s: int, full: Optional[np.ndarray] = None,
             sigma: Optional[float] = None) -> np.ndarray:
    """Bilinear (``full`` None) or joint-bilateral upsampling of (C, h, w) to (C, H, W)."""
    y0, y1, fy = _taps(h, low.shape[1], s)
    x0, x1, fx = _taps(w, low.shape[2], s)
    coarse = None if full is None else block_mean(full, s)
    acc = np.zeros((low.shape[0], h, w))
    total = np.zeros((h, w))
    for yi, wy in ((y0, 1 - fy), (y1, fy)):
        for xi, wx in ((x0, 1 - fx), (x1, fx)):
            weight = wy[:, None] * wx[None, :]
            if coarse is not None:
                d = ((full - coarse[:, yi][:, :, xi]) ** 2).sum(0)
                weight = weight * (np.exp(-d / (2 * sigma ** 2)) + 1e-4)
            acc += weight * low[:, yi][:, :, xi]
            total += weight
    return acc / total


def denoise_given(radiance: np.ndarray, guides: np.ndarray, weights: Optional[np.ndarray]):
    """vtkPTVDenoiser with given guides (C, H, W) in [0, 255] and blend weights."""
    from pathtracedvolume import vtkPTVDenoiser
    from pathtracedvolume.scene import numpy_to_image
    from vtkmodules.util.numpy_support import vtk_to_numpy

    den = vtkPTVDenoiser()
    den.SetNumberOfThreads(2)
    keep = [numpy_to_image(radiance, "Radiance"),
            numpy_to_image(np.ascontiguousarray(np.moveaxis(guides, 0, -1)), "Guides")]
    if weights is not None:
        keep.append(numpy_to_image(np.ascontiguousarray(np.moveaxis(weights, 0, -1)),
                                   "BlendWeights"))
    for image in keep:
        den.SetImage(image.GetPointData().GetScalars().GetName(), image)
    if not den.Execute():
        raise RuntimeError(den.GetStatus())
    out = den.GetOutput()
    w, h, _ = out.GetDimensions()
    return vtk_to_numpy(out.GetPointData().GetArray("Denoised")).reshape(h, w, 3).copy()


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--model", type=Path, default=HERE.parents[1] / "Data/Models/guidenet.onnx")
    p.add_argument("--datasets", nargs="+", default=["stent", "head", "concrete"])
    p.add_argument("--sizes", nargs="+", type=int, default=[256, 512])
    p.add_argument("--sigmas", nargs="+", type=float, default=[0.15, 0.3])
    p.add_argument("--cache", type=Path, default=HERE.parents[1] / ".cache" / "bench")
    args = p.parse_args()
    import onnxruntime as ort
    from pathtracedvolume.metrics import psnr
    from ptv_training.evaluate import cpp_denoise
    from ptv_training.features import build_features

    session = ort.InferenceSession(str(args.model), providers=["CPUExecutionProvider"])
    meta = session.get_modelmeta().custom_metadata_map
    channels = meta["ptv.input_channels"].split(",")
    stride = int(meta.get("ptv.guide_stride", "1"))
    model_levels = meta["ptv.levels"].count(":")
    for size in args.sizes:
        for dataset in args.datasets:
            passes = pb.bench_passes(dataset, size, 64, args.cache)
            ref = passes["Reference"]
            inputs = {n: passes[n] for n in pb.PASSES}
            result = {"OIDN fast": psnr(pb.oidn(inputs, "fast"), ref),
                      "C++": psnr(cpp_denoise(args.model, inputs, pb.PASSES, 2)["output"], ref)}
            levels = model_levels if size * size <= 256 * 256 else pb.model_default_levels(
                args.model)
            features = build_features(passes, channels)
            _, h, w = features.shape
            low = session.run(None, {session.get_inputs()[0].name:
                                     block_mean(features, stride)[None].astype(np.float32)})[0][0]

            def run(up: np.ndarray) -> float:
                weights = up[model_levels:model_levels + levels - 1] if levels > 1 else None
                return psnr(denoise_given(passes["Radiance"], 255.0 * up[:levels], weights), ref)

            result["bilinear, given"] = run(upsample(low, h, w, stride))
            hit = (passes["Alpha"][..., 0] > 0).astype(np.float64)
            depth = features[channels.index("depth")]
            for name, full in (("hit", hit[None]), ("hit+depth", np.stack([hit, depth]))):
                for sigma in args.sigmas:
                    result[f"joint-bilateral {name}, sigma {sigma}"] = run(
                        upsample(low, h, w, stride, full, sigma))
            print(f"{dataset} {size}²: " + "; ".join(f"{k} {v:.2f}" for k, v in result.items()),
                  flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
