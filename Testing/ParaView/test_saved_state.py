"""pvbatch test (issue #61): a saved state (.pvsm) restores the "Path Traced Volume"
representation and its properties.

The head CT is shown as "Path Traced Volume" with non-default values of visible and advanced
properties (SamplesPerFrame, StillQuality, StillTimeBudget, Denoise, DisplayPass, LightIntensity,
Scattering, EdgeSamples, MaximumHistory) and the state is saved; a second pvbatch process, as a
user's next session, loads the plugin (ParaView's rule: a state names its plugins' proxies, so
the plugin loads first) and the state. The restored representation must be "Path Traced Volume"
with every value, and must render. Run by ctest (PTV.ParaView.test_saved_state) with PTV_PLUGIN, PTV_SOURCE_DIR,
PTV_CACHE_DIR and PTV_TEST_TEMP set.
"""
import os
import sys

from paraview.simple import *  # noqa: F401,F403 (pvbatch convention)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ptvpvtest  # noqa: E402

import shutil
import subprocess

vtk_messages = ptvpvtest.collect_vtk_messages()
LoadPlugin(os.environ["PTV_PLUGIN"], remote=False, ns=globals())
TEMP = os.environ.get("PTV_TEST_TEMP", ".")
os.makedirs(TEMP, exist_ok=True)
STATE = os.path.join(TEMP, "saved_state.pvsm")
check = ptvpvtest.Checks()

SETTINGS = {"SamplesPerFrame": 2, "StillQuality": 35.0, "StillTimeBudget": 12.0, "Denoise": 0,
            "DisplayPass": "Albedo", "LightIntensity": 1.5, "Scattering": 0, "EdgeSamples": 1,
            "MaximumHistory": 3}


def save() -> None:
    """The first session: the scene, the settings, the state file; then the second session."""
    reader, view, display = ptvpvtest.head_scene(size=[96, 96])
    for name, value in SETTINGS.items():
        setattr(display, name, value)
    Render(view)
    SaveState(STATE)
    check(os.path.getsize(STATE) > 0, "the state is saved")
    done = subprocess.run([shutil.which("pvbatch") or "pvbatch", "--force-offscreen-rendering",
                           os.path.abspath(__file__), "--load", STATE],
                          capture_output=True, text=True, timeout=600)
    print(done.stdout, done.stderr, flush=True)
    check(done.returncode == 0 and "PASS" in done.stdout, "a new session restores the state")


def load(path: str) -> None:
    """The second session: the plugin, then the state; the representation and its values."""
    LoadState(path)
    view = GetActiveViewOrCreate("RenderView")
    sources = list(GetSources().values())
    check(len(sources) == 1, f"one source restored ({len(sources)})")
    restored = GetDisplayProperties(sources[0], view) if sources else None
    check(restored is not None and restored.Representation == "Path Traced Volume",
          "the representation is Path Traced Volume")
    for name, value in SETTINGS.items():
        got = getattr(restored, name) if restored is not None else None
        same = (abs(float(got) - float(value)) < 1e-9 if isinstance(value, (int, float))
                else got == value)
        check(same, f"{name} restored ({got!r}, saved {value!r})")
    if restored is not None:
        view.ViewSize = [96, 96]
        shot = os.path.join(TEMP, "saved_state.png")
        SaveScreenshot(shot, view, ImageResolution=[96, 96])
        check(float(ptvpvtest.read_png(shot).std()) > 1.0, "the restored view renders the volume")


if "--load" in sys.argv:
    load(sys.argv[sys.argv.index("--load") + 1])
else:
    save()
check(not vtk_messages, f"no VTK error or warning: {vtk_messages[:3]}")
if check.failures:
    print(f"FAIL: {len(check.failures)} check(s)")
    sys.exit(1)
print("PASS")
