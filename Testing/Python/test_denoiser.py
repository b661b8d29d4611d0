"""vtkPTVDenoiser end to end: C++ (ptvFeatures -> ONNX Runtime GuideNet -> bilateral grid) against
the Python definition (features.py -> torch GuideNet -> bilateral_grid.py) on real rendered
passes, within 1e-4 of the image range; and its contract on bad input (clear errors, documented
fallbacks, finite output). Needs a display (ctest runs under Xvfb) and the built package."""
from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(os.environ.get("PTV_SOURCE_DIR", Path(__file__).resolve().parents[2]))
sys.path.append(str(ROOT / "Training"))

import torch
import pathtracedvolume.vtkPTVRendering as rendering

from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction  # noqa: E402
from vtkmodules.vtkImagingCore import vtkRTAnalyticSource  # noqa: E402
from vtkmodules.vtkRenderingCore import (vtkColorTransferFunction, vtkRenderer,  # noqa: E402
                                         vtkRenderWindow, vtkVolume, vtkVolumeProperty)
import vtkmodules.vtkRenderingOpenGL2  # noqa: E402,F401

from ptv_training import bilateral_grid, features  # noqa: E402
from ptv_training.export_onnx import export  # noqa: E402
from ptv_training.guidenet import GuideNet  # noqa: E402

W, H = 61, 43  # odd, not multiples of any grid step
LEVELS = ((4, 4), (8, 8), (16, 16))
TRACED = ["Radiance", "Alpha", "Albedo", "Depth", "Position", "Normal",
          "ScatterDepth", "ScatterPosition", "ScatterNormal", "Coverage"]


def render_passes(frames: int = 1) -> dict[str, np.ndarray]:
    """The traced passes of a small wavelet scene, as (H, W, C) float32 arrays."""
    source = vtkRTAnalyticSource()
    source.SetWholeExtent(-12, 12, -12, 12, -12, 12)
    color = vtkColorTransferFunction()
    color.AddRGBPoint(37, 0.9, 0.5, 0.2)
    color.AddRGBPoint(277, 1.0, 1.0, 0.9)
    opacity = vtkPiecewiseFunction()
    opacity.AddPoint(37, 0.0)
    opacity.AddPoint(150, 0.0)
    opacity.AddPoint(277, 0.9)
    prop = vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.ShadeOn()
    prop.SetInterpolationTypeToLinear()
    mapper = rendering.vtkPathTracedVolumeMapper()
    mapper.ConvergeStillRendersOff()  # frame by frame
    mapper.SetInputConnection(source.GetOutputPort())
    mapper.DenoiseOff()
    # the camera rays' opacity, as a model with "coverage" needs
    mapper.GetExpertOptions().CoverageMarchOn()
    mapper.GetExpertOptions().ScatterPassesOn()  # every traced pass (TRACED)
    mapper.GetExpertOptions().SetMaximumAccumulatedFrames(frames)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    renderer = vtkRenderer()
    renderer.AddVolume(volume)
    renderer.SetBackground(0.4, 0.4, 0.45)
    renderer.GetActiveCamera().Azimuth(25)
    renderer.GetActiveCamera().Elevation(15)
    renderer.ResetCamera()
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(W, H)
    window.AddRenderer(renderer)
    for _ in range(frames):
        window.Render()
    out = {}
    for name in TRACED:
        image = vtkImageData()
        assert mapper.GetPass(name, image)
        a = vtk_to_numpy(image.GetPointData().GetArray(name)).astype(np.float32)
        out[name] = a.reshape(H, W, -1).copy()
    return out


def to_image(name: str, a: np.ndarray) -> vtkImageData:
    h, w = a.shape[:2]
    comps = a.shape[2] if a.ndim == 3 else 1
    arr = numpy_to_vtk(np.ascontiguousarray(a, dtype=np.float32).reshape(h * w, comps), deep=1)
    arr.SetName(name)
    image = vtkImageData()
    image.SetDimensions(w, h, 1)
    image.GetPointData().SetScalars(arr)
    return image


