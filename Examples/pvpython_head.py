"""Path-trace the head CT in ParaView from Python and save a PNG and the EXR render passes.

Loads the PathTracedVolume plugin, opens the head CT, switches its representation to
"Path Traced Volume", applies the "Head Two-Band (paper)" preset, renders (a still render:
until the estimated quality reaches StillQuality or N frames are accumulated; the view's
streaming passes refine further only if it stopped short of both), saves a screenshot,
writes every render pass to one EXR with the representation's Write Passes command, and reads the
passes back as numpy arrays.

    xvfb-run -a pvpython --force-offscreen-rendering Examples/pvpython_head.py --size 256

Also runs with pvbatch. Needs the built plugin (found in ``build/`` or given with --plugin or
$PTV_PLUGIN), the head CT (``scripts/fetch_datasets.py head``) and an X display: Debian's ParaView
has no EGL or OSMesa context, so even ``--force-offscreen-rendering`` renders on an X server.
``xvfb-run -a`` gives one (drop it where $DISPLAY is set); without any, ParaView crashes in its
first render (after a warning that representations "require remote rendering"), so the script
stops before that with exit status 2 and this advice.
"""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path
from typing import Dict

import numpy as np

REPO = Path(__file__).resolve().parents[1]
PLUGIN_DEFAULT = (REPO / "build" / "lib" / "paraview-5.11" / "plugins" / "PathTracedVolume"
                  / "PathTracedVolume.so")
# Appended, never prepended: the compiled package (EXR reader) and the pure-Python helpers.
for folder in (REPO / "build" / "python", REPO / "Python"):
    if str(folder) not in sys.path:
        sys.path.append(str(folder))

PRESET = "Head Two-Band (paper)"


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--plugin", default=os.environ.get("PTV_PLUGIN", str(PLUGIN_DEFAULT)),
                        help="PathTracedVolume.so (default: $PTV_PLUGIN or the build tree's)")
    parser.add_argument("--input", type=Path, default=None,
                        help="a .vti volume (default: the head CT from the dataset cache)")
    parser.add_argument("--size", type=int, default=160, help="view width and height (160)")
    parser.add_argument("--frames", type=int, default=16,
                        help="1-spp frames to accumulate (16)")
    parser.add_argument("--output-dir", type=Path, default=Path("out"),
                        help="where head_pv.png and head_pv.exr go (out/)")
    parser.add_argument("--check", action="store_true",
                        help="verify the outputs (exist, finite, not blank); exit 1 if not")
    return parser.parse_args()


def run(args: argparse.Namespace) -> Dict[str, np.ndarray]:
    from paraview import simple
    from pathtracedvolume import datasets

    simple.LoadPlugin(args.plugin, remote=False, ns=globals())
    path = args.input or datasets.dataset_path("head")
    reader = simple.XMLImageDataReader(FileName=[str(path)])

    view = simple.CreateView("RenderView")
    view.ViewSize = [args.size, args.size]
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = [0.32, 0.34, 0.43]  # also the environment light's colour

    display = simple.Show(reader, view)
    display.SetRepresentationType("Path Traced Volume")
    simple.ColorBy(display, ("POINTS", "ImageScalars"))
    display.MaximumAccumulatedFrames = args.frames
    # Write Passes writes the passes the mapper keeps; the Scatter* ones need the expert option
    # ScatterPasses, which the representation does not show: set it on the representation's
    # mapper (in this builtin session the client-side object is the one that renders).
    import pathtracedvolume.vtkPTVParaViewViews  # noqa: F401 (wraps the representation's class)
    representation = display.GetClientSideObject().GetActiveRepresentation()
    representation.GetPathTracedMapper().GetExpertOptions().ScatterPassesOn()

    # The preset's colour and opacity (ImportPresets once per user profile; ApplyPreset by name).
    lut = simple.GetColorTransferFunction("ImageScalars")
    pwf = simple.GetOpacityTransferFunction("ImageScalars")
    if not lut.ApplyPreset(PRESET, True):
        simple.ImportPresets(str(REPO / "Data" / "TransferFunctions" / "head.json"))
        lut.ApplyPreset(PRESET, True)
    pwf.ApplyPreset(PRESET, True)

    camera = view.GetActiveCamera()
    camera.SetPosition(0, -1, 0)  # front view
    camera.SetFocalPoint(0, 0, 0)
    camera.SetViewUp(0, 0, 1)
    view.ResetCamera()

    simple.Render(view)  # a still render: traces until the estimate reaches StillQuality
    while view.SMProxy.StreamingUpdate(True):  # refinement up to MaximumAccumulatedFrames
        pass                                    # (nothing more once the still has converged)
    display.UpdatePropertyInformation()
    print("frames %s on %s, denoiser: %s" % (display.GetProperty("AccumulatedFrames").GetData(),
                                             display.GetProperty("ActiveBackend").GetData(),
                                             display.GetProperty("DenoiserStatus").GetData()))

    args.output_dir.mkdir(parents=True, exist_ok=True)
    png = args.output_dir / "head_pv.png"
    exr = args.output_dir / "head_pv.exr"
    simple.SaveScreenshot(str(png), view, ImageResolution=[args.size, args.size],
                          TransparentBackground=0)
    display.PassesFileName = str(exr.resolve())
    display.SMProxy.InvokeCommand("WritePasses")  # the "Write Passes" button
    print(f"wrote {png} and {exr}")
    arrays = read_passes(exr)
    simple.Delete(display)
    simple.Delete(view)
    simple.Delete(reader)
    return arrays


