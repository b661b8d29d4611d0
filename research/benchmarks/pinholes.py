"""Dark 1-spp pinholes after denoising: do they survive as a pepper pattern?

On a benchmark frame (``ptvbench.bench_passes``: the dataset's paper preset and view, 1 spp, a
64-spp reference; default the head at 512²), the pinholes are the covered pixels (alpha > 0.99,
reference luminance > 0.05) whose 1-spp luminance is below a quarter of the reference's. For
OIDN RT fast and each given model (C++ ``vtkPTVDenoiser``) the script prints the median
denoised/reference luminance ratio at the pinholes and elsewhere, the share of covered pixels
below 0.8 of the reference, and the PSNR. A denoiser that lets pinholes through shows a ratio
at the pinholes well below the one elsewhere.

    PYTHONPATH=build/python .venv/bin/python research/benchmarks/pinholes.py \\
        Data/Models/guidenet.onnx "older model=old.onnx" --markdown out.md

A model is ``PATH`` or ``LABEL=PATH``; ``--markdown`` also writes the figures as a table.
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
    p.add_argument("models", nargs="*", help="GuideNet .onnx files, PATH or LABEL=PATH")
    p.add_argument("--dataset", default="head")
    p.add_argument("--size", type=int, default=512)
    p.add_argument("--cache", type=Path, default=HERE.parents[1] / ".cache" / "bench")
    p.add_argument("--markdown", type=Path, help="also write the figures as a markdown table")
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
    for spec in args.models:
        label, _, path = spec.rpartition("=")
        images[label or path] = cpp_denoise(Path(path), inputs, pb.PASSES, threads=2)["output"]
    rows = []
    for name, image in images.items():
        ratio = lum(image) / np.maximum(lum(ref), 1e-6)
        row = (name, np.median(ratio[pins]), np.median(ratio[covered & ~pins]),
               ((ratio < 0.8) & covered).sum() / covered.sum(), psnr(image, ref))
        rows.append(row)
        print(f"{name}: denoised/reference at pinholes {row[1]:.3f}, elsewhere {row[2]:.3f}; "
              f"below 0.8 of the reference {row[3]:.4f}; PSNR {row[4]:.2f} dB")
    if args.markdown:
        from evaluation.common import md_table
        lines = [f"{args.dataset} {args.size}², 1 spp, 64-spp reference: pinholes (covered pixels "
                 f"below 1/4 of the reference's luminance) {pins.sum() / covered.sum():.4f} of the "
                 "covered pixels", "",
                 *md_table(["denoiser", "denoised / reference at pinholes (median)",
                            "elsewhere (median)", "covered pixels below 0.8 of the reference",
                            "PSNR [dB]"],
                           [(r[0], f"{r[1]:.3f}", f"{r[2]:.3f}", f"{100 * r[3]:.2f} %",
                             f"{r[4]:.2f}") for r in rows]), ""]
        args.markdown.write_text("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
