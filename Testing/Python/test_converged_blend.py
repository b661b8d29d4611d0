"""The shown image (pass Converged) is the learned blend of ``ptv_training.converge_blend``:
C++ (ptvConvergence) against numpy on the same accumulation, frame by frame.

The mapper's statistics are float sums; numpy gets the mean M from the Radiance pass after each
frame and rebuilds the frames' second moment from consecutive means (f_k = k M_k - (k-1) M_k-1),
so the features differ by float rounding: features enter the MLP through logs and its weights
are O(1-10), so the weights differ by ~1e-4 and the tone-mapped images by a few 1e-4 at most
(tolerance 2e-3, the C++ log and tone table being approximations to 1e-4 as well).
Needs the head dataset, a display (ctest runs under Xvfb) and the built package on PYTHONPATH.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from pathtracedvolume.metrics import tonemap
from pathtracedvolume.scene import Scene, place_camera

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "Training"))
from ptv_training import converge_blend as cb  # noqa: E402

SIZE = 96
FRAMES = 8


def test_converged_pass_is_the_trained_blend() -> None:
    weights = cb.read_header(ROOT / "Rendering" / "Accumulate" / "ptvConvergenceBlend.h")
    scene = Scene.of_dataset("head", (SIZE, SIZE), denoise=True)
    place_camera(scene.renderer, azimuth=30.0, elevation=10.0)
    mapper = scene.mapper
    mapper.ConvergeStillRendersOff()
    mapper.SetSeed(3)
    mapper.GetExpertOptions().SetMaximumAccumulatedFrames(FRAMES)
    mapper.ResetAccumulation()
    moments = cb.SecondMoment()
    checked = 0
    for k in range(1, FRAMES + 1):
        scene.render(1)
        mean = scene.get_pass("Radiance").astype(np.float64)
        second = moments.add(mean)
        if k not in (1, 2, 3, 8):
            continue
        denoised = scene.get_pass("Denoised")
        shown = scene.get_pass("Converged")
        expected = cb.shown(weights, mean, second, denoised, k)
        gap = np.abs(tonemap(shown).astype(np.float64) - tonemap(expected))
        print(f"{k} frames: max tone-mapped gap {gap.max():.2e}, mean {gap.mean():.2e}")
        assert gap.max() < 2e-3, f"{k} frames: C++ and numpy blends differ by {gap.max():.2e}"
        # The blend is not one of its ends: it moved away from D where the mean has samples.
        if k == 8:
            assert np.abs(shown - denoised).max() > 1e-3
        checked += 1
    assert checked == 4
