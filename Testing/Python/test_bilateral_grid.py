"""Tests of the bilateral-grid denoiser: the torch reference and the C++ class.

(a) ``ptv_training.bilateral_grid`` alone: a brute-force evaluation of the definitions in
    ``Rendering/Kernels/ptvBilateralGrid.h`` on tiny images, constant images come back, the
    output is finite for NaN/Inf/negative input, gradients reach the guides and weights.
(b) The C++ grid of ``vtkPTVDenoiser`` run alone (images "Guides" and "BlendWeights" given, no
    network; "Albedo" given exactly when demodulating) against the torch reference on random and
    structured inputs, sizes 37x23, 64x64, 129x77 and 1x1, 1 and 3 levels, clamp on and off:
    max |C++ - torch| <= 1e-4 * (max - min of the torch output), for the dispatched and the
    portable build of the C++ kernels.
"""

from __future__ import annotations

import itertools
import math
import sys
from pathlib import Path
from typing import Callable, Dict, Tuple

import numpy as np
import pytest

from ptv_vtk_messages import observe
import torch

TRAINING_DIR = Path(__file__).resolve().parents[2] / "Training"
if str(TRAINING_DIR) not in sys.path:
    sys.path.append(str(TRAINING_DIR))

from ptv_training import bilateral_grid as bg  # noqa: E402

SIZES = ((37, 23), (64, 64), (129, 77), (1, 1))  # (W, H)
PARITY_TOLERANCE = 1e-4


def to_torch(array: np.ndarray) -> torch.Tensor:
    """(H, W, C) numpy -> (1, C, H, W) float32 tensor."""
    return torch.from_numpy(np.ascontiguousarray(array, dtype=np.float32)).permute(2, 0, 1)[None]


def random_inputs(rng: np.random.Generator, width: int, height: int,
                  levels: int) -> Tuple[np.ndarray, ...]:
    """HDR radiance with fireflies, albedo with zeros, guides in [0, 255], weights in [0, 1]."""
    radiance = rng.gamma(0.8, 0.5, (height, width, 3)).astype(np.float32)
    fireflies = rng.random((height, width)) < 0.01
    radiance[fireflies] *= rng.uniform(100.0, 5000.0, (int(fireflies.sum()), 1)).astype(np.float32)
    albedo = rng.random((height, width, 3)).astype(np.float32)
    albedo[rng.random((height, width)) < 0.05] = 0.0
    albedo[rng.random((height, width, 3)) < 0.02] = 0.0
    guides = (rng.random((height, width, levels)) * 255.0).astype(np.float32)
    guides[rng.random((height, width, levels)) < 0.02] = 0.0
    guides[rng.random((height, width, levels)) < 0.02] = 255.0
    weights = rng.random((height, width, max(levels - 1, 1))).astype(np.float32)
    return radiance, albedo, guides, weights[..., :levels - 1]


def structured_inputs(rng: np.random.Generator, width: int, height: int,
                      levels: int) -> Tuple[np.ndarray, ...]:
    """Smooth gradients with sharp edges (a disc and a step), noise, guides that follow them."""
    y, x = np.mgrid[0:height, 0:width].astype(np.float32)
    fx = x / max(width - 1, 1)
    fy = y / max(height - 1, 1)
    disc = ((fx - 0.4) ** 2 + (fy - 0.55) ** 2) < 0.09
    step = fx > 0.7
    base = np.stack([0.2 + fx, 0.5 + 0.5 * fy, 0.3 + 0.2 * fx * fy], axis=-1)
    base[disc] *= 4.0
    base[step] *= 0.1
    radiance = (base * rng.exponential(1.0, base.shape)).astype(np.float32)
    albedo = np.stack([0.8 - 0.5 * fx, 0.3 + 0.6 * fy, np.full_like(fx, 0.5)], axis=-1)
    albedo[disc] = (0.9, 0.1, 0.1)
    albedo[step] = 0.0
    luma = 255.0 * np.clip(0.25 * base.mean(axis=-1), 0.0, 1.0)
    guides = np.stack([np.clip(luma + 10.0 * level + rng.normal(0.0, 2.0, luma.shape), 0.0, 255.0)
                       for level in range(levels)], axis=-1).astype(np.float32)
    weights = np.stack([np.clip(0.6 - 0.3 * fx, 0.0, 1.0), np.clip(0.2 + 0.3 * fy, 0.0, 1.0)],
                       axis=-1).astype(np.float32)
    return radiance, albedo, guides, weights[..., :levels - 1]


