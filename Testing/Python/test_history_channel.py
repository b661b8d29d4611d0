"""A GuideNet with the ``history`` input channel runs in the mapper on its HistoryLength pass.

The channel (Training/ptv_training/features.py) is 1 / max(1, HistoryLength): the share of the
newest frame in each pixel's mean. The mapper hands its HistoryLength pass to the denoiser, so
a model trained with the channel sees, while the camera moves, which pixels carry a reprojected
history and how long it is. These tests render the wavelet scene with a random model of that
kind, move the camera (TemporalReprojection on: the counts differ per pixel), and check that the
mapper ran the network (no fixed-guide fallback) and that its Denoised pass is what
vtkPTVDenoiser gives for the same passes and HistoryLength, bit for bit, and differs from what
the same passes give with a history of one frame everywhere. Needs a display (ctest runs under
Xvfb) and the built package on PYTHONPATH."""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import vtkmodules.util.numpy_support as vtk_numpy
import pathtracedvolume.vtkPTVRendering as ptv

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "Training"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

import torch  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkImageData  # noqa: E402
from ptv_training import features  # noqa: E402
from ptv_training.export_onnx import export  # noqa: E402
from ptv_training.guidenet import GuideNet  # noqa: E402
from ptv_wavelet_scene import get_pass, set_traced_passes, wavelet_scene  # noqa: E402

W, H = 64, 48


@pytest.fixture(scope="module")
def history_model(tmp_path_factory) -> Path:
    torch.manual_seed(11)
    channels = features.PAPER_10 + ["history"]
    net = GuideNet(len(channels), hidden=8, kernel=3, levels=3, stride=2, out_channels=8).eval()
    return export(net, tmp_path_factory.mktemp("history") / "history.onnx", channels,
                  levels=((4, 4), (8, 8), (16, 16)))


def vtk_denoise(mapper, history: np.ndarray) -> np.ndarray:
    """vtkPTVDenoiser on the mapper's traced passes and the given HistoryLength, with the
    mapper's model and its opacity step (DenoiseAlpha), as (H, W, 3)."""
    denoiser = ptv.vtkPTVDenoiser()
    denoiser.SetModelFile(mapper.GetDenoiserModelFile())
    denoiser.DenoiseAlphaOn()
    keep = set_traced_passes(mapper, denoiser)
    counts = vtk_numpy.numpy_to_vtk(np.ascontiguousarray(history, np.float32).reshape(-1, 1),
                                    deep=1)
    counts.SetName("HistoryLength")
    image = vtkImageData()
    image.SetDimensions(W, H, 1)
    image.GetPointData().SetScalars(counts)
    denoiser.SetImage("HistoryLength", image)
    assert denoiser.Execute()
    assert denoiser.GetNetworkActive(), denoiser.GetStatus()
    out = denoiser.GetOutput().GetPointData().GetArray("Denoised")
    return vtk_numpy.vtk_to_numpy(out).reshape(H, W, 3).copy()


def test_mapper_denoises_with_its_history_length(history_model) -> None:
    window, mapper, keep = wavelet_scene((W, H), denoise=True)
    mapper.SetDenoiserModelFile(str(history_model))
    mapper.GetExpertOptions().SetMaximumHistory(2)
    assert mapper.GetTemporalReprojection()
    window.Render()
    camera = keep[3].GetActiveCamera()
    for _ in range(2):  # two small turns: the kept pixels' counts grow past 1
        camera.Azimuth(1.0)
        window.Render()
    status = mapper.GetDenoiserStatus()
    assert status.startswith("GuideNet") and "history.onnx" in status, status
    counts = get_pass(mapper, "HistoryLength", (W, H)).reshape(H, W)
    assert (counts > 1.5).any() and (counts == 1.0).any(), "kept and fresh pixels both"
    denoised = get_pass(mapper, "Denoised", (W, H)).reshape(H, W, 3)
    assert np.array_equal(denoised, vtk_denoise(mapper, counts))
    assert not np.array_equal(denoised, vtk_denoise(mapper, np.ones_like(counts)))
