"""Quality of the shipped denoiser model (Data/Models/guidenet.onnx) through the mapper.

A head CT view that is not a training view (the training views are random; this one is the
"Head Two-Band (paper)" preset unjittered, azimuth 30, elevation 15, the mapper's default key
light) is traced at 128 x 128 with 1 spp and denoised by the mapper (DenoiseOn, one
accumulated frame, pass "Denoised"); against a 512-spp reference of an independent seed,
PSNR(denoised) must beat PSNR(noisy) by more than 3 dB (tone-mapped
clip(max(0, x)^(1/2.2), 0, 1), scikit-image, data_range 1). The mapper's denoised pass must
also be what vtkPTVDenoiser computes from the same passes.

Needs the built package on PYTHONPATH, a display (ctest: Xvfb) and the head dataset."""
from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(os.environ.get("PTV_SOURCE_DIR") or Path(__file__).resolve().parents[2])
if str(ROOT / "Training") not in sys.path:
    sys.path.append(str(ROOT / "Training"))  # appended: the compiled package stays first

import pathtracedvolume.vtkPTVRendering  # noqa: F401
MODEL = ROOT / "Data" / "Models" / "guidenet.onnx"
SIZE = 128
REFERENCE_SPP = 512
VIEW = {"dataset": "head", "preset": "Head Two-Band (paper)", "azimuth": 30.0,
        "elevation": 15.0, "distance_factor": 1.0}


def test_shipped_model_beats_noisy_by_3db(volume_path) -> None:
    volume_path("head")
    assert MODEL.is_file(), f"shipped model missing: {MODEL}"
    from ptv_training.data import psnr
    from ptv_training.evaluate import cpp_denoise
    from ptv_training.features import required_passes
    from ptv_training.scene import Scene

    scene = Scene("head", (SIZE, SIZE))
    mapper = scene.set_view(VIEW, seed=11, denoise=True, max_frames=1)
    mapper.SetDenoiserModelFile(str(MODEL))
    assert scene.render(1) == 1
    assert "GuideNet" in mapper.GetDenoiserStatus(), mapper.GetDenoiserStatus()
    noisy = scene.get_pass("Radiance")
    denoised = scene.get_pass("Denoised")
    passes = {name: scene.get_pass(name) for name in
              ("Radiance", "Albedo", "Normal", "Depth", "ScatterNormal", "ScatterDepth",
               "Position", "ScatterPosition", "Alpha", "Coverage", "Footprint")}

    scene.set_view(VIEW, seed=12345, denoise=False, max_frames=REFERENCE_SPP, coverage=False)
    assert scene.render(REFERENCE_SPP) == REFERENCE_SPP
    reference = scene.get_pass("Radiance")

    p_noisy = psnr(noisy, reference)
    p_denoised = psnr(denoised, reference)
    print(f"head view, {SIZE}^2: noisy 1 spp {p_noisy:.2f} dB, denoised {p_denoised:.2f} dB "
          f"(reference {REFERENCE_SPP} spp)")
    assert np.isfinite(denoised).all()
    assert p_denoised > p_noisy + 3.0

    import onnx
    channels = next(p.value for p in onnx.load(str(MODEL)).metadata_props
                    if p.key == "ptv.input_channels").split(",")
    # The mapper denoises the opacity too (DenoiseAlpha): the same colour where it is not 0,
    # and it keeps the pixels its Footprint pass marks empty black.
    standalone = cpp_denoise(MODEL, passes, required_passes(channels) + ["Footprint"],
                             alpha=True)
    assert standalone["network_active"]
    span = float(denoised.max() - denoised.min()) or 1.0
    assert np.abs(standalone["output"] - denoised).max() <= 1e-4 * span
