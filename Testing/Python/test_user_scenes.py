"""Ordinary scenes a user's first script builds (issue #59): each must draw the right image.

* A cube in front of the head in a default vtkRenderWindow (which asks for 8 multisamples): the
  cube must stay in front, as with SetMultiSamples(0) (before: the depth read of the
  multisampled framebuffer failed and the volume was drawn over the cube).
* Two overlapping translucent volumes: each shows through the other in either order of
  AddVolume, as the stock mapper's (before: the first one's depth cut the second one's rays).
Needs the head dataset, a display (ctest runs under Xvfb) and the built package on PYTHONPATH.
"""
from __future__ import annotations

from typing import Any

import numpy as np
from vtkmodules.util import numpy_support
from vtkmodules.vtkFiltersSources import vtkCubeSource
from vtkmodules.vtkRenderingCore import (vtkActor, vtkPolyDataMapper, vtkRenderer,
                                         vtkRenderWindow, vtkVolume, vtkWindowToImageFilter)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (OpenGL factories)
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401 (the stock mapper's display helper)

from pathtracedvolume import vtkPathTracedVolumeMapper
from pathtracedvolume.scene import load_dataset, paper_preset, volume_property

SIZE = 96
# Windows stay open until the process ends: closing the X server's last client makes Xvfb
# without -noreset reset, and the next window would abort in XOpenDisplay.
_WINDOWS: list = []


def _screenshot(window: Any) -> np.ndarray:
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    grab.Update()
    w, h = window.GetSize()
    pixels = numpy_support.vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars())
    return pixels.reshape(h, w, -1)[..., :3].astype(np.float64) / 255.0


def _cube_in_front(multisamples: int) -> np.ndarray:
    """The head with a red cube between it and the camera; ``multisamples`` < 0: the window's
    default."""
    data = load_dataset("head")
    mapper = vtkPathTracedVolumeMapper()
    mapper.SetInputData(data)
    mapper.SetSeed(1)
    mapper.ConvergeStillRendersOff()
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(volume_property(paper_preset("head")))
    renderer = vtkRenderer()
    renderer.AddVolume(volume)
    renderer.ResetCamera()
    camera = renderer.GetActiveCamera()
    b = data.GetBounds()
    centre = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
    eye = np.array(camera.GetPosition())
    toward = np.array(centre) + 0.3 * (eye - np.array(centre))  # between the head and the eye
    cube = vtkCubeSource()
    cube.SetCenter(*toward)
    side = 0.25 * (b[1] - b[0])
    cube.SetXLength(side)
    cube.SetYLength(side)
    cube.SetZLength(side)
    cube_mapper = vtkPolyDataMapper()
    cube_mapper.SetInputConnection(cube.GetOutputPort())
    actor = vtkActor()
    actor.SetMapper(cube_mapper)
    actor.GetProperty().SetColor(1.0, 0.0, 0.0)
    actor.GetProperty().SetAmbient(1.0)
    actor.GetProperty().SetDiffuse(0.0)
    renderer.AddActor(actor)
    renderer.ResetCameraClippingRange()
    window = vtkRenderWindow()
    if multisamples >= 0:
        window.SetMultiSamples(multisamples)
    window.SetOffScreenRendering(1)
    window.SetSize(SIZE, SIZE)
    window.AddRenderer(renderer)
    window.Render()
    image = _screenshot(window)
    _WINDOWS.append(window)
    return image


def test_cube_in_front_of_the_volume_with_the_default_window() -> None:
    reference = _cube_in_front(0)
    default = _cube_in_front(-1)
    red = (reference[..., 0] > 0.9) & (reference[..., 1] < 0.1) & (reference[..., 2] < 0.1)
    assert red.sum() > 100, "the cube is not in view: the test scene is wrong"
    still_red = (default[..., 0] > 0.9) & (default[..., 1] < 0.1) & (default[..., 2] < 0.1)
    kept = (still_red & red).sum() / red.sum()
    print(f"cube pixels: {red.sum()}, kept in the default window: {kept:.3f}")
    assert kept > 0.95, f"the volume is drawn over the cube in a default window ({kept:.3f})"


