"""The denoised image is drawn with its own opacity, DenoisedAlpha, not with the accumulated Alpha.

One frame's Alpha is 0 or 1 per pixel. Drawn with it, the window showed the background wherever
the frame's ray met no event (the shader discards alpha <= 0) however much colour the denoiser
gave the pixel, and no background through a translucent pixel whose ray met one. These tests
read the window back and check it against the passes: premultiplied colour over the background
with DenoisedAlpha as the opacity, DenoisedAlpha is the Alpha pass through the finest level of
the denoiser's grid (vtkPTVDenoiser with the same guide), and Converged is drawn with the same
per-pixel mix of Alpha and DenoisedAlpha as its colour's (ptvConvergence: DenoisedAlpha, plus
the 3x3 or 7x7 box of Alpha - DenoisedAlpha, or Alpha), so within the range of those four.
Needs a display (ctest runs under Xvfb) and the built package on PYTHONPATH."""
from __future__ import annotations

from typing import Tuple

import numpy as np

import vtkmodules.util.numpy_support as vtk_numpy
import pathtracedvolume.vtkPTVRendering as ptv

from vtkmodules.vtkCommonDataModel import vtkImageData  # noqa: E402
from ptv_wavelet_scene import (get_pass as wavelet_pass, read_window,  # noqa: E402
                               set_traced_passes, wavelet_scene)

W, H = 64, 48
# One unit of the window's 8 bits, and the rounding of colour + (1 - alpha) background into it.
LSB = 1.0 / 255.0


def make_scene(background: Tuple[float, float, float]):
    # Translucent (opacity at most 0.05): many rays of one frame meet no event.
    return wavelet_scene((W, H), extent=16, opacity=0.05, background=background, denoise=True)


def get_pass(mapper, name: str) -> np.ndarray:
    return wavelet_pass(mapper, name, (W, H)).reshape(H, W, -1)


def opacity_bounds(alpha: np.ndarray, denoised_alpha: np.ndarray, background: np.ndarray
                   ) -> Tuple[np.ndarray, np.ndarray]:
    """Per pixel the least and most opacity the shown image's mix can draw with (its four
    candidates, clamped to [0, 1]), widened by the window's rounding."""
    from scipy.ndimage import uniform_filter
    residual = alpha - denoised_alpha
    candidates = np.stack([denoised_alpha, alpha] + [
        denoised_alpha + uniform_filter(residual, size=s, mode="nearest") for s in (3, 7)])
    candidates = np.clip(candidates, 0.0, 1.0)
    slack = 3 * LSB / background.min()
    return candidates.min(0) - slack, candidates.max(0) + slack


def used_opacity(win: np.ndarray, shown: np.ndarray, background: np.ndarray) -> np.ndarray:
    """The opacity the window was drawn with, from colour + (1 - a) background."""
    return 1 - ((win - shown) / background).mean(-1)


def test_one_frame_is_drawn_with_the_mixed_opacity() -> None:
    background = np.array([0.2, 0.4, 0.6])
    window, mapper, _ = make_scene(tuple(background))
    window.Render()
    assert mapper.GetAccumulatedFrames() == 1
    shown = get_pass(mapper, "Converged").astype(np.float64)
    alpha = get_pass(mapper, "Alpha")[..., 0].astype(np.float64)
    denoised_alpha = get_pass(mapper, "DenoisedAlpha")[..., 0].astype(np.float64)
    assert set(np.unique(alpha)) <= {0.0, 1.0}
    assert 0.0 <= denoised_alpha.min() and denoised_alpha.max() <= 1.0
    # The case that was drawn wrong: pixels with colour whose ray met no event.
    lit = (alpha == 0) & (shown.max(-1) > 4 * LSB) & (denoised_alpha > 0)
    assert lit.sum() >= 20, f"the scene should have translucent misses ({lit.sum()})"

    win = read_window(window)
    lo, hi = opacity_bounds(alpha, denoised_alpha, background)
    inside = (shown + background < 1 - 2 * LSB).all(-1) & (np.maximum(alpha, denoised_alpha) > 0)
    used = used_opacity(win, shown, background)
    assert ((used >= lo) & (used <= hi))[inside].all(), "opacity outside the mix's candidates"
    nothing = (alpha == 0) & (denoised_alpha == 0)
    assert np.abs(win[nothing] - background).max() <= 1.5 * LSB, "opacity 0: the background"
    # Drawn with the frame's Alpha those pixels would show the background alone.
    moved = np.abs(win[lit] - background).max(-1)
    assert moved.mean() > 3 * LSB, f"colour where the frame's ray met nothing: {moved.mean()}"