def cxx_denoise(passes: dict[str, np.ndarray], model: str | None, **settings) -> tuple:
    den = rendering.vtkPTVDenoiser()
    messages: list[str] = []
    den.AddObserver("ErrorEvent", lambda o, e: messages.append("error"))
    den.AddObserver("WarningEvent", lambda o, e: messages.append("warning"))
    if model is not None:
        den.SetModelFile(model)
    for key, value in settings.items():
        getattr(den, f"Set{key}")(value)
    for name, a in passes.items():
        den.SetImage(name, to_image(name, a))
    ok = den.Execute()
    out = None
    if ok:
        array = den.GetOutput().GetPointData().GetArray("Denoised")
        out = vtk_to_numpy(array).reshape(H_of(passes), -1, 3)
    return ok, out, den, messages


def H_of(passes: dict[str, np.ndarray]) -> int:
    return next(iter(passes.values())).shape[0]


@pytest.fixture(scope="module")
def passes() -> dict[str, np.ndarray]:
    return render_passes()


def make_model(folder: Path, stride: int = 1, kernel: int = 5, hidden: int = 8,
               out_channels: int | None = None, seed: int = 3
               ) -> tuple[Path, GuideNet, list[str]]:
    """A seeded random GuideNet on the volume features, exported for the C++ side."""
    torch.manual_seed(seed)
    channels = features.VOLUME_FEATURES
    net = GuideNet(len(channels), hidden=hidden, kernel=kernel, levels=3, stride=stride,
                   out_channels=out_channels)
    path = folder / f"guidenet_s{stride}_k{kernel}_o{net.out_channels}.onnx"
    export(net, path, channels, levels=LEVELS)
    return path, net.eval(), channels


@pytest.fixture(scope="module")
def random_model(tmp_path_factory) -> tuple[Path, GuideNet, list[str]]:
    return make_model(tmp_path_factory.mktemp("model"))


# Today's shape (stride 1, 5 outputs) and the CPU-shaped variants: the network at 1/2 and 1/4
# resolution with 8 (padded) outputs, and an odd-sized frame for every stride.
VARIANTS = [(1, 5, None), (2, 3, 8), (4, 3, 8), (2, 5, 8)]


@pytest.fixture(scope="module")
def variant_models(tmp_path_factory) -> dict:
    folder = tmp_path_factory.mktemp("variants")
    return {v: make_model(folder, stride=v[0], kernel=v[1], out_channels=v[2]) for v in VARIANTS}


def torch_pipeline(passes: dict[str, np.ndarray], net: GuideNet, channels) -> np.ndarray:
    """The reference: features -> GuideNet (pool, net, upsample) -> the torch bilateral grid,
    with the levels an image of this size uses (bilateral_grid.fitting_levels)."""
    from ptv_training.train import run_model
    feats = torch.from_numpy(features.build_features(passes, channels))[None]
    height, width = passes["Radiance"].shape[:2]
    with torch.no_grad():
        rad = torch.from_numpy(passes["Radiance"]).permute(2, 0, 1)[None]
        alb = torch.from_numpy(passes["Albedo"]).permute(2, 0, 1)[None]
        ref, _, _ = run_model(net, feats, rad, alb, LEVELS, 8.0, True,
                              bilateral_grid.fitting_levels(LEVELS, height, width))
    return ref[0].permute(1, 2, 0).numpy()


