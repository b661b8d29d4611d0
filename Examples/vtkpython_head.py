#!/usr/bin/env python3
"""Path-trace the head CT with a plain VTK pipeline in Python and save PNG + EXR passes.

vtkXMLImageDataReader -> vtkPathTracedVolumeMapper (head two-band preset) -> offscreen render
of N accumulated 1-spp frames -> the render passes as numpy arrays (vtk_to_numpy) -> the window
as PNG and every pass in one multi-channel EXR (vtkPTVEXRPassWriter).

    PYTHONPATH=build/python xvfb-run -a .venv/bin/python Examples/vtkpython_head.py --size 256

Needs the built package (``build/python`` on PYTHONPATH; found automatically in a build tree
named ``build``), the head CT (``scripts/fetch_datasets.py head``) and an X display: Debian's VTK
renders offscreen on an X server too. ``xvfb-run -a`` gives one (drop it where $DISPLAY is set);
without any, the script stops with exit status 2 and that advice rather than abort in X.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Dict

import numpy as np

REPO = Path(__file__).resolve().parents[1]


def _import_package() -> None:
    """Make ``pathtracedvolume`` importable: appended, never prepended, to sys.path."""
    try:
        import pathtracedvolume.vtkPTVRendering  # noqa: F401
    except ImportError:
        sys.path.append(str(REPO / "build" / "python"))


_import_package()

from pathtracedvolume import datasets, presets  # noqa: E402
from pathtracedvolume.headless import headless_window, require_display  # noqa: E402
from pathtracedvolume.vtkPTVFilters import vtkPTVEXRPassWriter  # noqa: E402
from pathtracedvolume.vtkPTVRendering import vtkPathTracedVolumeMapper  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkImageData  # noqa: E402
from vtkmodules.vtkIOImage import vtkPNGWriter  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLImageDataReader  # noqa: E402
from vtkmodules.vtkRenderingCore import (vtkRenderer, vtkRenderWindow,  # noqa: E402
                                         vtkVolume, vtkVolumeProperty,
                                         vtkWindowToImageFilter)
import vtkmodules.vtkRenderingOpenGL2  # noqa: E402,F401 (the OpenGL render window)

PRESET = "Head Two-Band (paper)"


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--input", type=Path, default=None,
                        help="a .vti volume (default: the head CT from the dataset cache)")
    parser.add_argument("--preset", default=PRESET, help="transfer-function preset name")
    parser.add_argument("--size", type=int, default=160, help="image width and height (160)")
    parser.add_argument("--frames", type=int, default=16,
                        help="1-spp frames to accumulate (16)")
    parser.add_argument("--no-denoise", action="store_true", help="show the noisy running mean")
    parser.add_argument("--output-dir", type=Path, default=Path("out"),
                        help="where head_vtk.png and head_vtk.exr go (out/)")
    parser.add_argument("--check", action="store_true",
                        help="verify the outputs (exist, finite, not blank); exit 1 if not")
    return parser.parse_args()


def render(args: argparse.Namespace) -> Dict[str, np.ndarray]:
    path = args.input or datasets.dataset_path("head")
    reader = vtkXMLImageDataReader()
    reader.SetFileName(str(path))

    prop = vtkVolumeProperty()
    presets.apply_preset(presets.find_preset(args.preset), prop)
    prop.SetInterpolationTypeToLinear()

    mapper = vtkPathTracedVolumeMapper()
    mapper.SetInputConnection(reader.GetOutputPort())
    mapper.GetExpertOptions().SetMaximumAccumulatedFrames(args.frames)
    mapper.SetDenoise(not args.no_denoise)
    mapper.GetExpertOptions().ScatterPassesOn()  # keep the Scatter* passes too: every pass
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)

    renderer = vtkRenderer()
    renderer.AddVolume(volume)
    renderer.SetBackground(0.32, 0.34, 0.43)  # also the environment light's colour
    camera = renderer.GetActiveCamera()
    camera.SetPosition(0, -1, 0)  # front view: the CT's y axis runs front to back, z up
    camera.SetFocalPoint(0, 0, 0)
    camera.SetViewUp(0, 0, 1)
    renderer.ResetCamera()

    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(args.size, args.size)
    window.AddRenderer(renderer)
    for _ in range(args.frames):
        window.Render()
    print(f"{mapper.GetAccumulatedFrames()} frames on {mapper.GetActiveBackend()}, "
          f"denoiser: {mapper.GetDenoiserStatus()}")

    args.output_dir.mkdir(parents=True, exist_ok=True)
    png, exr = args.output_dir / "head_vtk.png", args.output_dir / "head_vtk.exr"
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    grab.Update()
    png_writer = vtkPNGWriter()
    png_writer.SetFileName(str(png))
    png_writer.SetInputConnection(grab.GetOutputPort())
    png_writer.Write()

    # Every pass as one image (one array per pass), as numpy, and as one EXR.
    passes = vtkImageData()
    if not mapper.GetPasses(passes):
        raise RuntimeError("the mapper has no passes (nothing rendered?)")
    width, height, _ = passes.GetDimensions()
    arrays: Dict[str, np.ndarray] = {}
    pd = passes.GetPointData()
    for i in range(pd.GetNumberOfArrays()):
        values = vtk_to_numpy(pd.GetArray(i))
        arrays[pd.GetArrayName(i)] = values.reshape(height, width, -1)  # row 0 = bottom
    exr_writer = vtkPTVEXRPassWriter()
    exr_writer.SetFileName(str(exr))
    exr_writer.SetInputData(passes)
    if not exr_writer.Write():
        raise RuntimeError(f"could not write {exr}")
    for name, values in arrays.items():
        print(f"  {name:16s} {values.shape}  mean {values.mean():.4g}")
    print(f"wrote {png} and {exr}")
    window.Finalize()
    return arrays


def check_outputs(args: argparse.Namespace, arrays: Dict[str, np.ndarray]) -> bool:
    from pathtracedvolume.vtkPTVFilters import vtkPTVEXRPassReader
    from vtkmodules.vtkIOImage import vtkPNGReader

    ok = True
    png = vtkPNGReader()
    png.SetFileName(str(args.output_dir / "head_vtk.png"))
    png.Update()
    pixels = vtk_to_numpy(png.GetOutput().GetPointData().GetScalars())
    if pixels.size == 0 or np.ptp(pixels[:, :3]) < 30:
        print("FAILED: the PNG is missing or blank")
        ok = False
    reader = vtkPTVEXRPassReader()
    reader.SetFileName(str(args.output_dir / "head_vtk.exr"))
    reader.Update()
    pd = reader.GetOutput().GetPointData()
    names = {pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())}
    if names != set(arrays):
        print(f"FAILED: the EXR holds {sorted(names)}, expected {sorted(arrays)}")
        ok = False
    for name in names & set(arrays):
        values = vtk_to_numpy(pd.GetArray(name))
        if not np.isfinite(values).all():
            print(f"FAILED: pass {name} is not finite")
            ok = False
    if arrays["Alpha"].max() <= 0:
        print("FAILED: the volume covers no pixel")
        ok = False
    print("check:", "ok" if ok else "FAILED")
    return ok


def main() -> int:
    args = parse_args()
    # Before any window opens (creating one opens nothing): without X, stop with exit status 2.
    require_display([sys.executable, *sys.argv],
                    headless=headless_window(vtkRenderWindow().GetClassName()))
    arrays = render(args)
    return 0 if not args.check or check_outputs(args, arrays) else 1


if __name__ == "__main__":
    sys.exit(main())
