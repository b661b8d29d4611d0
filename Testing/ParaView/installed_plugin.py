"""Run by install_plugin.sh: the plugin loaded from an installed, moved prefix, in pvbatch
(LoadPlugin with the installed file) and in the ParaView GUI (PTV_GUI=1: loaded by name through
--plugin-search-paths=<plugin folder> --plugins=PathTracedVolume).

The source tree's Data/ and the build tree's copy are covered by empty folders and PTV_DATA_DIR is
unset, so the model, the presets and the Python package can only come from the plugin folder
($PTV_PLUGIN_DIR). Checks: the plugin loads; the Python package imports from the plugin folder;
the default model and preset folder are the plugin folder's; the head CT renders as "Path Traced Volume" with the default settings and the
denoiser status names the GuideNet (not the fixed-guide fallback). Prints PASS at the end (the
GUI writes its lines to $PTV_RESULT and exits with os._exit: it has no Python quit).
"""
import os
import sys

from paraview.simple import *  # noqa: F401,F403 (pvbatch convention)

# The GUI's --script defines no __file__: install_plugin.sh passes the script's path.
sys.path.insert(0, os.path.dirname(os.path.abspath(os.environ["PTV_SCRIPT"])))
import ptvpvtest  # noqa: E402

PLUGIN_DIR = os.path.realpath(os.environ["PTV_PLUGIN_DIR"])
GUI = os.environ.get("PTV_GUI") == "1"
check = ptvpvtest.Checks()


def finish():
    failures = check.failures
    check.say("FAIL: %d check(s)" % len(failures) if failures else "PASS")
    if GUI:
        with open(os.environ["PTV_RESULT"], "w") as f:
            f.write("\n".join(check.lines) + "\n")
        os._exit(1 if failures else 0)
    if failures:
        sys.exit(1)


def main():
    for hidden in os.environ["PTV_HIDDEN_DATA"].split(":"):
        check(os.path.isdir(hidden) and not os.listdir(hidden), "%s is hidden (empty)" % hidden)

    if not GUI:
        LoadPlugin(os.path.join(PLUGIN_DIR, "PathTracedVolume.so"), remote=False, ns=globals())
    sys.path.insert(0, os.path.join(PLUGIN_DIR, "python"))
    import pathtracedvolume
    from pathtracedvolume import vtkPTVRendering
    from pathtracedvolume.presets import find_preset, presets_dir

    package = os.path.realpath(os.path.dirname(pathtracedvolume.__file__))
    check(package.startswith(PLUGIN_DIR), "the Python package is the plugin folder's: %s" % package)
    model = vtkPTVRendering.vtkPTVDenoiser.GetDefaultModelFile()
    check(os.path.realpath(model).startswith(PLUGIN_DIR) and os.path.isfile(model),
          "the default model is the plugin folder's: %s" % model)
    presets = vtkPTVRendering.vtkPTVTransferFunctionPreset.GetDefaultPresetDirectory()
    check(os.path.realpath(presets).startswith(PLUGIN_DIR) and os.path.isdir(presets),
          "the preset folder is the plugin folder's: %s" % presets)
    check(str(presets_dir()).startswith(PLUGIN_DIR), "pathtracedvolume.presets reads the same folder")
    preset = find_preset("Head Two-Band (paper)")
    check(bool(preset.get("RGBPoints")), "a shipped preset loads through the Python package")

    reader = XMLImageDataReader(
        FileName=[os.path.join(os.environ["PTV_CACHE_DIR"], "data", "head.vti")])
    view = GetActiveViewOrCreate("RenderView") if GUI else CreateView("RenderView")
    if not GUI:
        view.ViewSize = [96, 96]
    display = Show(reader, view)
    check("Path Traced Volume" in list(display.GetProperty("Representation").Available),
          "'Path Traced Volume' is offered")
    display.SetRepresentationType("Path Traced Volume")
    ColorBy(display, ("POINTS", "ImageScalars"))
    display.StillQuality = 20  # a quick still: this test is about where things load from
    Render(view)
    display.UpdatePropertyInformation()
    status = str(display.GetProperty("DenoiserStatus").GetData())
    frames = display.GetProperty("AccumulatedFrames").GetData()
    check(status.startswith("GuideNet") and PLUGIN_DIR in status,
          "the denoiser runs the installed GuideNet: %r" % status)
    check(frames >= 1, "the view rendered (%d frames)" % frames)


try:
    main()
except Exception:  # the GUI would otherwise stay open: report and exit
    import traceback
    check(False, "exception:\n" + traceback.format_exc())
finish()
