"""One scene set-up for the scripts, benchmarks, training data and examples.

A dataset (:mod:`.datasets`) with a transfer-function preset (:mod:`.presets`) under
``vtkPathTracedVolumeMapper`` (or VTK's ``vtkFixedPointVolumeRayCastMapper``, ``mapper="stock"``)
in an offscreen window, the project's camera convention, and render passes as NumPy arrays.

The camera convention (:func:`place_camera`): position (0, -1, 0), focal point (0, 0, 0), view-up
(0, 0, 1) -- the CT datasets' y axis runs front to back and z runs up, so this looks at the face
-- then ``Azimuth``, ``Elevation``, ``OrthogonalizeViewUp``, ``ResetCamera`` and a ``Dolly``
(> 1 = closer).

Images are NumPy arrays of shape (H, W, C), float32, in VTK's row order (bottom row first), as
the mapper's passes and ``vtkPTVDenoiser``'s images are. Needs the compiled package
(``PYTHONPATH=<build>/python``) and, for rendering, a display (Xvfb).
"""
from __future__ import annotations

from typing import Any, Callable, List, Mapping, Optional, Sequence, Tuple

import numpy as np

#: The background, which the path tracer also uses as its environment light: ParaView's default.
BACKGROUND = (0.32, 0.34, 0.43)


def load_dataset(name: str) -> Any:
    """The dataset's ``.vti`` (:func:`pathtracedvolume.datasets.dataset_path`) as an updated
    ``vtkImageData``."""
    from vtkmodules.vtkIOXML import vtkXMLImageDataReader

    from .datasets import dataset_path

    reader = vtkXMLImageDataReader()
    reader.SetFileName(str(dataset_path(name)))
    reader.Update()
    return reader.GetOutput()


def paper_preset(dataset: str) -> dict:
    """The dataset's ``"<Dataset> Two-Band (paper)"`` preset."""
    from .presets import find_preset

    return find_preset(f"{dataset.capitalize()} Two-Band (paper)")


def volume_property(preset: Mapping[str, Any], shade: bool = True) -> Any:
    """A ``vtkVolumeProperty`` with the preset's functions, linear interpolation and shading."""
    from vtkmodules.vtkRenderingCore import vtkVolumeProperty

    from .presets import apply_preset

    prop = vtkVolumeProperty()
    apply_preset(preset, prop)
    prop.SetShade(int(shade))
    prop.SetInterpolationTypeToLinear()
    return prop


def place_camera(renderer: Any, azimuth: float = 0.0, elevation: float = 0.0,
                 dolly: float = 1.0) -> Any:
    """Sets the renderer's active camera by the project's convention (module docstring) to fit
    the visible props; returns the camera."""
    camera = renderer.GetActiveCamera()
    camera.SetPosition(0, -1, 0)
    camera.SetFocalPoint(0, 0, 0)
    camera.SetViewUp(0, 0, 1)
    camera.Azimuth(float(azimuth))
    camera.Elevation(float(elevation))
    camera.OrthogonalizeViewUp()
    renderer.ResetCamera()
    camera.Dolly(float(dolly))
    renderer.ResetCameraClippingRange()
    return camera


def get_pass(mapper: Any, name: str) -> np.ndarray:
    """``mapper.GetPass(name)`` as (H, W, C) float32, bottom row first."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonDataModel import vtkImageData

    image = vtkImageData()
    if not mapper.GetPass(name, image):
        raise RuntimeError(f"the mapper has no pass {name!r}")
    w, h, _ = image.GetDimensions()
    return np.array(vtk_to_numpy(image.GetPointData().GetArray(name)),
                    dtype=np.float32).reshape(h, w, -1)


def numpy_to_image(array: np.ndarray, name: str) -> Any:
    """(H, W[, C]) float32, bottom row first -> a W x H x 1 ``vtkImageData`` whose active scalars
    are a point array ``name`` (what ``vtkPTVDenoiser.SetImage`` takes)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData

    a = np.asarray(array, dtype=np.float32)
    if a.ndim == 2:
        a = a[:, :, None]
    h, w, c = a.shape
    image = vtkImageData()
    image.SetDimensions(w, h, 1)
    flat = np.ascontiguousarray(a.reshape(h * w, c) if c > 1 else a.reshape(h * w))
    vtk_array = numpy_to_vtk(flat, deep=True)
    vtk_array.SetName(name)
    image.GetPointData().AddArray(vtk_array)
    image.GetPointData().SetActiveScalars(name)
    return image