@pytest.mark.parametrize("portable", [False, True], ids=["dispatched", "portable"])
@pytest.mark.parametrize("variant", VARIANTS, ids=lambda v: f"s{v[0]}k{v[1]}o{v[2] or 5}")
def test_cxx_matches_python_pipeline(passes, variant_models, variant, portable) -> None:
    """C++ (features, ONNX Runtime, upsampling, grid) against torch, both kernel builds.

    Tolerance 1e-4 of the output range: the grid's sums run in another order in C++ (a push
    splat) than in torch, and float sums of up to (2 ss)^2 * 2 = 2048 terms differ by a few
    1e-6 relative (the bound n * 2^-24 = 1.2e-4 is never approached); the network's outputs
    agree to ~1e-6 (ONNX Runtime vs torch), which moves a guide by < 1e-3 of a range bin.
    """
    path, net, channels = variant_models[variant]
    ok, out, den, messages = cxx_denoise(passes, str(path), PortableKernels=portable)
    assert ok and den.GetNetworkActive(), den.GetStatus()
    assert messages == []
    if variant[0] > 1:
        assert f"guides at 1/{variant[0]} resolution" in den.GetStatus()
    assert (den.GetKernelTarget() in ("SCALAR", "EMU128")) == portable, den.GetKernelTarget()
    ref = torch_pipeline(passes, net, channels)
    span = float(ref.max() - ref.min())
    err = float(np.abs(out - ref).max())
    assert span > 0
    print(f"parity {variant} portable={portable} ({den.GetKernelTarget()}): "
          f"max err {err:.3g}, range {span:.3g}")
    assert err <= 1e-4 * span, f"max |C++ - Python| = {err:.3g}, range {span:.3g}"


def parity(passes: dict[str, np.ndarray], path: Path, net: GuideNet, channels,
           portable: bool) -> np.ndarray:
    """The C++ output for ``passes`` with the model at ``path``, checked against the torch
    pipeline within the tolerance of test_cxx_matches_python_pipeline (no message)."""
    ok, out, den, messages = cxx_denoise(passes, str(path), PortableKernels=portable)
    assert ok and den.GetNetworkActive() and messages == [], den.GetStatus()
    ref = torch_pipeline(passes, net, channels)
    span = float(ref.max() - ref.min())
    err = float(np.abs(out - ref).max())
    assert span > 0 and err <= 1e-4 * span, f"max |C++ - Python| = {err:.3g}, range {span:.3g}"
    return out


@pytest.mark.parametrize("portable", [False, True], ids=["dispatched", "portable"])
def test_history_channel_matches_python(passes, tmp_path, portable) -> None:
    """A model with the ``history`` channel (1 / max(1, HistoryLength), features.py) reads the
    HistoryLength image as torch does -- fractional counts, counts below 1, NaN (one frame) and
    +inf (0) -- within the parity tolerance of test_cxx_matches_python_pipeline; the channel
    reaches the output (a history of 4 frames everywhere denoises otherwise than 1); without a
    HistoryLength image every pixel counts one frame (the result of a HistoryLength of 1)."""
    torch.manual_seed(7)
    channels = features.PAPER_10 + ["history"]
    net = GuideNet(len(channels), hidden=8, kernel=3, levels=3, stride=2, out_channels=8).eval()
    path = export(net, tmp_path / "history.onnx", channels, levels=LEVELS)
    h, w = H_of(passes), passes["Radiance"].shape[1]
    frames = np.random.default_rng(3).uniform(0.0, 4.0, (h, w, 1)).astype(np.float32)
    frames[0, 0], frames[0, 1], frames[1, 0] = np.nan, np.inf, 1.0
    with_history = dict(passes, HistoryLength=frames)
    plane = features.build_features(with_history, ["history"])[0]
    assert plane[0, 0] == 1.0 and plane[0, 1] == 0.0 and plane[1, 0] == 1.0
    parity(with_history, path, net, channels, portable)
    outs = []
    for count in (1.0, 4.0):
        still = dict(passes, HistoryLength=np.full((h, w, 1), count, np.float32))
        ok, out, den, messages = cxx_denoise(still, str(path), PortableKernels=portable)
        assert ok and den.GetNetworkActive() and messages == [], den.GetStatus()
        outs.append(out)
    assert not np.array_equal(outs[0], outs[1])
    ok, out, den, messages = cxx_denoise(passes, str(path), PortableKernels=portable)
    assert ok and den.GetNetworkActive() and messages == [], den.GetStatus()
    assert np.array_equal(out, outs[0])


