"""The shown image of a still view (pass Converged) on a real dataset at 512²: adding samples must
not make it worse, and from 8 samples on (where the raw mean starts to be blended in) it must
stay within 0.3 dB of the better of the raw mean and the denoised image.

TestPTVStillRender checks the same on an analytic scene; this case caught what it did not: with
the denoiser's error estimate box-filtered over 3x3 pixels, the head at 512² went from 39.4 dB
at 4 spp to 39.1 at 8 (0.9 dB under the denoised image alone), because that estimate was too
noisy at 8 frames and gave noisy raw pixels weight. PSNR after the tone map x^(1/2.2) against
a 256-spp reference of another seed, mean over three seeds (each seed's numbers are printed).
Needs the head dataset, a display (ctest runs under Xvfb) and the built package on PYTHONPATH.
"""
from __future__ import annotations

from typing import Dict, List

import numpy as np

from pathtracedvolume.metrics import tonemap
from pathtracedvolume.scene import Scene, place_camera

SIZE = 512
SEEDS = (1, 2, 3)
READS = (4, 8, 16)


def psnr(image: np.ndarray, reference: np.ndarray) -> float:
    mse = np.mean((tonemap(image).astype(np.float64) - tonemap(reference)) ** 2)
    return float(-10.0 * np.log10(mse))


def test_converged_image_improves_with_samples_on_the_head() -> None:
    scene = Scene.of_dataset("head", (SIZE, SIZE), denoise=False)
    place_camera(scene.renderer, azimuth=30.0, elevation=10.0)
    mapper = scene.mapper
    mapper.SetSamplesPerFrame(16)
    mapper.SetSeed(1000)
    mapper.GetExpertOptions().SetMaximumAccumulatedFrames(16)
    mapper.ResetAccumulation()
    scene.render(16)
    reference = scene.get_pass("Radiance")

    mapper.SetSamplesPerFrame(1)
    mapper.SetDenoise(True)
    mapper.GetExpertOptions().SetMaximumAccumulatedFrames(max(READS))
    seen: Dict[int, List[List[float]]] = {k: [] for k in READS}
    for seed in SEEDS:
        mapper.SetSeed(seed)
        mapper.ResetAccumulation()
        frames = 0
        for k in READS:
            scene.render(k - frames)
            frames = k
            row = [psnr(scene.get_pass(name), reference)
                   for name in ("Converged", "Denoised", "Radiance")]
            print(f"seed {seed}, {k} spp: converged / denoised / raw {row[0]:.2f} / "
                  f"{row[1]:.2f} / {row[2]:.2f} dB")
            seen[k].append(row)
    mean = {k: np.mean(rows, axis=0) for k, rows in seen.items()}
    for before, after in zip(READS, READS[1:]):
        assert mean[after][0] >= mean[before][0], (
            f"the shown image got worse from {before} to {after} spp: "
            f"{mean[before][0]:.2f} -> {mean[after][0]:.2f} dB")
    for k in READS[1:]:
        converged, denoised, raw = mean[k]
        assert converged >= max(denoised, raw) - 0.3, (
            f"{k} spp: shown {converged:.2f} dB, denoised {denoised:.2f}, raw {raw:.2f}")
