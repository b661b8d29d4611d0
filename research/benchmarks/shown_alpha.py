"""What the window shows against the image it should show, one traced frame per view.

The mapper draws its shown pass (``Converged``; after one frame the denoised image) as
premultiplied colour over the background, with an opacity per pixel (``ptvShownImage.cxx``,
``ptvDisplay.cxx``: fragments with opacity <= 0 are discarded). Until 2026-12-03 that opacity was
the accumulated ``Alpha`` pass, which after one frame is 0 or 1 per pixel (the 1-spp coverage):
the window showed the background wherever the frame's ray met no event, however much colour the
denoiser had put there, and no background through translucent pixels whose ray did. Now the
denoised image is drawn with ``DenoisedAlpha`` (the Alpha pass through the denoiser's grid).

This script renders the Table-1 views (the cameras and seeds of
``Training/ptv_training/compare.py``; ``--background`` is also the environment light, as in
every scene of the project): a 1-spp frame, denoised and drawn, and a reference of
``--reference-spp`` frames of an independent seed, composited over the background with its own
accumulated alpha. It reads the window back (8 bits) and reports per view, PSNR after the tone
map of ``docs/measuring.md`` against the composited reference (clipped to [0, 1] as a window
holds it):

* ``window``: what the window shows now;
* ``drawn with Alpha``: the same shown pass drawn as before (opacity = the frame's Alpha pass,
  fragments with alpha 0 discarded), computed in numpy from the passes and rounded to 8 bits;
* ``pass``: the premultiplied shown pass against the premultiplied reference, the figure the
  evaluation report gives (on a black background it is the window's image before rounding);
* ``alpha 0``: the share of the covered pixels (reference above 0.02 after the tone map) whose
  frame had no event (Alpha 0).

    PYTHONPATH=build/python xvfb-run -a .venv/bin/python research/benchmarks/shown_alpha.py \
        --size 256 [--background 0.32 0.34 0.43]
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "Training"))


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--size", type=int, default=256, help="image size (default 256)")
    p.add_argument("--datasets", nargs="*", default=["head", "stent", "concrete"])
    p.add_argument("--reference-spp", type=int, default=256, help="reference frames (256)")
    p.add_argument("--background", type=float, nargs=3, default=[0.0, 0.0, 0.0],
                   help="background and environment colour (default black)")
    a = p.parse_args()

    from vtkmodules.util.numpy_support import vtk_to_numpy

    from pathtracedvolume.metrics import psnr
    from pathtracedvolume.scene import paper_preset
    from ptv_training import compare
    from ptv_training.scene import Scene
    from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter

    def tm(x: np.ndarray) -> np.ndarray:
        return np.clip(np.maximum(x, 0) ** (1 / 2.2), 0, 1)

    bg = np.asarray(a.background, np.float32)
    print(f"{a.size}^2, one traced frame, shown pass Converged, background {tuple(a.background)}")
    print("| dataset | view | window | drawn with Alpha | pass | alpha 0 |")
    print("|---|---|---|---|---|---|")
    for ds in a.datasets:
        for cam in (0, 1):
            azimuth, elevation = compare.PAPER_CAMERAS[cam]
            spec = {"dataset": ds, "transfer_function": paper_preset(ds), "azimuth": azimuth,
                    "elevation": elevation, "background": tuple(a.background)}
            scene = Scene(ds, (a.size, a.size))
            scene.set_view(spec, seed=compare.PAPER_SEEDS[1], max_frames=a.reference_spp)
            if scene.render(a.reference_spp) != a.reference_spp:
                raise RuntimeError("the reference did not accumulate")
            ref = scene.get_pass("Radiance")
            ref_alpha = scene.get_pass("Alpha")
            target = tm(np.clip(ref + (1 - ref_alpha) * bg, 0, 1))
            scene.set_view(spec, seed=compare.PAPER_SEEDS[0], denoise=True, max_frames=1)
            scene.render(1)
            shown = scene.get_pass("Converged")
            alpha = scene.get_pass("Alpha")
            grab = vtkWindowToImageFilter()
            grab.SetInput(scene.window)
            grab.ShouldRerenderOff()
            grab.ReadFrontBufferOff()
            grab.Update()
            win = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars()).reshape(
                a.size, a.size, -1)[..., :3] / 255.0
            before = np.where(alpha > 0, np.clip(shown + (1 - alpha) * bg, 0, 1), bg)
            before = np.round(before * 255) / 255
            covered = tm(ref).max(-1) > 0.02
            print(f"| {ds} | {cam} | {psnr(tm(win), target):.2f} | "
                  f"{psnr(tm(before), target):.2f} | {psnr(tm(shown), tm(ref)):.2f} | "
                  f"{np.mean(alpha[..., 0][covered] == 0):.1%} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
