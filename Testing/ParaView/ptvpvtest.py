"""Shared by the ParaView test scripts (pvbatch, pvpython, the GUI): checks, VTK message
collection, PNG reading and the front view of the head CT.

Import it after putting this folder on sys.path::

    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import ptvpvtest
"""
from __future__ import annotations

from typing import List

import numpy as np


class Checks:
    """``check(ok, what)`` prints ``ok``/``FAILED`` lines and keeps the failures."""

    def __init__(self) -> None:
        self.failures: List[str] = []
        self.lines: List[str] = []

    def say(self, line: str) -> None:
        print(line, flush=True)
        self.lines.append(line)

    def __call__(self, ok: bool, what: str) -> None:
        self.say(("ok     " if ok else "FAILED ") + what)
        if not ok:
            self.failures.append(what)


def collect_vtk_messages() -> List[str]:
    """A list that receives the text of every VTK error and warning from now on. pvbatch logs
    them as "ERR|" / "WARN|" (vtkLogger), which ctest's "ERROR: In" expression does not match;
    the output window passes the full text to observers, so tests collect and judge them."""
    from vtkmodules.util.misc import calldata_type
    from vtkmodules.util.vtkConstants import VTK_STRING
    from vtkmodules.vtkCommonCore import vtkCommand, vtkOutputWindow

    messages: List[str] = []

    @calldata_type(VTK_STRING)
    def collect(caller, event, text):
        messages.append(text)

    window = vtkOutputWindow.GetInstance()
    window.AddObserver(vtkCommand.ErrorEvent, collect)
    window.AddObserver(vtkCommand.WarningEvent, collect)
    collect_vtk_messages.keep = collect  # the observer must outlive this call
    return messages


def read_png(path: str) -> np.ndarray:
    """The PNG's RGB as an (H, W, 3) float64 array in 0..255, bottom row first."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOImage import vtkPNGReader

    png = vtkPNGReader()
    png.SetFileName(path)
    png.Update()
    image = png.GetOutput()
    w, h, _ = image.GetDimensions()
    pixels = vtk_to_numpy(image.GetPointData().GetScalars()).astype(np.float64)
    return pixels.reshape(h, w, -1)[..., :3]


def head_scene(preset: str = "Head Two-Band (paper)", size=None):
    """The head CT (``$PTV_CACHE_DIR/data/head.vti``) shown as "Path Traced Volume" in a new
    render view (no axes, the fixed background [0.32, 0.34, 0.43], which is also the
    environment light), coloured by ImageScalars with ``preset`` (colour and opacity, imported
    from Data/TransferFunctions/head.json), front view; returns (reader, view, display)."""
    import os

    from paraview import simple

    reader = simple.XMLImageDataReader(
        FileName=[os.path.join(os.environ["PTV_CACHE_DIR"], "data", "head.vti")])
    view = simple.CreateView("RenderView")
    if size is not None:
        view.ViewSize = list(size)
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = [0.32, 0.34, 0.43]
    display = simple.Show(reader, view)
    display.SetRepresentationType("Path Traced Volume")
    simple.ColorBy(display, ("POINTS", "ImageScalars"))
    simple.ImportPresets(os.path.join(os.environ["PTV_SOURCE_DIR"], "Data", "TransferFunctions",
                                      "head.json"))
    simple.GetColorTransferFunction("ImageScalars").ApplyPreset(preset, True)
    simple.GetOpacityTransferFunction("ImageScalars").ApplyPreset(preset, True)
    front_view(view)
    return reader, view, display


def front_view(view) -> None:
    """The head CT's front view (its y axis runs front to back, z up), reset to fit."""
    camera = view.GetActiveCamera()
    camera.SetPosition(0, -1, 0)
    camera.SetFocalPoint(0, 0, 0)
    camera.SetViewUp(0, 0, 1)
    view.ResetCamera()
