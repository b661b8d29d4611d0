"""ParaView GUI startup script for docs/paraview-gui.png (run by docs/paraview_gui_screenshot.sh).

Loads the PathTracedVolume plugin, opens the head CT, shows it as "Path Traced Volume" with the
"Head Two-Band (paper)" preset, and renders 8 frames (denoised).
Paths come from PTV_PLUGIN and PTV_SOURCE_DIR / PTV_CACHE_DIR (set by the shell script).
"""
import os

from paraview.simple import *  # noqa: F401,F403 (ParaView convention)

SOURCE = os.environ["PTV_SOURCE_DIR"]
LoadPlugin(os.environ["PTV_PLUGIN"], remote=False, ns=globals())
head = XMLImageDataReader(registrationName="head.vti", FileName=[
    os.path.join(os.environ.get("PTV_CACHE_DIR", os.path.join(SOURCE, ".cache")), "data",
                 "head.vti")])
view = GetActiveViewOrCreate("RenderView")
view.OrientationAxesVisibility = 1
display = Show(head, view)
display.SetRepresentationType("Path Traced Volume")
ColorBy(display, ("POINTS", "ImageScalars"))
display.MaximumAccumulatedFrames = 8
ImportPresets(os.path.join(SOURCE, "Data", "TransferFunctions", "head.json"))
GetColorTransferFunction("ImageScalars").ApplyPreset("Head Two-Band (paper)", True)
GetOpacityTransferFunction("ImageScalars").ApplyPreset("Head Two-Band (paper)", True)
camera = view.GetActiveCamera()
camera.SetPosition(0, -1, 0)
camera.SetFocalPoint(0, 0, 0)
camera.SetViewUp(0, 0, 1)
view.ResetCamera()
SetActiveSource(head)
for _ in range(8):
    Render(view)
