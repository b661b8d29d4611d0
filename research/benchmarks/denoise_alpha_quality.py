"""Our denoised colour with and without the opacity step (DenoiseAlpha), and OIDN fast.

With ``DenoiseAlpha`` the Alpha pass goes through the finest level of the same grid and the
colour is set to 0 where that opacity is 0 (no event near the pixel in that level's space):
the colour the coarser levels spread into empty space goes. The mapper always does this. This
compares the three on the Table-1 views of ``Training/ptv_training/compare.py`` (``paper_view``:
1-spp passes of seed 1, a reference of ``--reference-spp`` frames of seed 100003, rendered once
into ``--cache``): PSNR / SSIM after the tone map of ``docs/measuring.md``, the premultiplied
colour against the premultiplied reference (the evaluation report's measure). Quality only.

    PYTHONPATH=build/python xvfb-run -a .venv/bin/python research/benchmarks/denoise_alpha_quality.py --size 256
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "Training"))
NAMES = ["Radiance", "Alpha", "Albedo", "Depth", "Position", "Normal", "ScatterDepth",
         "ScatterPosition", "ScatterNormal", "Coverage"]


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--size", type=int, default=256, help="image size (default 256)")
    p.add_argument("--reference-spp", type=int, default=256, help="reference frames (256)")
    p.add_argument("--cache", type=Path, default=ROOT / ".cache" / "training" / "paper_views",
                   help="rendered Table-1 views (default .cache/training/paper_views)")
    a = p.parse_args()

    from skimage.metrics import structural_similarity
    from vtkmodules.util.numpy_support import vtk_to_numpy

    from pathtracedvolume import vtkPTVDenoiser
    from pathtracedvolume.metrics import psnr
    from pathtracedvolume.scene import numpy_to_image
    from ptv_training import compare

    def tm(x: np.ndarray) -> np.ndarray:
        return np.clip(np.maximum(x, 0) ** (1 / 2.2), 0, 1)

    print(f"{a.size}^2 Table-1 views, reference {a.reference_spp} spp: PSNR / SSIM")
    print("| view | ours, colour only | ours, DenoiseAlpha | OIDN fast |")
    print("|---|---|---|---|")
    sums = np.zeros(3)
    count = 0
    for ds in compare.PAPER_DATASETS:
        for cam in range(len(compare.PAPER_CAMERAS)):
            view = compare.paper_view(ds, a.size, cam, a.reference_spp, a.cache)
            passes, ref = view["inputs"], tm(view["reference"])
            den = vtkPTVDenoiser()
            keep = [numpy_to_image(passes[n], n) for n in NAMES]
            for name, image in zip(NAMES, keep):
                den.SetImage(name, image)
            results = []
            for on in (False, True):
                den.SetDenoiseAlpha(on)
                if not den.Execute():
                    raise RuntimeError(den.GetStatus())
                array = den.GetOutput().GetPointData().GetArray("Denoised")
                results.append(vtk_to_numpy(array).reshape(a.size, a.size, 3).copy())
            results.append(compare.oidn_fast(passes))
            cells = []
            for k, image in enumerate(results):
                value = psnr(tm(image), ref)
                sums[k] += value
                ssim = structural_similarity(tm(image), ref, channel_axis=2, data_range=1)
                cells.append(f"{value:.2f} / {ssim:.4f}")
            count += 1
            print(f"| {ds} {cam} | " + " | ".join(cells) + " |")
    print("| mean PSNR | " + " | ".join(f"{s / count:.2f}" for s in sums) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