def torch_denoise(radiance: np.ndarray, albedo: np.ndarray, guides: np.ndarray,
                  weights: np.ndarray, clamp: float, demodulate: bool = True) -> np.ndarray:
    levels = guides.shape[-1]
    out = bg.denoise(to_torch(radiance), to_torch(albedo) if demodulate else None,
                     to_torch(guides),
                     to_torch(weights) if levels > 1 else None,
                     bg.DEFAULT_LEVELS[:levels], clamp)
    return out[0].permute(1, 2, 0).numpy()


# ------------------------------------------------------------------------------------------
# (a) the torch reference alone
# ------------------------------------------------------------------------------------------

def brute_force_level(demod: np.ndarray, guide: np.ndarray, ss: int,
                      sr: int) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Splat and slice literally as defined (float64 loops over every cell and pixel)."""
    height, width, _ = demod.shape
    gw, gh, gd = math.ceil(width / ss), math.ceil(height / ss), math.ceil(256 / sr)

    def tent(a: float) -> float:
        return max(0.0, 1.0 - abs(a))

    u = [(x + 0.5) / ss - 0.5 for x in range(width)]
    v = [(y + 0.5) / ss - 0.5 for y in range(height)]
    z = np.clip(guide, 0.0, 255.0) / sr
    values = np.zeros((gd, gh, gw, 3))
    weights = np.zeros((gd, gh, gw))
    for k, j, i in itertools.product(range(gd), range(gh), range(gw)):
        for y, x in itertools.product(range(height), range(width)):
            w = tent(u[x] - i) * tent(v[y] - j) * tent(z[y, x] - k)
            weights[k, j, i] += w
            values[k, j, i] += w * demod[y, x]
        if weights[k, j, i] > 0:
            values[k, j, i] /= weights[k, j, i]
    sliced = np.zeros((height, width, 3))
    for y, x in itertools.product(range(height), range(width)):
        i0, j0, k0 = math.floor(u[x]), math.floor(v[y]), math.floor(z[y, x])
        acc, total = np.zeros(3), 0.0
        for j, i, k in itertools.product((j0, j0 + 1), (i0, i0 + 1), (k0, k0 + 1)):
            if 0 <= i < gw and 0 <= j < gh and 0 <= k < gd and weights[k, j, i] > 0:
                w = tent(u[x] - i) * tent(v[y] - j) * tent(z[y, x] - k)
                acc += w * values[k, j, i]
                total += w
        sliced[y, x] = acc / total if total > 0 else 0.0
    return values, weights, sliced


@pytest.mark.parametrize("width,height,ss,sr", [(7, 5, 2, 64), (9, 4, 3, 50), (1, 1, 4, 4),
                                                (5, 6, 1, 100)])
def test_splat_and_slice_match_the_definition(width: int, height: int, ss: int,
                                              sr: int) -> None:
    rng = np.random.default_rng(width * 100 + height)
    demod = rng.gamma(1.0, 1.0, (height, width, 3))
    guide = rng.random((height, width)) * 255.0
    guide[0, 0] = 2.0 * sr  # exactly on a range-bin boundary
    values, weights, sliced = brute_force_level(demod, guide, ss, sr)
    d = torch.from_numpy(demod).permute(2, 0, 1)[None]
    g = torch.from_numpy(guide)[None, None]
    grid_values, grid_weights = bg.splat(d, g, ss, sr)
    assert tuple(grid_weights.shape[1:]) == weights.shape
    np.testing.assert_allclose(grid_weights[0].numpy(), weights, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(grid_values[0].permute(1, 2, 3, 0).numpy(), values,
                               rtol=1e-12, atol=1e-12)
    out = bg.slice(grid_values, grid_weights, g, ss, sr)
    np.testing.assert_allclose(out[0].permute(1, 2, 0).numpy(), sliced, rtol=1e-12, atol=1e-12)


def test_blend_formula() -> None:
    rng = np.random.default_rng(3)
    s = [torch.from_numpy(rng.random((2, 3, 4, 5))) for _ in range(3)]
    w = torch.from_numpy(rng.random((2, 2, 4, 5)))
    w1, w2 = w[:, 0:1], w[:, 1:2]
    torch.testing.assert_close(bg.blend(s, w), s[0] * w1 + s[1] * w2 + s[2] * (1 - w1 - w2))
    torch.testing.assert_close(bg.blend(s[:2], w[:, :1]), s[0] * w1 + s[1] * (1 - w1))
    assert bg.blend(s[:1], None) is s[0]


@pytest.mark.parametrize("levels", [1, 2, 3])
@pytest.mark.parametrize("clamp", [8.0, 0.0])
def test_constant_image_comes_back(levels: int, clamp: float) -> None:
    rng = np.random.default_rng(levels)
    height, width = 45, 61
    colour = np.array([0.3, 0.6, 0.9], dtype=np.float32)
    albedo_colour = np.array([0.2, 0.0, 0.8], dtype=np.float32)
    radiance = np.broadcast_to(colour, (height, width, 3))
    albedo = np.broadcast_to(albedo_colour, (height, width, 3))
    guides = (rng.random((height, width, levels)) * 255.0).astype(np.float32)
    weights = rng.random((height, width, max(levels - 1, 1)))[..., :levels - 1]
    out = torch_denoise(radiance, albedo, guides, weights, clamp)
    assert np.abs(out - radiance).max() <= 1e-6


def test_output_finite_for_bad_input() -> None:
    rng = np.random.default_rng(5)
    radiance, albedo, guides, weights = random_inputs(rng, 40, 30, 3)
    radiance[0, :5] = [np.nan, np.inf, -np.inf]
    radiance[1, :5] = -3.0
    radiance[2, :5] = 3e38
    albedo[3, :5] = [np.nan, -1.0, np.inf]
    guides[4, :5] = [np.nan, np.inf, -np.inf]
    guides[5, :5] = [-50.0, 300.0, 1e30]
    weights[6, :5] = [np.nan, np.inf]
    weights[7, :5] = [-2.0, 5.0]
    for clamp in (8.0, 0.0):
        out = torch_denoise(radiance, albedo, guides, weights, clamp)
        assert np.isfinite(out).all()  # (may be negative: the third blend weight may be)
    nan_frame = np.full_like(radiance, np.nan)
    assert np.array_equal(torch_denoise(nan_frame, albedo, guides, weights, 8.0),
                          np.zeros_like(radiance))


def test_gradients_reach_guides_and_weights() -> None:
    rng = np.random.default_rng(6)
    radiance, albedo, guides, weights = structured_inputs(rng, 33, 20, 3)
    g = to_torch(guides).requires_grad_(True)
    w = to_torch(weights).requires_grad_(True)
    out = bg.denoise(to_torch(radiance), to_torch(albedo), g, w)
    loss = (out - to_torch(radiance)).abs().mean()
    loss.backward()
    for name, grad in (("guides", g.grad), ("weights", w.grad)):
        assert grad is not None, name
        assert torch.isfinite(grad).all(), name
        assert grad.abs().max() > 0, name


def test_gradcheck_small() -> None:
    rng = np.random.default_rng(7)
    radiance = torch.from_numpy(rng.gamma(1.0, 1.0, (1, 3, 6, 7)))
    albedo = torch.from_numpy(rng.random((1, 3, 6, 7)))
    guides = torch.from_numpy(10.0 + 200.0 * rng.random((1, 2, 6, 7))).requires_grad_(True)
    weights = torch.from_numpy(0.1 + 0.8 * rng.random((1, 1, 6, 7))).requires_grad_(True)

    def f(g: torch.Tensor, w: torch.Tensor) -> torch.Tensor:
        return bg.denoise(radiance, albedo, g, w, levels=((2, 32), (3, 64)), clamp=0.0)

    assert torch.autograd.gradcheck(f, (guides, weights), eps=1e-6, atol=1e-5)


def test_batch_is_per_image() -> None:
    rng = np.random.default_rng(8)
    frames = [random_inputs(rng, 20, 12, 3) for _ in range(2)]
    batched = bg.denoise(*(torch.cat([to_torch(f[i]) for f in frames]) for i in range(4)))
    for index, frame in enumerate(frames):
        single = torch_denoise(*frame, clamp=8.0)
        np.testing.assert_array_equal(batched[index].permute(1, 2, 0).numpy(), single)


def test_invalid_shapes_raise() -> None:
    r = torch.zeros(1, 3, 4, 5)
    with pytest.raises(ValueError, match="guides"):
        bg.denoise(r, r, torch.zeros(1, 2, 4, 5), torch.zeros(1, 2, 4, 5))
    with pytest.raises(ValueError, match="weights"):
        bg.denoise(r, r, torch.zeros(1, 3, 4, 5), None)
    with pytest.raises(ValueError, match="albedo"):
        bg.denoise(r, torch.zeros(1, 3, 4, 6), torch.zeros(1, 1, 4, 5), None, levels=((4, 4),))
    with pytest.raises(ValueError, match="spatial_step"):
        bg.splat(r, torch.zeros(1, 1, 4, 5), 0, 4)


# ------------------------------------------------------------------------------------------
# (b) C++ (vtkPTVDenoiser with given guides) against the torch reference
# ------------------------------------------------------------------------------------------

def vtk_image(array: np.ndarray):
    """(H, W, C) float32 -> W x H x 1 vtkImageData with C-component active scalars."""
    from vtkmodules.util import numpy_support
    from vtkmodules.vtkCommonDataModel import vtkImageData

    height, width, components = array.shape
    image = vtkImageData()
    image.SetDimensions(width, height, 1)
    scalars = numpy_support.numpy_to_vtk(
        np.ascontiguousarray(array, dtype=np.float32).reshape(-1, components), deep=1)
    scalars.SetName("input")
    image.GetPointData().SetScalars(scalars)
    return image


def grid_denoiser(radiance: np.ndarray, albedo: np.ndarray, guides: np.ndarray,
                  weights: np.ndarray, clamp: float, threads: int = 2,
                  demodulate: bool = True):
    """A vtkPTVDenoiser set up to run the grid alone on the given guides and weights: Radiance,
    Albedo (only when demodulating: the grid divides by it exactly when it is given), Guides,
    BlendWeights (when L > 1). Returns the denoiser and its message list."""
    from pathtracedvolume.vtkPTVRendering import vtkPTVDenoiser

    levels = guides.shape[-1]
    denoiser = vtkPTVDenoiser()
    messages = observe(denoiser)
    denoiser.SetNumberOfLevels(levels)
    denoiser.SetClamp(clamp)
    denoiser.SetNumberOfThreads(threads)
    denoiser.SetImage("Radiance", vtk_image(radiance))
    if demodulate:
        denoiser.SetImage("Albedo", vtk_image(albedo))
    denoiser.SetImage("Guides", vtk_image(guides))
    if levels > 1:
        denoiser.SetImage("BlendWeights", vtk_image(weights))
    return denoiser, messages


def denoised(denoiser, shape: Tuple[int, ...]) -> np.ndarray:
    """The "Denoised" array of the denoiser's output as (H, W, 3) (a copy)."""
    from vtkmodules.util import numpy_support

    output = denoiser.GetOutput()
    scalars = output.GetPointData().GetScalars()
    assert scalars.GetName() == "Denoised"
    assert output.GetDimensions() == (shape[1], shape[0], 1)
    return numpy_support.vtk_to_numpy(scalars).reshape(shape).copy()


