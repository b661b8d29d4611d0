"""Where the volume is, and what clipping and cropping keep, against VTK's own CPU ray caster
(vtkFixedPointVolumeRayCastMapper) on the same scene: the silhouettes agree within a pixel.

Scene: vtkRTAnalyticSource with extent -16..16 (the image's first point is not at its origin,
which the mapper once ignored; cropping uses extent 0..32, because VTK's own conversion of
cropping planes clamps structured indices to 0..dims-1 and is only right for such extents), a
step opacity at 150, 96² pixels, black background. Our silhouette is the Depth pass (first
non-transparent sample) of one frame; the stock one is every pixel the stock mapper drew.

Tolerances (measured, not guessed): ours lies inside the stock silhouette dilated by one pixel;
the stock silhouette is about half a pixel wider everywhere, cut or not (it quantises scalars to
16 bits and samples at other positions), so it lies inside ours dilated by two pixels. Both up
to 1% of the pixels, for boundary pixels a different sample position may flip.
"""
from __future__ import annotations

from typing import Callable, Optional

import numpy as np
from scipy import ndimage

import vtkmodules.util.numpy_support as vtk_numpy
import pathtracedvolume.vtkPTVRendering as ptv

from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction, vtkPlane
from vtkmodules.vtkImagingCore import vtkRTAnalyticSource
from vtkmodules.vtkRenderingCore import (vtkColorTransferFunction, vtkRenderer, vtkRenderWindow,
                                         vtkVolume, vtkVolumeProperty, vtkWindowToImageFilter)
from vtkmodules.vtkRenderingVolume import vtkFixedPointVolumeRayCastMapper
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401

N = 96


class Scene:
    def __init__(self, first: int = -16) -> None:
        self.source = vtkRTAnalyticSource()
        self.source.SetWholeExtent(first, first + 32, first, first + 32, first, first + 32)
        self.source.SetCenter(first + 16, first + 16, first + 16)
        color = vtkColorTransferFunction()
        color.AddRGBPoint(37, 0.2, 0.4, 1.0)
        color.AddRGBPoint(277, 1.0, 0.9, 0.5)
        opacity = vtkPiecewiseFunction()
        opacity.AddPoint(37, 0.0)
        opacity.AddPoint(150, 0.0)
        opacity.AddPoint(151, 0.8)
        opacity.AddPoint(277, 0.8)
        self.prop = vtkVolumeProperty()
        self.prop.SetColor(color)
        self.prop.SetScalarOpacity(opacity)
        self.ours = ptv.vtkPathTracedVolumeMapper()
        self.ours.ConvergeStillRendersOff()  # frame by frame
        self.ours.DenoiseOff()
        self.stock = vtkFixedPointVolumeRayCastMapper()
        self.stock.SetAutoAdjustSampleDistances(0)
        for mapper in (self.ours, self.stock):
            mapper.SetInputConnection(self.source.GetOutputPort())
        self.volume = vtkVolume()
        self.volume.SetProperty(self.prop)
        self.renderer = vtkRenderer()
        self.renderer.AddVolume(self.volume)
        self.renderer.SetBackground(0, 0, 0)
        self.window = vtkRenderWindow()
        self.window.SetOffScreenRendering(1)
        self.window.SetSize(N, N)
        self.window.AddRenderer(self.renderer)
        self.volume.SetMapper(self.stock)
        camera = self.renderer.GetActiveCamera()
        camera.Azimuth(25)
        camera.Elevation(15)
        self.renderer.ResetCamera()

    def masks(self, configure: Optional[Callable] = None):
        """(ours, stock) silhouettes after ``configure(mapper)`` on both mappers."""
        out = []
        for mapper in (self.ours, self.stock):
            if configure:
                configure(mapper)
            self.volume.SetMapper(mapper)
            self.window.Render()
            if mapper is self.ours:
                image = vtkImageData()
                assert mapper.GetPass("Depth", image)
                depth = vtk_numpy.vtk_to_numpy(image.GetPointData().GetArray("Depth"))
                far = self.renderer.GetActiveCamera().GetClippingRange()[1]
                out.append(depth.reshape(N, N) < 0.999 * far)
            else:
                grab = vtkWindowToImageFilter()
                grab.SetInput(self.window)
                grab.ReadFrontBufferOff()
                grab.Update()
                rgb = vtk_numpy.vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars())
                out.append(rgb.reshape(N, N, -1)[..., :3].max(axis=2) > 0)
        return out[0], out[1]


def assert_same_silhouette(ours: np.ndarray, stock: np.ndarray, what: str) -> None:
    assert ours.sum() > 50 and stock.sum() > 50, f"{what}: nothing visible"
    outside_ours = (ours & ~ndimage.binary_dilation(stock)).sum()
    outside_stock = (stock & ~ndimage.binary_dilation(ours, iterations=2)).sum()
    print(f"{what}: ours {ours.sum()} px, stock {stock.sum()} px, ours outside stock+1px "
          f"{outside_ours}, stock outside ours+2px {outside_stock}")
    assert outside_ours <= 0.01 * ours.sum(), what
    assert outside_stock <= 0.01 * stock.sum(), what


def test_volume_position_matches_stock() -> None:
    scene = Scene()
    ours, stock = scene.masks()
    assert_same_silhouette(ours, stock, "no cut (extent -16..16)")


def test_clipping_plane_matches_stock() -> None:
    scene = Scene()
    full, _ = scene.masks()
    plane = vtkPlane()
    plane.SetOrigin(2, 0, 0)
    plane.SetNormal(1, 0.3, 0)

    def clip(mapper) -> None:
        mapper.RemoveAllClippingPlanes()
        mapper.AddClippingPlane(plane)
    ours, stock = scene.masks(clip)
    assert ours.sum() < 0.8 * full.sum(), "the plane removes part of the volume"
    assert_same_silhouette(ours, stock, "clipping plane")


def test_cropping_matches_stock() -> None:
    scene = Scene(first=0)
    full, _ = scene.masks()
    for flags, name in ((0x0002000, "sub-volume"), (0x2ebfeba, "fence"),
                        (0x1ebfeb, "inverted cross")):
        def crop(mapper, flags=flags) -> None:
            mapper.CroppingOn()
            mapper.SetCroppingRegionPlanes(7, 23, 8, 26, 10, 22)
            mapper.SetCroppingRegionFlags(flags)
        ours, stock = scene.masks(crop)
        assert ours.sum() < full.sum(), f"{name}: cropping removes part of the volume"
        assert_same_silhouette(ours, stock, f"cropping {name}")
