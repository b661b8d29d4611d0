"""Dark 1-spp pinholes after denoising: do they survive as a pepper pattern?

On a benchmark frame (``ptvbench.bench_passes``: the dataset's paper preset and view, 1 spp, a
64-spp reference; default the head at 512²), the pinholes are the covered pixels (alpha > 0.99,
reference luminance > 0.05) whose 1-spp luminance is below a quarter of the reference's. For
OIDN RT fast and each given model (C++ ``vtkPTVDenoiser``) the script prints the median
denoised/reference luminance ratio at the pinholes and elsewhere, the share of covered pixels
below 0.8 of the reference, and the PSNR. A denoiser that lets pinholes through shows a ratio
at the pinholes well below the one elsewhere.

    PYTHONPATH=build/python .venv/bin/python Testing/Benchmarks/pinholes.py \\
        Data/Models/guidenet.onnx
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.append(str(HERE.parents[1] / "Training"))

import ptvbench as pb  # noqa: E402

LUMA = np.array([0.2126, 0.7152, 0.0722])


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("models", nargs="*", type=Path, help="GuideNet .onnx files")
    p.add_argument("--dataset", default="head")
    p.add_argument("--size", type=int, default=512)
    p.add_argument("--cache", type=Path, default=HERE.parents[1] / ".cache" / "bench")
    args = p.parse_args()
    from pathtracedvolume.metrics import psnr
    from ptv_training.evaluate import cpp_denoise

    passes = pb.bench_passes(args.dataset, args.size, 64, args.cache)
    ref = passes["Reference"]
    lum = lambda x: x[..., :3] @ LUMA  # noqa: E731
    covered = (passes["Alpha"][..., 0] > 0.99) & (lum(ref) > 0.05)
    pins = covered & (lum(passes["Radiance"]) < 0.25 * lum(ref))
    print(f"{args.dataset} {args.size}²: pinholes {pins.sum() / covered.sum():.4f} of the "
          "covered pixels")
    inputs = {n: passes[n] for n in pb.PASSES}
    images = {"OIDN RT fast": pb.oidn(inputs, "fast")}
    for model in args.models:
        images[str(model)] = cpp_denoise(model, inputs, pb.PASSES, threads=2)["output"]
    for name, image in images.items():
        ratio = lum(image) / np.maximum(lum(ref), 1e-6)
        print(f"{name}: denoised/reference at pinholes {np.median(ratio[pins]):.3f}, elsewhere "
              f"{np.median(ratio[covered & ~pins]):.3f}; below 0.8 of the reference "
              f"{((ratio < 0.8) & covered).sum() / covered.sum():.4f}; "
              f"PSNR {psnr(image, ref):.2f} dB")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