def read_passes(exr: Path) -> Dict[str, np.ndarray]:
    """The passes of an EXR as numpy arrays (height, width, components), row 0 = bottom."""
    from pathtracedvolume.vtkPTVFilters import vtkPTVEXRPassReader
    from vtkmodules.util.numpy_support import vtk_to_numpy

    reader = vtkPTVEXRPassReader()
    reader.SetFileName(str(exr))
    reader.Update()
    image = reader.GetOutput()
    width, height, _ = image.GetDimensions()
    pd = image.GetPointData()
    arrays = {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)).reshape(height, width, -1)
              for i in range(pd.GetNumberOfArrays())}
    for name, values in arrays.items():
        print(f"  {name:16s} {values.shape}  mean {values.mean():.4g}")
    return arrays


def check_outputs(args: argparse.Namespace, arrays: Dict[str, np.ndarray]) -> bool:
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOImage import vtkPNGReader

    ok = True
    png = vtkPNGReader()
    png.SetFileName(str(args.output_dir / "head_pv.png"))
    png.Update()
    pixels = vtk_to_numpy(png.GetOutput().GetPointData().GetScalars())
    if pixels is None or pixels.size == 0 or np.ptp(pixels[:, :3]) < 30:
        print("FAILED: the PNG is missing or blank")
        ok = False
    expected = {"Radiance", "Alpha", "Albedo", "Depth", "Position", "Normal", "ScatterDepth",
                "ScatterPosition", "ScatterNormal", "Denoised"}
    if not expected <= set(arrays):
        print(f"FAILED: the EXR holds {sorted(arrays)}")
        ok = False
    for name, values in arrays.items():
        if values.size != args.size * args.size * values.shape[-1] or not np.isfinite(values).all():
            print(f"FAILED: pass {name}: wrong size or not finite")
            ok = False
    if "Alpha" in arrays and arrays["Alpha"].max() <= 0:
        print("FAILED: the volume covers no pixel")
        ok = False
    print("check:", "ok" if ok else "FAILED")
    return ok


def require_display() -> None:
    """Exit with status 2 and the command to run instead where ParaView cannot render."""
    from paraview.modules.vtkRemotingCore import vtkProcessModule, vtkRemotingCoreConfiguration
    from paraview.modules.vtkRemotingViews import vtkPVRenderingCapabilitiesInformation as caps
    from pathtracedvolume import headless

    if vtkProcessModule.GetProcessType() == vtkProcessModule.PROCESS_BATCH:
        interpreter = ["pvbatch"]
    else:
        interpreter = ["pvpython"]
        if vtkRemotingCoreConfiguration.GetInstance().GetForceOffscreenRendering():
            interpreter.append("--force-offscreen-rendering")
    egl_or_osmesa = bool(caps.GetLocalCapabilities() & caps.HEADLESS_RENDERING)
    headless.require_display([*interpreter, *sys.argv], headless=egl_or_osmesa)


def main() -> int:
    args = parse_args()
    require_display()  # before the first view: without X, ParaView 5.11 crashes in it
    arrays = run(args)
    return 0 if not args.check or check_outputs(args, arrays) else 1


if __name__ == "__main__":
    sys.exit(main())