@pytest.mark.parametrize("portable", [False, True], ids=["dispatched", "portable"])
def test_coverage_channel_matches_python(passes, tmp_path, portable) -> None:
    """A model with the ``coverage`` channel (clip(Coverage, 0, 1), features.py) reads the
    Coverage image as torch does, values outside [0, 1] included, within the parity tolerance of
    test_cxx_matches_python_pipeline; the channel reaches the output (the traced coverage
    denoises otherwise than Alpha in its place); without a Coverage image the denoiser refuses
    the frame and names the pass."""
    torch.manual_seed(11)
    channels = features.PAPER_10 + ["coverage"]
    net = GuideNet(len(channels), hidden=8, kernel=3, levels=3, stride=2, out_channels=8).eval()
    path = export(net, tmp_path / "coverage.onnx", channels, levels=LEVELS)
    coverage = passes["Coverage"][..., 0]
    assert ((coverage > 0.05) & (coverage < 0.95)).mean() > 0.05  # the scene is translucent
    odd = dict(passes, Coverage=passes["Coverage"].copy())
    odd["Coverage"][0, 0], odd["Coverage"][0, 1] = -0.5, 1.5
    plane = features.build_features(odd, ["coverage"])[0]
    assert plane[0, 0] == 0.0 and plane[0, 1] == 1.0
    outs = []
    for given in (odd, dict(passes, Coverage=passes["Alpha"])):
        outs.append(parity(given, path, net, channels, portable))
    assert not np.array_equal(outs[0], outs[1])
    from ptv_vtk_messages import observe

    den = rendering.vtkPTVDenoiser()
    seen = observe(den)
    den.SetModelFile(str(path))
    for name, a in passes.items():
        if name != "Coverage":
            den.SetImage(name, to_image(name, a))
    assert not den.Execute()
    assert any("ErrorEvent" in m and "'Coverage'" in m for m in seen), seen


def test_mapper_coverage_pass(tmp_path) -> None:
    """The mapper's Coverage pass: Alpha unless the march is on; with CoverageMarch each
    camera ray's opacity -- fractional in the translucent wavelet, every other pass bit for bit
    as without it, and its mean that of Alpha over 64 frames (its expectation; within 5
    standard errors of the gap); with Denoise and a model that reads "coverage" the mapper
    marches by itself (CoverageMarch off), with a model that does not it does not."""
    from ptv_wavelet_scene import get_pass, wavelet_scene

    size = (40, 30)

    def run(compute: bool, model: Path | None = None, frames: int = 1) -> dict:
        window, mapper, keep = wavelet_scene(size, opacity=0.15, seed=5,
                                             denoise=model is not None)
        mapper.GetExpertOptions().SetCoverageMarch(compute)
        if model is not None:
            mapper.SetDenoiserModelFile(str(model))
            # the passes of the frame alone (test_edge_samples.py)
            mapper.GetExpertOptions().SetEdgeSamples(1)
        mapper.GetExpertOptions().SetMaximumAccumulatedFrames(frames)
        for _ in range(frames):
            window.Render()
        return {name: get_pass(mapper, name, size) for name in TRACED}

    off, on = run(False), run(True)
    assert np.array_equal(off["Coverage"], off["Alpha"])
    c = on["Coverage"]
    assert ((c > 0.05) & (c < 0.95)).mean() > 0.1 and c.min() >= 0 and c.max() <= 1
    assert all(np.array_equal(off[name], on[name]) for name in TRACED if name != "Coverage")
    many = run(True, frames=64)
    gap = many["Alpha"] - many["Coverage"]  # per pixel: mean of 64 coin flips minus their p
    se = np.sqrt(np.sum(many["Coverage"] * (1 - many["Coverage"])) / 64) / gap.size
    assert abs(gap.mean()) < 5 * se + 1e-6, (gap.mean(), se)
    torch.manual_seed(2)
    for channels, marched in ((features.PAPER_10 + ["coverage"], True),
                              (features.PAPER_10, False)):
        net = GuideNet(len(channels), hidden=8, kernel=3, levels=3, stride=2, out_channels=8)
        path = export(net.eval(), tmp_path / f"c{len(channels)}.onnx", channels, levels=LEVELS)
        denoised = run(False, path)
        assert np.array_equal(denoised["Coverage"], on["Coverage"] if marched else on["Alpha"])