def _two_volumes(order: str, stock: bool = False) -> np.ndarray:
    """Two overlapping translucent wavelet volumes, a red one in front of a blue one along the
    view, added in ``order`` ("front first", "back first", or "front" / "back" alone);
    ``stock``: VTK's CPU ray caster instead."""
    from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
    from vtkmodules.vtkImagingCore import vtkRTAnalyticSource
    from vtkmodules.vtkRenderingCore import vtkColorTransferFunction as ColorTF
    from vtkmodules.vtkRenderingCore import vtkVolumeProperty
    from vtkmodules.vtkRenderingVolume import vtkFixedPointVolumeRayCastMapper

    renderer = vtkRenderer()
    renderer.SetBackground(0.0, 0.0, 0.0)
    volumes = []
    for shift, colour in (((0.0, 0.0, 12.0), (1.0, 0.3, 0.2)),
                          ((8.0, 6.0, -12.0), (0.2, 0.4, 1.0))):
        source = vtkRTAnalyticSource()
        source.SetWholeExtent(-10, 10, -10, 10, -10, 10)
        source.Update()
        image = source.GetOutput()
        image.SetOrigin(*shift)
        ctf = ColorTF()
        ctf.AddRGBPoint(37.0, *colour)
        ctf.AddRGBPoint(277.0, *colour)
        otf = vtkPiecewiseFunction()
        otf.AddPoint(37.0, 0.02)
        otf.AddPoint(277.0, 0.02)
        prop = vtkVolumeProperty()
        prop.SetColor(ctf)
        prop.SetScalarOpacity(otf)
        prop.SetInterpolationTypeToLinear()
        mapper = vtkFixedPointVolumeRayCastMapper() if stock else vtkPathTracedVolumeMapper()
        mapper.SetInputData(image)
        volume = vtkVolume()
        volume.SetMapper(mapper)
        volume.SetProperty(prop)
        volumes.append((volume, image))
    chosen = {"front first": volumes, "back first": volumes[::-1], "front": volumes[:1],
              "back": volumes[1:]}[order]
    for volume, _ in chosen:
        renderer.AddVolume(volume)
    camera = renderer.GetActiveCamera()
    camera.SetFocalPoint(4.0, 3.0, 0.0)
    camera.SetPosition(4.0, 3.0, 120.0)  # looking down -z: the first volume is the front one
    renderer.ResetCameraClippingRange()
    window = vtkRenderWindow()
    window.SetMultiSamples(0)
    window.SetOffScreenRendering(1)
    window.SetSize(64, 64)
    window.AddRenderer(renderer)
    window.Render()
    image = _screenshot(window)
    _WINDOWS.append(window)
    return image


def test_two_translucent_volumes_draw_in_either_order() -> None:
    """Where the red volume covers the blue one, the blue one must still show through, in
    either order (before: the one added first wrote its depth at every pixel it drew, and the
    other's rays stopped there)."""
    front = _two_volumes("front", stock=True).max(-1) > 0.02
    back = _two_volumes("back", stock=True).max(-1) > 0.02
    overlap = front & back
    assert overlap.sum() > 50, "the volumes do not overlap in view: the test scene is wrong"
    blue = {}
    for order in ("front first", "back first"):
        image = _two_volumes(order)
        drawn = image.max(-1) > 0.02
        blue[order] = float(image[..., 2][overlap].mean())
        print(f"{order}: {drawn.sum()} drawn pixels ({(drawn & (front | back)).sum()} of the "
              f"stock union {(front | back).sum()}), blue in the overlap {blue[order]:.3f}")
        assert (drawn & (front | back)).sum() > 0.9 * (front | back).sum()
    back_alone = float(_two_volumes("back")[..., 2][overlap].mean())
    print(f"blue volume alone in the overlap: {back_alone:.3f}")
    for order, value in blue.items():
        assert value > 0.5 * back_alone, f"{order}: the red volume hides the blue one"


def _wavelet_values() -> np.ndarray:
    from vtkmodules.vtkImagingCore import vtkRTAnalyticSource
    source = vtkRTAnalyticSource()
    source.SetWholeExtent(-12, 12, -12, 12, -12, 12)
    source.Update()
    return numpy_support.vtk_to_numpy(source.GetOutput().GetPointData().GetScalars())


