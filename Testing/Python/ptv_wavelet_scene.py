"""Shared by the Python tests: the mapper on VTK's wavelet source in an off-screen window, its
passes as numpy arrays, and the window read back."""
from __future__ import annotations

from typing import Any, Sequence, Tuple

import numpy as np


def wavelet_scene(size: Tuple[int, int], extent: int = 10, opacity: float = 0.6,
                  background: Sequence[float] = (0.5, 0.5, 0.5), seed: int = 0,
                  denoise: bool = False,
                  scatter_passes: bool = True) -> Tuple[Any, Any, tuple]:
    """(window, mapper, objects to keep alive): the wavelet over [-extent, extent]^3, colour
    blue to yellow and opacity 0 to ``opacity`` over its range, shaded, frame by frame (still
    renders do not converge), ``size`` = (W, H) pixels. With ``scatter_passes`` the mapper
    keeps every traced pass (the expert option ScatterPasses; the tests read them all, e.g.
    :func:`set_traced_passes`); off: the mapper's default, no Scatter* passes."""
    import pathtracedvolume.vtkPTVRendering as ptv
    from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
    from vtkmodules.vtkImagingCore import vtkRTAnalyticSource
    from vtkmodules.vtkRenderingCore import (vtkColorTransferFunction, vtkRenderer,
                                             vtkRenderWindow, vtkVolume, vtkVolumeProperty)
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401

    source = vtkRTAnalyticSource()
    source.SetWholeExtent(-extent, extent, -extent, extent, -extent, extent)
    color = vtkColorTransferFunction()
    color.AddRGBPoint(37, 0.2, 0.4, 1.0)
    color.AddRGBPoint(277, 1.0, 0.9, 0.5)
    ramp = vtkPiecewiseFunction()
    ramp.AddPoint(37, 0.0)
    ramp.AddPoint(277, opacity)
    prop = vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(ramp)
    prop.ShadeOn()
    mapper = ptv.vtkPathTracedVolumeMapper()
    mapper.ConvergeStillRendersOff()  # frame by frame
    mapper.SetInputConnection(source.GetOutputPort())
    mapper.SetSeed(seed)
    mapper.SetDenoise(denoise)
    mapper.GetExpertOptions().SetScatterPasses(scatter_passes)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    renderer = vtkRenderer()
    renderer.AddVolume(volume)
    renderer.SetBackground(*background)
    renderer.ResetCamera()
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(*size)
    window.AddRenderer(renderer)
    return window, mapper, (source, prop, volume, renderer)


def get_pass(mapper: Any, name: str, size: Tuple[int, int]) -> np.ndarray:
    """Pass ``name`` as a flat float32 array (W * H values, or W * H x components)."""
    import vtkmodules.util.numpy_support as vtk_numpy
    from vtkmodules.vtkCommonDataModel import vtkImageData

    image = vtkImageData()
    assert mapper.GetPass(name, image), name
    assert image.GetDimensions() == (size[0], size[1], 1)
    return vtk_numpy.vtk_to_numpy(image.GetPointData().GetArray(name)).copy()


def read_window(window: Any) -> np.ndarray:
    """The window's colour as drawn by the last render, (H, W, 3) in [0, 1], bottom row first."""
    import vtkmodules.util.numpy_support as vtk_numpy
    from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter

    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ShouldRerenderOff()
    grab.ReadFrontBufferOff()  # off-screen: the frame is in the back buffer
    grab.Update()
    w, h = window.GetSize()
    pixels = vtk_numpy.vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars())
    return pixels.reshape(h, w, -1)[..., :3].astype(np.float64) / 255.0


TRACED_PASSES = 11  # the traced passes come first (vtkPathTracedVolumeMapper::GetPassName)


def set_traced_passes(mapper: Any, denoiser: Any) -> list:
    """Give ``denoiser`` (a vtkPTVDenoiser) the mapper's traced passes by name, as the mapper's
    own denoise sees them; returns the images (keep them while the denoiser runs)."""
    from vtkmodules.vtkCommonDataModel import vtkImageData

    images = []
    names = [mapper.GetPassName(i) for i in range(TRACED_PASSES)]
    for name in names:
        image = vtkImageData()
        assert mapper.GetPass(name, image), name
        image.GetPointData().SetActiveScalars(name)
        images.append(image)
        denoiser.SetImage(name, image)
    return images
