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
    window.Finalize()
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
    for shift, colour in (((0.0, 0.0, 12.0), (1.0, 0.3, 0.2)), ((8.0, 6.0, -12.0), (0.2, 0.4, 1.0))):
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
    window.Finalize()
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
