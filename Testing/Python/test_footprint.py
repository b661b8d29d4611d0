"""The Footprint pass (vtkPTVExpertOptions FootprintRays, ptvIntegrator.h step 4d) and
the denoiser's use of it: pixels whose four corners it marks empty come out black.

The closed-form check of the kernel (a straight edge) is the C++ TestPTVKernelFootprint; here
the same rule is checked end to end through the mapper and vtkPTVDenoiser."""
from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("pathtracedvolume")

from ptv_wavelet_scene import get_pass, set_traced_passes, wavelet_scene  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

import pathtracedvolume.vtkPTVRendering as ptv  # noqa: E402

SIZE = (48, 36)  # (W, H)
TRACED = ["Radiance", "Alpha", "Albedo", "Depth", "Position", "Normal", "ScatterDepth",
          "ScatterPosition", "ScatterNormal", "Coverage"]


def empty_by_corners(footprint: np.ndarray) -> np.ndarray:
    """The documented rule: a pixel is empty when the Footprint entries of its four corners --
    its own and those of pixels (x + 1, y), (x, y + 1), (x + 1, y + 1), clamped at the edge --
    are all 0 (``footprint`` is (H, W))."""
    f = np.pad(footprint > 0, ((0, 1), (0, 1)), mode="edge")
    return ~(f[:-1, :-1] | f[:-1, 1:] | f[1:, :-1] | f[1:, 1:])


def render(compute: bool, denoise: bool = False, frames: int = 1, zoom: float = 0.6) -> tuple:
    """The wavelet zoomed out (``zoom`` < 1: empty space around the box) after ``frames``."""
    window, mapper, keep = wavelet_scene(SIZE, opacity=0.3, seed=3, denoise=denoise)
    keep[3].GetActiveCamera().Zoom(zoom)
    mapper.GetExpertOptions().SetFootprintRays(compute)
    mapper.GetExpertOptions().SetMaximumAccumulatedFrames(frames)
    for _ in range(frames):
        window.Render()
    names = TRACED + ["Footprint"] + (["Denoised", "DenoisedAlpha"] if denoise else [])
    passes = {name: get_pass(mapper, name, SIZE) for name in names}
    return passes, (window, mapper, keep)


def grid(a: np.ndarray) -> np.ndarray:
    return a.reshape(SIZE[1], SIZE[0], -1)


def test_footprint_pass_and_other_passes_unchanged() -> None:
    """Off: Footprint is 1 everywhere. On: 1 wherever the camera ray met opacity (a first hit),
    0 on the empty space around the box, and every other pass is bit-identical (the rays draw
    no random numbers); so after 4 accumulated frames."""
    for frames in (1, 4):
        off, _ = render(False, frames=frames)
        on, _ = render(True, frames=frames)
        assert np.all(off["Footprint"] == 1.0)
        for name in TRACED:
            assert np.array_equal(off[name], on[name]), name
        f = on["Footprint"]
        assert f.min() >= 0 and f.max() <= 1
        far = off["Depth"].max()
        met = on["Depth"] < 0.999 * far  # a first hit in some frame: its mean is below far
        assert np.all(f[met] > 0)
        assert 0.1 < (f == 0).mean() < 0.9, (f == 0).mean()
        assert np.all(on["Alpha"][f == 0] == 0)


def test_denoised_image_is_black_where_the_footprint_is_empty() -> None:
    """With Denoise the frame loop traces the pass by itself (FootprintRays off), and the
    denoised colour and opacity are 0 exactly on the pixels the corner rule marks empty; a
    pixel that is not marked keeps what the denoiser made of it (the same as with a Footprint
    image of ones, through vtkPTVDenoiser on the mapper's own passes)."""
    passes, (window, mapper, keep) = render(False, denoise=True)
    f = grid(passes["Footprint"])[..., 0]
    assert (f == 0).mean() > 0.1  # traced by itself
    empty = empty_by_corners(f)
    assert 0.05 < empty.mean() < 0.9
    denoised, alpha = grid(passes["Denoised"]), grid(passes["DenoisedAlpha"])[..., 0]
    assert np.all(denoised[empty] == 0) and np.all(alpha[empty] == 0)

    def denoise(footprint: np.ndarray | None) -> np.ndarray:
        den = ptv.vtkPTVDenoiser()
        images = set_traced_passes(mapper, den)
        if footprint is None:
            den.SetImage("Footprint", None)
        else:
            image = images[TRACED.index("Coverage") + 1]  # the Footprint image, replaced
            array = image.GetPointData().GetArray("Footprint")
            for i, value in enumerate(footprint.ravel()):
                array.SetValue(i, float(value))
        den.SetDenoiseAlpha(True)
        assert den.Execute(), den.GetStatus()
        out = den.GetOutput().GetPointData().GetArray("Denoised")
        return vtk_to_numpy(out).reshape(SIZE[1], SIZE[0], 3).copy()

    ones = denoise(np.ones_like(f))
    assert np.array_equal(denoise(None), ones)
    marked = denoise(f)
    assert np.array_equal(marked, denoised)
    assert np.array_equal(marked[~empty], ones[~empty])
    assert np.all(marked[empty] == 0) and ones[empty].max() > 0  # it changed something


def test_footprint_in_the_settings() -> None:
    """Documented properties with their defaults, printed by PrintSelf."""
    mapper = ptv.vtkPathTracedVolumeMapper()
    options = mapper.GetExpertOptions()
    assert not options.GetFootprintRays()
    mapper.GetExpertOptions().FootprintRaysOn()
    assert options.GetFootprintRays()
    assert "FootprintRays: 1" in str(mapper)
