"""VTK's intensity blend modes (issue #61): maximum, minimum and average intensity and additive
are ray cast in the tracer's kernels and match VTK's own mappers' images.

* MaximumIntensity and MinimumIntensity against vtkFixedPointVolumeRayCastMapper;
* AverageIntensity and Additive against vtkOpenGLGPUVolumeRayCastMapper at the same sample
  distance (one voxel). vtkFixedPointVolumeRayCastMapper has no average (it errors) and renders
  Additive as Composite (measured here with VTK 9.2), so VTK's GPU ray caster is the reference;
* each renders without a warning and a still render stops after the minimum of 8 samples (no
  Monte Carlo noise to converge), with Denoise left on;
* a split volume (DistributedVolume) cannot composite a projection across pieces: one warning,
  Composite.

The scene: a 32^3 radial field with a ripple, a red-to-green colour map, 96^2, a blue
background. Our pixels are the mean of 8 jittered rays and the stock mappers' one central ray,
so silhouettes differ by up to a whole pixel's coverage; the tolerances: median channel
difference <= 1/255 and >= 95 % of the pixels within 8/255 (measured: 97-100 %).
Needs a display (ctest runs under Xvfb) and the built package on PYTHONPATH.
"""
from __future__ import annotations

from typing import Any, Callable, List

import numpy as np
import pytest
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction
from vtkmodules.vtkRenderingCore import (vtkColorTransferFunction, vtkRenderer, vtkRenderWindow,
                                         vtkVolume, vtkVolumeProperty, vtkWindowToImageFilter)
from vtkmodules.vtkRenderingVolume import vtkFixedPointVolumeRayCastMapper
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (OpenGL factories)
from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper

from pathtracedvolume import vtkPathTracedVolumeMapper

SIZE = 96
MAXIMUM, MINIMUM, AVERAGE, ADDITIVE = 1, 2, 3, 4
_WINDOWS: list = []  # kept open: Xvfb resets when its last client leaves


def _volume() -> vtkImageData:
    n = 32
    z, y, x = np.mgrid[0:n, 0:n, 0:n]
    r = np.sqrt((x - 15.5) ** 2 + (y - 15.5) ** 2 + (z - 15.5) ** 2)
    v = np.clip(255 * (1 - r / 16) + 30 * np.sin(x / 3.0), 0, 255).astype(np.uint8)
    image = vtkImageData()
    image.SetDimensions(n, n, n)
    array = numpy_to_vtk(v.ravel(), deep=True)
    array.SetName("v")
    image.GetPointData().SetScalars(array)
    return image


def _render(mapper: Any, mode: int) -> np.ndarray:
    colour = vtkColorTransferFunction()
    colour.AddRGBPoint(0, 1, 0, 0)
    colour.AddRGBPoint(255, 0, 1, 0)
    opacity = vtkPiecewiseFunction()
    if mode == MINIMUM:  # the low scalars are the visible ones
        opacity.AddPoint(0, 0.8)
        opacity.AddPoint(255, 0.0)
    else:
        opacity.AddPoint(0, 0.0)
        opacity.AddPoint(255, 0.5)
    prop = vtkVolumeProperty()
    prop.SetColor(colour)
    prop.SetScalarOpacity(opacity)
    prop.SetInterpolationTypeToLinear()
    mapper.SetInputData(_volume())
    mapper.SetBlendMode(mode)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    renderer = vtkRenderer()
    renderer.AddVolume(volume)
    renderer.SetBackground(0, 0, 1)
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetMultiSamples(0)
    window.SetSize(SIZE, SIZE)
    window.AddRenderer(renderer)
    _WINDOWS.append(window)
    renderer.GetActiveCamera().Azimuth(30)
    renderer.GetActiveCamera().Elevation(20)
    renderer.ResetCamera()
    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    grab.ShouldRerenderOff()
    grab.Update()
    pixels = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars())
    return pixels.reshape(SIZE, SIZE, -1)[..., :3].astype(np.float64)


def _gpu() -> Any:
    mapper = vtkOpenGLGPUVolumeRayCastMapper()
    mapper.AutoAdjustSampleDistancesOff()
    mapper.SetSampleDistance(1.0)  # one voxel: the path tracer's step
    return mapper


@pytest.mark.parametrize("mode,reference", [
    (MAXIMUM, vtkFixedPointVolumeRayCastMapper), (MINIMUM, vtkFixedPointVolumeRayCastMapper),
    (AVERAGE, _gpu), (ADDITIVE, _gpu)], ids=["maximum", "minimum", "average", "additive"])
def test_projection_matches_vtk(mode: int, reference: Callable[[], Any]) -> None:
    ours = vtkPathTracedVolumeMapper()
    messages: List[str] = []
    ours.AddObserver(vtkCommand.WarningEvent, lambda *a: messages.append("warning"))
    image = _render(ours, mode)
    stock = _render(reference(), mode)
    diff = np.abs(image - stock).max(axis=2)
    shown = (np.abs(stock - [0, 0, 255]).max(axis=2) > 8).mean()
    assert shown > 0.2, f"the reference shows too little to compare ({shown:.2f} of the image)"
    assert np.median(diff) <= 1.0 and (diff <= 8).mean() >= 0.95, (
        f"median {np.median(diff)}, within 8/255: {(diff <= 8).mean():.3f}, "
        f"max {diff.max()}")
    assert not messages
    assert ours.GetStatistics().GetLastRenderFrames() == 8 and ours.GetStillConverged(), (
        ours.GetStatistics().GetLastRenderFrames(), ours.GetStillConverged())


def test_split_volume_projection_warns_once_and_composites() -> None:
    from vtkmodules.util.misc import calldata_type
    from vtkmodules.util.vtkConstants import VTK_STRING

    ours = vtkPathTracedVolumeMapper()
    ours.DistributedVolumeOn()
    ours.SetPieceExtent(0, 31, 0, 31, 0, 31)
    ours.SetWholeExtent(0, 31, 0, 31, 0, 31)
    texts: List[str] = []

    @calldata_type(VTK_STRING)
    def on_warning(obj: Any, event: str, data: Any) -> None:
        texts.append(str(data))
    ours.AddObserver(vtkCommand.WarningEvent, on_warning)
    image = _render(ours, MAXIMUM)
    _WINDOWS[-1].Render()
    assert len(texts) == 1 and "DistributedVolume" in texts[0], texts
    composite = _render(vtkPathTracedVolumeMapper(), 0)
    mip = _render(vtkFixedPointVolumeRayCastMapper(), MAXIMUM)
    to_composite = np.abs(image - composite).mean()
    to_mip = np.abs(image - mip).mean()
    assert to_composite < 0.3 * to_mip, (to_composite, to_mip)