class Scene:
    """A volume under one mapper in an offscreen render window.

    ``volume`` is a ``vtkImageData`` or an algorithm (its output port is connected); ``prop`` a
    ``vtkVolumeProperty``. The path-traced mapper starts with ``Denoise`` as given, still renders
    not converged (each :meth:`render` traces one frame) and ``threads`` CPU threads (0: every
    core); :attr:`mapper` is there for any other setting. The camera is placed by
    :func:`place_camera` with ``azimuth`` / ``elevation``; :meth:`view` moves it.
    """

    def __init__(self, volume: Any, prop: Any, size: Tuple[int, int] = (256, 256),
                 azimuth: float = 0.0, elevation: float = 0.0, mapper: str = "pathtraced",
                 denoise: bool = True, threads: int = 0,
                 background: Sequence[float] = BACKGROUND) -> None:
        from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow, vtkVolume
        import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (OpenGL factories)
        import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401

        if mapper == "pathtraced":
            from . import vtkPathTracedVolumeMapper
            self.mapper = vtkPathTracedVolumeMapper()
            self.mapper.ConvergeStillRendersOff()  # one traced frame per render()
            self.mapper.SetDenoise(bool(denoise))
            self.mapper.SetNumberOfThreads(int(threads))
        elif mapper == "stock":
            from vtkmodules.vtkRenderingVolume import vtkFixedPointVolumeRayCastMapper
            self.mapper = vtkFixedPointVolumeRayCastMapper()
        else:
            raise ValueError(f"mapper must be 'pathtraced' or 'stock', not {mapper!r}")
        self.path_traced = mapper == "pathtraced"
        if hasattr(volume, "GetOutputPort"):
            self.mapper.SetInputConnection(volume.GetOutputPort())
        else:
            self.mapper.SetInputData(volume)
        self.size = (int(size[0]), int(size[1]))
        self.prop = prop
        self.volume = vtkVolume()
        self.volume.SetMapper(self.mapper)
        self.volume.SetProperty(prop)
        self.renderer = vtkRenderer()
        self.renderer.AddVolume(self.volume)
        self.renderer.SetBackground(*background)  # also the path tracer's environment light
        self.window = vtkRenderWindow()
        self.window.SetOffScreenRendering(1)
        self.window.SetSize(*self.size)
        self.window.AddRenderer(self.renderer)
        self.view(azimuth, elevation)

    @classmethod
    def of_dataset(cls, dataset: str, size: Tuple[int, int] = (256, 256),
                   preset: Optional[str] = None, **kwargs: Any) -> "Scene":
        """A scene of a bundled dataset with ``preset`` (default: its paper preset)."""
        from .presets import find_preset

        chosen = find_preset(preset) if preset else paper_preset(dataset)
        return cls(load_dataset(dataset), volume_property(chosen), size, **kwargs)

    def view(self, azimuth: float = 0.0, elevation: float = 0.0, dolly: float = 1.0) -> Any:
        """Places the camera (:func:`place_camera`); returns it."""
        return place_camera(self.renderer, azimuth, elevation, dolly)

    def render(self, frames: int = 1,
               on_frame: Optional[Callable[[int], None]] = None) -> List[float]:
        """Renders ``frames`` times (the path tracer: one 1-spp frame each); returns each
        render's milliseconds (the path tracer's trace time, else the wall time);
        ``on_frame(k)`` after render k (1-based)."""
        import time

        times = []
        for k in range(1, int(frames) + 1):
            start = time.perf_counter()
            self.window.Render()
            wall = 1000.0 * (time.perf_counter() - start)
            stats = self.mapper.GetStatistics() if self.path_traced else None
            times.append(float(stats.GetLastTraceTime()) if stats is not None else wall)
            if on_frame is not None:
                on_frame(k)
        return times

    def get_pass(self, name: str = "Radiance") -> np.ndarray:
        """Pass ``name`` of the current accumulation (:func:`get_pass`)."""
        return get_pass(self.mapper, name)

    def screenshot(self) -> Any:
        """The window's RGB image as a ``vtkImageData`` (what a PNG writer takes), as the last
        :meth:`render` left it: no render of its own (it would trace another frame)."""
        from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter

        grab = vtkWindowToImageFilter()
        grab.SetInput(self.window)
        grab.ShouldRerenderOff()
        grab.ReadFrontBufferOff()  # offscreen: the frame is in the back buffer
        grab.Update()
        return grab.GetOutput()