def test_denoised_alpha_is_alpha_through_the_finest_grid_level() -> None:
    window, mapper, _ = make_scene((0.0, 0.0, 0.0))
    window.Render()
    alpha = get_pass(mapper, "Alpha")
    guides = get_pass(mapper, "Guides")
    denoiser = ptv.vtkPTVDenoiser()
    images = []
    for name, values in (("Radiance", np.repeat(alpha, 3, axis=-1)),
                         ("Guides", guides[..., :1])):
        image = vtkImageData()
        image.SetDimensions(W, H, 1)
        array = vtk_numpy.numpy_to_vtk(
            np.ascontiguousarray(values.reshape(W * H, -1), np.float32), deep=1)
        array.SetName(name)
        image.GetPointData().SetScalars(array)
        images.append(image)
        denoiser.SetImage(name, image)
    denoiser.SetSpatialStep(0, 4)  # the shipped model's finest level (4:4)
    denoiser.SetRangeStep(0, 4)
    denoiser.SetClamp(0.0)
    assert denoiser.Execute(), denoiser.GetStatus()
    out = vtk_numpy.vtk_to_numpy(denoiser.GetOutput().GetPointData().GetArray("Denoised"))
    expected = np.clip(out.reshape(H, W, 3)[..., 0], 0, 1)
    # ... and 0 where the Footprint pass marks the pixel empty (all four corners 0).
    f = np.pad(get_pass(mapper, "Footprint")[..., 0] > 0, ((0, 1), (0, 1)), mode="edge")
    empty = ~(f[:-1, :-1] | f[:-1, 1:] | f[1:, :-1] | f[1:, 1:])
    expected[empty] = 0.0
    got = get_pass(mapper, "DenoisedAlpha")[..., 0]
    assert np.abs(got - expected).max() <= 1e-6
    assert np.abs(got - alpha[..., 0]).max() > 0.1, "the grid smooths the 0/1 coverage"


def test_converged_is_drawn_with_the_mix_of_alpha_and_denoised_alpha() -> None:
    background = np.array([0.5, 0.5, 0.5])
    window, mapper, _ = make_scene(tuple(background))
    for _ in range(12):
        window.Render()
    assert mapper.GetAccumulatedFrames() == 12
    shown = get_pass(mapper, "Converged").astype(np.float64)
    alpha = get_pass(mapper, "Alpha")[..., 0].astype(np.float64)
    denoised_alpha = get_pass(mapper, "DenoisedAlpha")[..., 0].astype(np.float64)
    win = read_window(window)
    inside = (shown + background < 1 - 2 * LSB).all(-1) & (np.maximum(alpha, denoised_alpha) > 0)
    used = used_opacity(win, shown, background)
    lo, hi = opacity_bounds(alpha, denoised_alpha, background)
    assert inside.sum() > 100
    assert ((used >= lo) & (used <= hi))[inside].all()
    assert np.abs(used - alpha)[inside].max() > 0.05, "not just the accumulated Alpha"


def test_vtk_denoiser_denoise_alpha_is_what_the_mapper_does() -> None:
    window, mapper, _ = make_scene((0.0, 0.0, 0.0))
    window.Render()
    denoiser = ptv.vtkPTVDenoiser()
    images = set_traced_passes(mapper, denoiser)
    assert denoiser.Execute()
    out = denoiser.GetOutput().GetPointData()
    assert out.GetArray("DenoisedAlpha") is None, "off by default: the colour alone"
    plain = vtk_numpy.vtk_to_numpy(out.GetArray("Denoised")).reshape(H, W, 3).copy()
    denoiser.DenoiseAlphaOn()
    assert denoiser.Execute()
    out = denoiser.GetOutput().GetPointData()
    color = vtk_numpy.vtk_to_numpy(out.GetArray("Denoised")).reshape(H, W, 3)
    alpha = vtk_numpy.vtk_to_numpy(out.GetArray("DenoisedAlpha")).reshape(H, W)
    assert np.array_equal(color, get_pass(mapper, "Denoised"))
    assert np.array_equal(alpha, get_pass(mapper, "DenoisedAlpha")[..., 0])
    assert denoiser.GetLastAlphaTime() > 0
    empty = alpha == 0
    assert (color[empty] == 0).all()
    assert np.array_equal(color[~empty], plain[~empty]), "only the empty pixels change"
    # Without the Alpha image it is an error, and the output keeps the last result.
    kept = color.copy()
    denoiser.SetImage("Alpha", None)
    errors = []
    denoiser.AddObserver("ErrorEvent", lambda obj, event: errors.append(event))
    assert not denoiser.Execute()
    assert errors
    after = denoiser.GetOutput().GetPointData().GetArray("Denoised")
    assert np.array_equal(vtk_numpy.vtk_to_numpy(after).reshape(H, W, 3), kept)