def cpp_denoise(radiance: np.ndarray, albedo: np.ndarray, guides: np.ndarray,
                weights: np.ndarray, clamp: float, threads: int = 2,
                demodulate: bool = True) -> np.ndarray:
    levels = guides.shape[-1]
    denoiser, messages = grid_denoiser(radiance, albedo, guides, weights, clamp, threads,
                                       demodulate)
    assert denoiser.Execute(), messages
    assert messages == []
    assert not denoiser.GetNetworkActive()
    assert denoiser.GetStatus() == f"given guides, {levels} levels" + (
        "" if demodulate else ", no demodulation (no Albedo)")
    return denoised(denoiser, radiance.shape)


INPUTS: Dict[str, Callable[..., Tuple[np.ndarray, ...]]] = {
    "random": random_inputs, "structured": structured_inputs}


@pytest.mark.parametrize("portable", ["0", "1"], ids=["dispatched", "portable"])
@pytest.mark.parametrize("kind", sorted(INPUTS))
@pytest.mark.parametrize("clamp", [8.0, 0.0], ids=["clamp8", "noclamp"])
@pytest.mark.parametrize("levels", [1, 3])
@pytest.mark.parametrize("size", SIZES, ids=[f"{w}x{h}" for w, h in SIZES])
def test_cpp_matches_torch(size: Tuple[int, int], levels: int, clamp: float,
                           kind: str, portable: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """Both builds of the C++ row kernels: this CPU's best instruction set (dispatched) and the
    baseline one (PTV_PORTABLE_KERNELS=1). The C++ splat pushes pixels into cells, torch gathers
    them: float sums of the same terms in another order, a few 1e-6 relative apart."""
    monkeypatch.setenv("PTV_PORTABLE_KERNELS", portable)
    width, height = size
    rng = np.random.default_rng(width * 1000 + height + levels)
    inputs = INPUTS[kind](rng, width, height, levels)
    reference = torch_denoise(*inputs, clamp=clamp)
    result = cpp_denoise(*inputs, clamp=clamp)
    assert np.isfinite(result).all()
    span = float(reference.max() - reference.min())
    error = float(np.abs(result - reference).max())
    print(f"parity {kind} {width}x{height} L={levels} clamp={clamp:g}: max |C++ - torch| = "
          f"{error:.3g} (output range {span:.4g}, relative {error / max(span, 1e-30):.3g})")
    assert error <= PARITY_TOLERANCE * span


def test_cpp_bad_input_parity() -> None:
    """Non-finite radiance/albedo/guides/weights are sanitised alike in C++ and torch."""
    rng = np.random.default_rng(11)
    radiance, albedo, guides, weights = random_inputs(rng, 40, 30, 3)
    radiance[0, :3] = [np.nan, np.inf, -1.0]
    radiance[2, :3] = 2e38
    albedo[3, :3] = [np.nan, -1.0, np.inf]
    albedo[4, :3] = 7.0
    guides[5, :3] = [np.nan, np.inf, -np.inf]
    guides[6, :3] = [-50.0, 300.0, 1e30]
    weights[7, :3] = [np.nan, np.inf]
    weights[8, :3] = [-2.0, 5.0]
    for clamp in (8.0, 0.0):
        reference = torch_denoise(radiance, albedo, guides, weights, clamp)
        result = cpp_denoise(radiance, albedo, guides, weights, clamp)
        assert np.isfinite(result).all()
        span = float(reference.max() - reference.min())
        assert np.abs(result - reference).max() <= PARITY_TOLERANCE * span


def test_cpp_threads_bit_identical() -> None:
    rng = np.random.default_rng(12)
    inputs = structured_inputs(rng, 129, 77, 3)
    one = cpp_denoise(*inputs, clamp=8.0, threads=1)
    for threads in (2, 3, 0):
        assert np.array_equal(one, cpp_denoise(*inputs, clamp=8.0, threads=threads))


def test_cpp_custom_steps_match_torch() -> None:
    levels = ((3, 5), (6, 50), (1, 256))
    rng = np.random.default_rng(13)
    radiance, albedo, guides, weights = random_inputs(rng, 31, 19, 3)
    reference = bg.denoise(to_torch(radiance), to_torch(albedo), to_torch(guides),
                           to_torch(weights), levels, clamp=2.5)[0].permute(1, 2, 0).numpy()
    denoiser, messages = grid_denoiser(radiance, albedo, guides, weights, clamp=2.5)
    denoiser.SetNumberOfLevels(0)  # 0: the guides' component count
    for index, (ss, sr) in enumerate(levels):
        denoiser.SetSpatialStep(index, ss)
        denoiser.SetRangeStep(index, sr)
        assert (denoiser.GetSpatialStep(index), denoiser.GetRangeStep(index)) == (ss, sr)
    assert denoiser.Execute(), messages
    assert denoiser.GetStatus() == "given guides, 3 levels"
    result = denoised(denoiser, radiance.shape)
    span = float(reference.max() - reference.min())
    assert np.abs(result - reference).max() <= PARITY_TOLERANCE * span
    # Steps are clamped to 1..256; an invalid level is an error and reads as 0.
    denoiser.SetSpatialStep(0, 0)
    denoiser.SetRangeStep(1, 1000)
    assert (denoiser.GetSpatialStep(0), denoiser.GetRangeStep(1)) == (1, 256)
    assert messages == []
    denoiser.SetSpatialStep(3, 4)
    assert len(messages) == 1 and "SetSpatialStep: level 3 is out of range [0, 2]" in \
        messages[0], messages
    assert denoiser.GetRangeStep(-1) == 0
    assert len(messages) == 2 and "GetRangeStep: level -1 is out of range" in messages[1]


def test_cpp_defaults() -> None:
    from pathtracedvolume.vtkPTVRendering import vtkPTVDenoiser

    denoiser = vtkPTVDenoiser()
    assert denoiser.GetNumberOfLevels() == 0  # the guides' (or the model's) level count
    assert denoiser.GetClamp() == 8.0
    assert denoiser.GetNumberOfThreads() == 0
    assert [(denoiser.GetSpatialStep(i), denoiser.GetRangeStep(i)) for i in range(3)] == list(
        bg.DEFAULT_LEVELS)


def test_cpp_given_guides_bad_inputs() -> None:
    """Guides/BlendWeights that do not fit are errors: Execute() fails with one message naming
    the image, and the output keeps the last result."""
    rng = np.random.default_rng(14)
    radiance, albedo, guides, weights = random_inputs(rng, 9, 7, 3)
    denoiser, messages = grid_denoiser(radiance, albedo, guides, weights, clamp=8.0)
    assert denoiser.Execute(), messages
    first = denoised(denoiser, radiance.shape)

    def fails(*texts: str) -> None:
        messages.clear()
        assert not denoiser.Execute()
        assert len(messages) == 1 and messages[0].startswith("ErrorEvent"), messages
        for text in texts:
            assert text in messages[0], (text, messages[0])
        assert np.array_equal(denoised(denoiser, radiance.shape), first)

    denoiser.SetNumberOfLevels(2)
    fails("'Guides' has 3 components but NumberOfLevels is 2")
    denoiser.SetNumberOfLevels(3)
    denoiser.SetImage("BlendWeights", vtk_image(weights[..., :1]))
    fails("Image 'BlendWeights' has 1 components; 3 levels of 'Guides' need 2.")
    denoiser.SetImage("BlendWeights", None)
    fails("3 levels of 'Guides' need 'BlendWeights' (2 components)")
    denoiser.SetImage("BlendWeights", vtk_image(weights[1:]))
    fails("Image 'BlendWeights' is 9 x 6 but the passes are 9 x 7.")
    denoiser.SetImage("Guides", vtk_image(np.concatenate([guides, guides[..., :1]], axis=-1)))
    denoiser.SetImage("BlendWeights",
                      vtk_image(np.concatenate([weights, weights[..., :1]], axis=-1)))
    denoiser.SetNumberOfLevels(0)
    fails("'Guides' has 4 components; 1 to 3 (one per grid level) are possible")
    denoiser.SetImage("BlendWeights", vtk_image(weights))
    denoiser.SetImage("Guides", None)
    fails("Image 'BlendWeights' is set without 'Guides'.")
    denoiser.SetImage("Guides", vtk_image(guides))
    messages.clear()
    assert denoiser.Execute() and messages == []
    assert np.array_equal(denoised(denoiser, radiance.shape), first)


def test_clamp_limit_uses_lit_pixels_only() -> None:
    """The outlier limit is Clamp x the mean luminance of the lit pixels (luminance > 0).

    A 10x10 frame, 96 black background pixels, 3 lit pixels of luminance 1 and one of 5:
    the lit mean is 2, so Clamp = 2 caps at 4 (a whole-frame mean of 0.08 would cap at 0.16).
    Checked on the demodulated clamp in torch and end to end in C++ with one 1x1-cell level
    and no range blur: the firefly pixel comes back as exactly its cap times (A + eps).
    """
    radiance = np.zeros((10, 10, 3), np.float32)
    albedo = np.full((10, 10, 3), 1.0 - bg.DEMODULATION_EPSILON, np.float32)  # A + eps = 1
    radiance[0, 0:3] = 1.0
    radiance[9, 9] = 5.0
    demod = bg.demodulate(to_torch(radiance), to_torch(albedo))
    clamped = bg.clamp_outliers(demod, 2.0)[0].permute(1, 2, 0).numpy()
    assert np.allclose(clamped[9, 9], 4.0, rtol=1e-6)
    assert np.allclose(clamped[0, 0:3], 1.0, rtol=1e-6)
    assert (clamped[1:9] == 0).all()
    dark = np.zeros_like(radiance)  # nothing lit: the limit is the 1e-6 floor, output 0
    assert (bg.clamp_outliers(bg.demodulate(to_torch(dark), to_torch(albedo)), 2.0) == 0).all()

    # C++: guides put every pixel in its own range bin far from its neighbours' values.
    guides = np.zeros((10, 10, 1), np.float32)
    guides[9, 9, 0] = 255.0
    weights = np.zeros((10, 10, 0), np.float32)
    result = cpp_denoise(radiance, albedo, guides, weights, clamp=2.0)
    expected = torch_denoise(radiance, albedo, guides, weights, clamp=2.0)
    assert np.allclose(result, expected, rtol=1e-6, atol=1e-7)
    assert np.allclose(result[9, 9], 4.0, rtol=1e-6)


@pytest.mark.parametrize("levels", [1, 3])
def test_cpp_matches_torch_without_demodulation(levels: int) -> None:
    """Demodulate off: C++ (no albedo image at all) and torch (albedo None) agree, and the
    result differs from the demodulated one (the albedo really is left out)."""
    rng = np.random.default_rng(7 + levels)
    inputs = structured_inputs(rng, 129, 77, levels)
    reference = torch_denoise(*inputs, clamp=8.0, demodulate=False)
    result = cpp_denoise(*inputs, clamp=8.0, demodulate=False)
    span = float(reference.max() - reference.min())
    assert np.isfinite(result).all()
    assert float(np.abs(result - reference).max()) <= PARITY_TOLERANCE * span
    demodulated = cpp_denoise(*inputs, clamp=8.0)
    assert float(np.abs(result - demodulated).max()) > 0.01 * span