def test_model_default_levels(passes, tmp_path) -> None:
    """export(default_levels=D): above 256^2 pixels the C++ runs the finest D levels unless
    NumberOfLevels asks for others (up to the model's), exactly what NumberOfLevels = D gives;
    at or below it every level (bilateral_grid.automatic_levels, the same rule)."""
    torch.manual_seed(6)
    channels = features.VOLUME_FEATURES
    net = GuideNet(len(channels), hidden=8, kernel=3, levels=3, stride=2, out_channels=8).eval()
    path = export(net, tmp_path / "default1.onnx", channels, levels=LEVELS, default_levels=1)
    import onnx
    props = {p.key: p.value for p in onnx.load(str(path)).metadata_props}
    assert props["ptv.default_levels"] == "1" and props["ptv.levels"] == "4:4,8:8,16:16"
    h, w = H_of(passes), next(iter(passes.values())).shape[1]
    reps = (-(-257 // h), -(-257 // w))  # just above 256^2 pixels
    large = {k: np.ascontiguousarray(np.tile(v, reps + (1,) * (v.ndim - 2)))
             for k, v in passes.items()}
    big = next(iter(large.values())).shape[:2]
    assert big[0] * big[1] > 256 * 256
    ok, out, den, messages = cxx_denoise(large, str(path))
    assert ok and den.GetNetworkActive() and messages == [], den.GetStatus()
    assert ", 1 levels" in den.GetStatus(), den.GetStatus()
    ok1, out1, den1, _ = cxx_denoise(large, str(path), NumberOfLevels=1)
    assert ok1 and np.array_equal(out, out1)
    ok3, out3, den3, _ = cxx_denoise(large, str(path), NumberOfLevels=3)
    assert ok3 and ", 3 levels" in den3.GetStatus() and not np.array_equal(out, out3)
    expected = bilateral_grid.automatic_levels(LEVELS, 1, h, w)
    assert h * w <= 256 * 256 and expected == bilateral_grid.fitting_levels(LEVELS, h, w)
    ok, _, small, _ = cxx_denoise(passes, str(path))
    assert ok and f", {expected} levels" in small.GetStatus(), small.GetStatus()
    assert bilateral_grid.automatic_levels(LEVELS, 1, 256, 256) == 3
    assert bilateral_grid.automatic_levels(LEVELS, 1, 256, 257) == 1
    assert bilateral_grid.automatic_levels(LEVELS, 2, 1024, 1024) == 2
    with pytest.raises(ValueError, match="default_levels"):
        export(net, tmp_path / "bad.onnx", channels, levels=LEVELS, use_levels=2,
               default_levels=3)


@pytest.mark.parametrize("use_levels", [1, 2])
def test_model_shipped_with_fewer_levels(passes, tmp_path, use_levels) -> None:
    """export(use_levels=N): the C++ runs the model's finest N levels (the other outputs become
    padding, the weights reordered after the guides) exactly as torch's run_model(use_levels=N)."""
    from ptv_training.train import run_model
    torch.manual_seed(5)
    channels = features.VOLUME_FEATURES
    net = GuideNet(len(channels), hidden=8, kernel=3, levels=3, stride=2, out_channels=8).eval()
    path = export(net, tmp_path / "fewer.onnx", channels, levels=LEVELS, use_levels=use_levels)
    import onnx
    props = {p.key: p.value for p in onnx.load(str(path)).metadata_props}
    assert props["ptv.levels"] == ",".join(f"{a}:{b}" for a, b in LEVELS[:use_levels])
    assert len(props["ptv.outputs"].split(",")) == 8
    ok, out, den, messages = cxx_denoise(passes, str(path))
    assert ok and den.GetNetworkActive() and messages == [], den.GetStatus()
    assert f"{use_levels} levels" in den.GetStatus()
    feats = torch.from_numpy(features.build_features(passes, channels))[None]
    with torch.no_grad():
        radiance = torch.from_numpy(passes["Radiance"]).permute(2, 0, 1)[None]
        albedo = torch.from_numpy(passes["Albedo"]).permute(2, 0, 1)[None]
        ref, _, _ = run_model(net, feats, radiance, albedo, LEVELS, 8.0, True, use_levels)
    ref = ref[0].permute(1, 2, 0).numpy()
    span = float(ref.max() - ref.min())
    assert float(np.abs(out - ref).max()) <= 1e-4 * span


@pytest.mark.parametrize("variant", VARIANTS, ids=lambda v: f"s{v[0]}k{v[1]}o{v[2] or 5}")
def test_threads_give_identical_output(passes, variant_models, variant) -> None:
    path, _, _ = variant_models[variant]
    images = [cxx_denoise(passes, str(path), NumberOfThreads=t)[1] for t in (1, 2, 3)]
    assert np.array_equal(images[0], images[1]) and np.array_equal(images[0], images[2])


def test_portable_environment_variable(passes, random_model, monkeypatch) -> None:
    """PTV_PORTABLE_KERNELS=1 forces the baseline build like the property does."""
    path, _, _ = random_model
    monkeypatch.setenv("PTV_PORTABLE_KERNELS", "1")
    ok, forced, den, _ = cxx_denoise(passes, str(path))
    assert ok and den.GetKernelTarget() in ("SCALAR", "EMU128")
    monkeypatch.delenv("PTV_PORTABLE_KERNELS")
    ok, _, den, _ = cxx_denoise(passes, str(path))
    assert ok and den.GetKernelTarget() not in ("", "SCALAR", "EMU128")


def test_levels_and_timings(passes, random_model) -> None:
    path, _, _ = random_model
    ok, out1, den, _ = cxx_denoise(passes, str(path), NumberOfLevels=1)
    assert ok and np.isfinite(out1).all()
    guides = vtkImageData()
    den.GetGuides(guides)
    assert guides.GetPointData().GetArray("Guides").GetNumberOfComponents() == 1
    assert den.GetLastGuideNetTime() > 0 and den.GetLastSplatTime() > 0


def test_small_images_drop_coarse_levels(passes, random_model) -> None:
    """With the automatic level count a small image drops the levels too coarse for it (fewer
    than 16 cells of the grid over the image), the finest always stays, and the result still
    matches the torch pipeline, which applies the same rule; an explicit count is kept."""
    path, net, channels = random_model
    assert bilateral_grid.fitting_levels(LEVELS, 43, 61) == 2  # 16-pixel cells: 10 < 16
    assert bilateral_grid.fitting_levels(LEVELS, 64, 64) == 3
    assert bilateral_grid.fitting_levels(LEVELS, 1, 1) == 1
    assert bilateral_grid.fitting_levels(LEVELS, 7, 1000) == 3  # a strip: 109 cells of 16 px
    for size, expected in ((8, 1), (12, 1), (24, 1), (32, 2)):
        y0, x0 = (H - size) // 2, (W - size) // 2  # the middle of the frame
        small = {k: np.ascontiguousarray(v[y0:y0 + size, x0:x0 + size])
                 for k, v in passes.items()}
        assert bilateral_grid.fitting_levels(LEVELS, size, size) == expected
        ok, out, den, messages = cxx_denoise(small, str(path))
        assert ok and messages == [] and f"{expected} levels" in den.GetStatus(), den.GetStatus()
        ref = torch_pipeline(small, net, channels)
        span = max(float(ref.max() - ref.min()), 1e-6)
        assert float(np.abs(out - ref).max()) <= 1e-4 * span
        ok, _, den, _ = cxx_denoise(small, str(path), NumberOfLevels=3)
        assert ok and "3 levels" in den.GetStatus(), den.GetStatus()


def test_fixed_guide_without_model(passes) -> None:
    ok, out, den, messages = cxx_denoise(passes, "/nonexistent/model.onnx")
    assert ok and not den.GetNetworkActive()
    assert "no GuideNet model" in den.GetStatus()
    assert messages == ["warning"]  # warned once
    assert np.isfinite(out).all()


@pytest.mark.parametrize("content", [b"", b"not an onnx model at all" * 10])
def test_corrupt_model_falls_back(passes, tmp_path, content) -> None:
    bad = tmp_path / "bad.onnx"
    bad.write_bytes(content)
    ok, out, den, messages = cxx_denoise(passes, str(bad))
    assert ok and not den.GetNetworkActive() and messages == ["warning"]
    assert np.isfinite(out).all()


def test_colour_only_model_and_truncated_model(passes, tmp_path) -> None:
    # Any channel subset is a valid model; a truncated file falls back with a warning.
    # (Models whose shapes contradict their metadata are refused in test_guidenet.py.)
    torch.manual_seed(0)
    net = GuideNet(3, hidden=0, kernel=3, levels=3)
    path = tmp_path / "colour.onnx"
    export(net, path, ["color.r", "color.g", "color.b"], levels=LEVELS)
    ok, out, den, _ = cxx_denoise(passes, str(path))
    assert ok and den.GetNetworkActive()  # a colour-only model is valid
    half = tmp_path / "truncated.onnx"
    half.write_bytes(path.read_bytes()[: path.stat().st_size // 2])
    ok, out, den, messages = cxx_denoise(passes, str(half))
    assert ok and not den.GetNetworkActive() and "warning" in messages


def test_bad_images_are_errors(passes, random_model) -> None:
    path, _, _ = random_model
    no_albedo = {k: v for k, v in passes.items() if k != "Albedo"}
    ok, _, _, messages = cxx_denoise(no_albedo, str(path))
    assert not ok and "error" in messages
    small = dict(passes)
    small["Depth"] = passes["Depth"][:-1]
    ok, _, _, messages = cxx_denoise(small, str(path))
    assert not ok and "error" in messages
    wrong = dict(passes)
    wrong["Albedo"] = passes["Albedo"][:, :, :1]
    ok, _, _, messages = cxx_denoise(wrong, str(path))
    assert not ok and "error" in messages
    den = rendering.vtkPTVDenoiser()
    errors = []
    den.AddObserver("ErrorEvent", lambda o, e: errors.append(e))
    den.SetImage("NoSuchPass", vtkImageData())
    assert errors


@pytest.mark.parametrize("variant", VARIANTS, ids=lambda v: f"s{v[0]}k{v[1]}o{v[2] or 5}")
def test_nan_inf_zero_albedo_and_odd_sizes(variant_models, variant) -> None:
    path, _, _ = variant_models[variant]
    rng = np.random.default_rng(1)
    for h, w in ((1, 1), (3, 4097), (17, 5)):
        p = {
            "Radiance": rng.random((h, w, 3), dtype=np.float32) * 2,
            "Albedo": np.zeros((h, w, 3), np.float32),
            "Normal": rng.random((h, w, 3), dtype=np.float32) * 2 - 1,
            "Depth": rng.random((h, w, 1), dtype=np.float32) * 10,
            "ScatterNormal": rng.random((h, w, 3), dtype=np.float32) * 2 - 1,
            "ScatterDepth": rng.random((h, w, 1), dtype=np.float32) * 10,
        }
        p["Radiance"].flat[:: 7] = np.nan
        p["Radiance"].flat[3:: 11] = np.inf
        ok, out, den, messages = cxx_denoise(p, str(path))
        assert ok and den.GetNetworkActive() and messages == []
        assert out.shape == (h, w, 3) and np.isfinite(out).all(), (h, w)


@pytest.mark.parametrize("use_network", [True, False], ids=["network", "fixed_guide"])
def test_sample_ratio_leans_towards_own_means(passes, random_model, use_network) -> None:
    """A "SampleRatio" image (how many times a plain pixel's samples each pixel's mean holds;
    the mapper's edge pixels hold EdgeSamples times) moves every pixel of ratio r > 1 towards
    its own mean by w = (r - 1) / (r - 1 + 4) (ptv::OwnMeanWeight, kDenoisedSampleWorth 4):
    out = D + w (mean - D), in the colour (Radiance) and in the DenoisedAlpha opacity (Alpha),
    D being the result without the image. Ratios <= 1, NaN and infinite, and pixels whose own
    radiance is NaN, infinite or negative, keep D; so does an image of ones."""
    p = {k: v for k, v in passes.items() if k != "Footprint"}  # its step would clear pixels
    h, w = H_of(p), p["Radiance"].shape[1]
    rng = np.random.default_rng(5)
    ratio = np.ones((h, w, 1), np.float32)
    ratio[rng.random((h, w)) < 0.3] = 3.0
    ratio[rng.random((h, w)) < 0.1] = 8.0
    ratio[0, :5, 0] = [np.nan, np.inf, -2.0, 0.5, 1.0]
    radiance = p["Radiance"].copy()
    radiance[1, :3] = [[np.nan, 0, 0], [np.inf, 0, 0], [-1.0, 0, 0]]
    ratio[1, :3] = 3.0
    p = dict(p, Radiance=radiance)
    settings = dict(DenoiseAlpha=True, UseNetwork=use_network)

    def run(extra: dict) -> tuple:
        ok, out, den, messages = cxx_denoise(dict(p, **extra), str(random_model[0]), **settings)
        assert ok and messages == [], den.GetStatus()
        assert den.GetNetworkActive() == use_network, den.GetStatus()
        alpha = vtk_to_numpy(den.GetOutput().GetPointData().GetArray("DenoisedAlpha"))
        return out.copy(), alpha.reshape(h, w).copy()

    base, base_alpha = run({})
    leaned, leaned_alpha = run({"SampleRatio": ratio})
    r = np.where(np.isfinite(ratio[..., 0]), ratio[..., 0], 1.0)
    usable = np.all(np.isfinite(radiance) & (radiance >= 0), axis=-1)
    weight = np.where(usable & (r > 1), (r - 1) / (np.maximum(r, 1) - 1 + 4.0), 0.0)
    own = np.where(usable[..., None], radiance, base)
    want = base + weight[..., None] * (own - base)
    want_alpha = base_alpha + weight * (np.clip(p["Alpha"][..., 0], 0, 1) - base_alpha)
    assert (weight > 0).sum() > 0.3 * h * w and np.any(np.abs(leaned - base) > 1e-3)
    assert np.allclose(leaned, want, rtol=1e-5, atol=1e-6)
    assert np.allclose(leaned_alpha, want_alpha, rtol=1e-5, atol=1e-6)
    assert np.array_equal(leaned[weight == 0], base[weight == 0])
    ones, ones_alpha = run({"SampleRatio": np.ones((h, w, 1), np.float32)})
    assert np.array_equal(ones, base) and np.array_equal(ones_alpha, base_alpha)
