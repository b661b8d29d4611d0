"""ParaView GUI test: progressive refinement while the GUI is idle, with default settings.

Run as ``paraview --dr --script=gui_progressive_refinement.py`` under Xvfb with ``PTV_PLUGIN``,
``PTV_CACHE_DIR``, ``PTV_TEST_TEMP`` and ``PYTHONPATH`` (<build>/python) set (Testing/CMakeLists.txt
does, test PTV.ParaView.gui_progressive_refinement), or connected to a pvserver with
``--server-url=cs://127.0.0.1:<port>`` (gui_clientserver.sh, test
PTV.ParaView.gui_progressive_refinement_clientserver; the view then renders on the server). The
script itself never renders while it waits:

1. loads the plugin in the GUI (its auto-start component pqPTVProgressiveRefinement starts),
   shows the head CT as "Path Traced Volume" with MaximumAccumulatedFrames=8 and returns, so
   that the GUI's event loop runs; "Enable Streaming" stays off (default settings, --dr);
2. a repeating timer of the view's Qt interactor (it does not render) polls the progress where
   the view renders (vtkPTVRepresentationInformation gathered from the render server's root; in
   a builtin session the information properties must agree): the GUI must reach 8 frames on its
   own, then stop rendering (no render for 1.5 s after that);
3. an "interaction": the camera turns and the view renders once (as the GUI does on a mouse
   drag): the accumulation restarts (1 or 2 frames after that render, fewer than 8: that still
   render traces one frame, because the plugin marks the GUI's representations
   InteractiveSession, so a still render outside a capture never freezes the window) and again
   reaches 8 on its own, then stops;
4. writes PASS or FAIL lines to $PTV_TEST_TEMP/gui_progressive_refinement.txt, prints them and
   exits (os._exit: the GUI has no Python quit command), with status 0 on success.
A global deadline (150 s) fails the test if the accumulation never completes. Without the
component (ProgressiveRefinement=0, which it respects) the GUI's own startup renders reach 4
frames and the test fails at the deadline.
"""
import os
import sys
import time

from paraview.simple import *  # noqa: F401,F403 (ParaView convention)
from vtkmodules.vtkCommonCore import vtkCommand

FRAMES = 8
DEADLINE_S = 150.0
QUIET_S = 1.5  # no render for this long after completion = "stopped"
TEMP = os.environ.get("PTV_TEST_TEMP", ".")
os.makedirs(TEMP, exist_ok=True)
RESULT = os.path.join(TEMP, "gui_progressive_refinement.txt")
HEAD = os.path.join(os.environ["PTV_CACHE_DIR"], "data", "head.vti")

from paraview import servermanager  # noqa: E402

REMOTE = servermanager.ActiveConnection.IsRemote()
if REMOTE:  # paraview --server-url=cs://host:port: the server needs the plugin too
    LoadPlugin(os.environ["PTV_PLUGIN"], remote=True, ns=globals())
LoadPlugin(os.environ["PTV_PLUGIN"], remote=False, ns=globals())
from pathtracedvolume.vtkPTVParaViewViews import vtkPTVRepresentationInformation  # noqa: E402
reader = XMLImageDataReader(FileName=[HEAD])
view = GetActiveViewOrCreate("RenderView")
GetLayout().PreviewMode = [320, 320]  # a small view: a few seconds per pass on 2 cores
display = Show(reader, view)
display.SetRepresentationType("Path Traced Volume")
ColorBy(display, ("POINTS", "ImageScalars"))
display.DenoiserUseNetwork = 0
if REMOTE:
    view.RemoteRenderThreshold = 0  # render on the server
if os.environ.get("PTV_SERVER_SPLIT") == "1":
    display.ReplicateVolumeLimit = 0  # a multi-rank server splits the volume across its ranks
display.MaximumAccumulatedFrames = FRAMES
camera = view.GetActiveCamera()
camera.SetPosition(0, -1, 0)
camera.SetFocalPoint(0, 0, 0)
camera.SetViewUp(0, 0, 1)
view.ResetCamera()

lines = []
state = {"phase": "refine-1", "renders": 0, "last_render": time.time(), "t0": time.time(),
         "done_at": None, "phase_renders": 0}


def log(text):
    text = "%6.2fs %s" % (time.time() - state["t0"], text)
    lines.append(text)
    print(text, flush=True)


def finish(ok):
    lines.append("PASS" if ok else "FAIL")
    with open(RESULT, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("PASS" if ok else "FAIL", flush=True)
    sys.stdout.flush()
    os._exit(0 if ok else 1)


def on_render(caller, event):
    state["renders"] += 1
    state["phase_renders"] += 1
    state["last_render"] = time.time()


view.SMProxy.AddObserver(vtkCommand.EndEvent, on_render)


def progress():
    """(AccumulatedFrames, LastRenderTraced) where the view renders: gathered from the render
    server's root (the GUI itself in a builtin session); in a builtin session the information
    properties must agree."""
    gathered = vtkPTVRepresentationInformation()
    servermanager.ActiveConnection.Session.GatherInformation(
        servermanager.vtkPVSession.RENDER_SERVER_ROOT, gathered, display.SMProxy.GetGlobalID())
    frames, traced = gathered.GetAccumulatedFrames(), int(gathered.GetLastRenderTraced())
    if not REMOTE:
        display.UpdatePropertyInformation()
        props = (display.GetProperty("AccumulatedFrames").GetData(),
                 display.GetProperty("LastRenderTraced").GetData())
        if props != (frames, traced):
            log("information properties %r != gathered %r" % (props, (frames, traced)))
            finish(False)
    return frames, traced


def on_timer(caller, event):
    now = time.time()
    if now - state["t0"] > DEADLINE_S:
        frames, traced = progress()
        log("deadline: phase %s, AccumulatedFrames=%d LastRenderTraced=%d renders=%d"
            % (state["phase"], frames, traced, state["renders"]))
        finish(False)
    frames, traced = progress()
    phase = state["phase"]
    if phase.startswith("refine"):
        if frames >= FRAMES:
            if state["done_at"] is None:
                state["done_at"] = now
                log("%s: AccumulatedFrames=%d after %d renders, none by this script"
                    % (phase, frames, state["phase_renders"]))
            elif now - state["last_render"] >= QUIET_S:
                log("%s: no render for %.1f s after completion: stopped"
                    % (phase, now - state["last_render"]))
                if phase == "refine-1":
                    # An "interaction": the camera turns and the view renders once.
                    state["phase"] = "refine-2"
                    state["done_at"] = None
                    state["phase_renders"] = 0
                    camera.Azimuth(20)
                    Render(view)
                    frames, traced = progress()
                    log("interaction: one render, AccumulatedFrames=%d" % frames)
                    if not 1 <= frames < FRAMES:
                        log("the accumulation did not restart")
                        finish(False)
                    state["phase_renders"] = 0
                else:
                    finish(True)


interactor = view.GetInteractor()
if interactor is None:
    log("the view has no interactor")
    finish(False)
interactor.AddObserver(vtkCommand.TimerEvent, on_timer)
interactor.CreateRepeatingTimer(100)
log("setup done (%s session; GUI idle from now on; Enable Streaming is off)"
    % ("client/server" if REMOTE else "builtin"))