def _offset_scene(values: np.ndarray, lo: float, hi: float, stock: bool = False) -> Any:
    """A 25^3 volume of ``values`` (any dtype) whose transfer function ramps opacity over
    [lo, hi]: (window, mapper, keep)."""
    from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction
    from vtkmodules.vtkRenderingCore import vtkColorTransferFunction, vtkVolumeProperty
    from vtkmodules.vtkRenderingVolume import vtkFixedPointVolumeRayCastMapper

    image = vtkImageData()
    image.SetDimensions(25, 25, 25)
    array = numpy_support.numpy_to_vtk(np.ascontiguousarray(values), deep=True)
    array.SetName("scalars")
    image.GetPointData().SetScalars(array)
    colour = vtkColorTransferFunction()
    colour.AddRGBPoint(lo, 0.2, 0.4, 1.0)
    colour.AddRGBPoint(hi, 1.0, 0.9, 0.5)
    opacity = vtkPiecewiseFunction()
    opacity.AddPoint(lo, 0.0)
    opacity.AddPoint(lo + 0.5 * (hi - lo), 0.0)
    opacity.AddPoint(hi, 0.9)
    prop = vtkVolumeProperty()
    prop.SetColor(colour)
    prop.SetScalarOpacity(opacity)
    prop.SetInterpolationTypeToLinear()
    mapper = vtkFixedPointVolumeRayCastMapper() if stock else vtkPathTracedVolumeMapper()
    if not stock:
        mapper.ConvergeStillRendersOff()
        mapper.DenoiseOff()
        mapper.SetSeed(2)
    mapper.SetInputData(image)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    renderer = vtkRenderer()
    renderer.AddVolume(volume)
    renderer.ResetCamera()
    renderer.GetActiveCamera().Azimuth(30)
    window = vtkRenderWindow()
    window.SetMultiSamples(0)
    window.SetOffScreenRendering(1)
    window.SetSize(48, 48)
    window.AddRenderer(renderer)
    return window, mapper, (image, prop, volume, renderer)


def _silhouette(values: np.ndarray, lo: float, hi: float, stock: bool = False) -> np.ndarray:
    window, mapper, keep = _offset_scene(values, lo, hi, stock)
    for _ in range(1 if stock else 8):
        window.Render()
    image = _screenshot(window).max(-1) > 0.05
    _WINDOWS.append(window)
    del keep
    return image


def test_offset_and_tiny_range_scalars_render_like_the_plain_ones() -> None:
    """Scalars float cannot hold as they are (1e10 + [37, 277] rounds to a few values, 1e300
    overflows, a 1e-36 range underflows) give the plain volume's silhouette, as the stock
    mapper does; before, they rendered blank, blocky, as a saturated box, or as 'NaN or
    infinite'."""
    base = _wavelet_values().astype(np.float64)
    lo, hi = 37.0, 277.0
    plain = _silhouette(base, lo, hi)
    stock = _silhouette(base, lo, hi, stock=True)
    print(f"plain: {plain.sum()} pixels drawn, agreement with the stock mapper "
          f"{(plain == stock).mean():.3f}")
    assert plain.sum() > 100 and (plain == stock).mean() > 0.9
    cases = {"int64 1e10 +": ((base + 1e10).astype(np.int64), 1e10 + lo, 1e10 + hi),
             "double 1e9 +": (base + 1e9, 1e9 + lo, 1e9 + hi),
             "double 1e300 +": (base * 1e285 + 1e300, 1e285 * lo + 1e300, 1e285 * hi + 1e300),
             "double x 1e-38": (base * 1e-38, lo * 1e-38, hi * 1e-38),
             "float x 1e-36": ((base * 1e-36).astype(np.float32), lo * 1e-36, hi * 1e-36)}
    for name, (values, a, b) in cases.items():
        got = _silhouette(values, a, b)
        agree = (got == plain).mean()
        print(f"{name}: {got.sum()} pixels drawn (plain {plain.sum()}), agreement {agree:.3f}")
        assert agree > 0.97, f"{name}: the silhouette differs from the plain volume's ({agree:.3f})"
