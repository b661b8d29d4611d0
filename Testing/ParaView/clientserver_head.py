"""pvpython test: the "Path Traced Volume" representation through a real pvserver on 127.0.0.1.

Run as ``pvpython --force-offscreen-rendering clientserver_head.py`` with ``PTV_PLUGIN``,
``PTV_SOURCE_DIR``, ``PTV_CACHE_DIR`` and ``PTV_TEST_TEMP`` set and a display (ctest runs it
under Xvfb; pvserver renders offscreen on the same display). Not a ``test_*.py``: pvbatch cannot
connect to a server, so Testing/CMakeLists.txt registers this file with pvpython.

1. builtin session: the head CT, "Head Two-Band (paper)", 8 accumulated frames at 160x160,
   fixed-guide denoiser; screenshot, WritePasses (PassesFileName) -> builtin.exr;
2. pvserver --server-port=<free port> --hostname=127.0.0.1 --force-offscreen-rendering, then
   Connect('127.0.0.1', port); the plugin loaded on the server (remote=True) and the client
   (remote=False); the same scene (the representation requires remote rendering); checks:
   progressive refinement through streaming passes; the screenshot is not blank and matches the
   builtin one (the tolerance absorbs image delivery); WritePasses runs on the server and its EXR
   holds bit-identical passes (the tracer is deterministic; this also shows that the server lit
   the volume with the view's background as environment, as the builtin session does).
   The information-only properties (AccumulatedFrames, LastRenderTraced, ActiveBackend,
   DenoiserStatus) are checked in the builtin session only: ParaView pulls information-only
   properties of a proxy that also lives on the client from the client's object, which never
   renders in client/server mode, so there they read 0 / "none" (printed, not checked). In both
   sessions vtkPTVRepresentationInformation, gathered from the render server's root
   (Session.GatherInformation), must report the 8 frames, CPU or CUDA and the fixed guide;
3. the server is stopped (also on failure, from ``finally``) and its log must hold no error.
With ``PTV_SERVER_RANKS`` = N > 1 the server is ``mpirun -np N pvserver``: the ranks trace each
frame together (the volume is replicated): the builtin session uses SamplesPerFrame N and the
server's passes must still equal its passes (rank r traces sample block f N + r).
With ``PTV_SERVER_SPLIT`` = 1 as well, the server splits the volume (ReplicateVolumeLimit 0):
each rank traces its piece and rank 0 composites them. The builtin session then uses
SamplesPerFrame 1 and both EdgeSamples 1 (the edge pixels would follow the pieces' own events):
the pieces trace its camera rays and samples, so the first-hit passes (Depth,
Position, Normal, Albedo) equal the builtin ones (to float rounding, at 99.9 % of the pixels),
while the events are the pieces' own random numbers: the Radiance's mean agrees within 2 % and
the screenshot within a noise-sized mean difference.
Exits non-zero on any failed check; prints PASS at the end.
"""
from __future__ import annotations

import os
import socket
import subprocess
import sys
import threading
import time
from typing import List, Optional

import numpy as np

from paraview.simple import *  # noqa: F401,F403 (pvpython convention)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ptvpvtest  # noqa: E402

PLUGIN = os.environ["PTV_PLUGIN"]
SOURCE_DIR = os.environ["PTV_SOURCE_DIR"]
HEAD = os.path.join(os.environ["PTV_CACHE_DIR"], "data", "head.vti")
TEMP = os.path.join(os.environ.get("PTV_TEST_TEMP", "."), "clientserver")
os.makedirs(TEMP, exist_ok=True)
PRESET = "Head Two-Band (paper)"
SIZE = [160, 160]
FRAMES = 8
# Mean |diff| (0..255) allowed between the builtin and the remote screenshot.
MAX_MEAN_DIFF = 1.0
SERVER_RANKS = int(os.environ.get("PTV_SERVER_RANKS", "1"))
SPLIT = SERVER_RANKS > 1 and os.environ.get("PTV_SERVER_SPLIT", "0") == "1"
if SERVER_RANKS > 1:
    TEMP = os.path.join(TEMP, "ranks%d%s" % (SERVER_RANKS, "_split" if SPLIT else ""))
    os.makedirs(TEMP, exist_ok=True)
if SPLIT:
    MAX_MEAN_DIFF = 3.0  # the pieces' own events: 8 spp of other noise, denoised

check = ptvpvtest.Checks()
failures: List[str] = check.failures


def free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def build_scene(name: str, remote: bool):
    """The head as "Path Traced Volume" in a new view; returns (view, display)."""
    reader = XMLImageDataReader(FileName=[HEAD])
    view = CreateView("RenderView")
    view.ViewSize = SIZE
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = [0.32, 0.34, 0.43]
    if remote:
        view.RemoteRenderThreshold = 0  # render on the server, where the passes are written
    display = Show(reader, view)
    display.SetRepresentationType("Path Traced Volume")
    ColorBy(display, ("POINTS", "ImageScalars"))
    display.DenoiserUseNetwork = 0
    display.MaximumAccumulatedFrames = FRAMES
    # N server ranks trace a block of samples each per frame: the builtin session traces N.
    # Split, they trace the same samples, each through its piece.
    display.SamplesPerFrame = 1 if remote or SPLIT else SERVER_RANKS
    if remote and SPLIT:
        display.ReplicateVolumeLimit = 0
    if SPLIT:
        # Without edge samples on either side: which pixels get them follows each frame's
        # opacities (with the fixed guide the events' Alpha), and the pieces draw their events
        # from their own streams, so an edge pixel of one session need not be one of the other,
        # and its first-hit means would then hold other samples. mpi_distributed.py checks the
        # split's edge samples.
        display.EdgeSamples = 1
    display.ConvergeStillRenders = 0  # frames are counted per render (streaming passes)
    display.PassesFileName = os.path.join(TEMP, name + ".exr")
    GetColorTransferFunction("ImageScalars").ApplyPreset(PRESET, True)
    GetOpacityTransferFunction("ImageScalars").ApplyPreset(PRESET, True)
    ptvpvtest.front_view(view)
    return view, display


def info(display, name: str):
    display.UpdatePropertyInformation()
    return display.GetProperty(name).GetData()


def gather_progress(display):
    """vtkPTVRepresentationInformation gathered from the render server's root (the process
    that renders; the builtin session's own in builtin mode)."""
    from paraview import servermanager
    from pathtracedvolume.vtkPTVParaViewViews import vtkPTVRepresentationInformation
    gathered = vtkPTVRepresentationInformation()
    servermanager.ActiveConnection.Session.GatherInformation(
        servermanager.vtkPVSession.RENDER_SERVER_ROOT, gathered, display.SMProxy.GetGlobalID())
    return gathered


def render_frames(view, display, name: str, remote: bool) -> np.ndarray:
    """Render until converged (progressive refinement through the view's streaming passes, as
    the GUI does), save a screenshot, write the passes; returns the screenshot."""
    Render(view)
    passes = 0
    while view.SMProxy.StreamingUpdate(True) and passes < 4 * FRAMES:
        passes += 1
    print("%s: %d streaming renders after the first" % (name, passes))
    check(0 < passes < FRAMES, "%s: progressive refinement renders, then stops" % name)
    frames = info(display, "AccumulatedFrames")
    traced = info(display, "LastRenderTraced")
    backend = info(display, "ActiveBackend")
    status = info(display, "DenoiserStatus")
    print("%s information properties: AccumulatedFrames=%r LastRenderTraced=%r "
          "ActiveBackend=%r DenoiserStatus=%r" % (name, frames, traced, backend, status))
    if not remote:
        check(frames == FRAMES, "%s: AccumulatedFrames=%d" % (name, FRAMES))
        check(backend in ("CPU", "CUDA"), "%s: ActiveBackend is CPU or CUDA" % name)
        check(str(status).startswith("fixed guide"),
              "%s: DenoiserStatus names the fixed guide" % name)
    # Where the view renders (the server in client/server mode), any session.
    gathered = gather_progress(display)
    print("%s gathered from the render server: Found=%r AccumulatedFrames=%d "
          "MaximumAccumulatedFrames=%d NeedsRefinement=%r ActiveBackend=%r DenoiserStatus=%r "
          "LastTraceTime=%.1f ms" % (name, gathered.GetFound(), gathered.GetAccumulatedFrames(),
                                      gathered.GetMaximumAccumulatedFrames(),
                                      gathered.GetNeedsRefinement(), gathered.GetActiveBackend(),
                                      gathered.GetDenoiserStatus(), gathered.GetLastTraceTime()))
    check(gathered.GetFound(), "%s: the gathered information found the representation" % name)
    check(gathered.GetAccumulatedFrames() == FRAMES and not gathered.GetNeedsRefinement(),
          "%s: gathered AccumulatedFrames=%d, refinement complete" % (name, FRAMES))
    check(gathered.GetActiveBackend() in ("CPU", "CUDA"),
          "%s: gathered ActiveBackend is CPU or CUDA" % name)
    check(gathered.GetDenoiserStatus().startswith("fixed guide"),
          "%s: gathered DenoiserStatus names the fixed guide" % name)
    png = os.path.join(TEMP, name + ".png")
    SaveScreenshot(png, view, ImageResolution=SIZE, TransparentBackground=0)
    exr = display.PassesFileName
    if os.path.exists(exr):
        os.remove(exr)
    # The command goes to the server without a reply: wait for the file.
    display.SMProxy.InvokeCommand("WritePasses")
    deadline = time.time() + 60
    while not os.path.exists(exr) and time.time() < deadline:
        time.sleep(0.1)
    check(os.path.exists(exr), "%s: WritePasses wrote %s" % (name, exr))
    # A screenshot with ConvergeStillRenders on converges where the view renders.
    display.ConvergeStillRenders = 1
    display.MaximumAccumulatedFrames = 1024
    SaveScreenshot(os.path.join(TEMP, name + "_still.png"), view, ImageResolution=SIZE,
                   TransparentBackground=0)
    still = gather_progress(display)
    print("%s still screenshot: AccumulatedFrames=%d EstimatedQuality=%.2f StillConverged=%r"
          % (name, still.GetAccumulatedFrames(), still.GetEstimatedQuality(),
             still.GetStillConverged()))
    check(still.GetStillConverged() and still.GetEstimatedQuality() >= 40.0
          and still.GetAccumulatedFrames() > FRAMES,
          "%s: a screenshot converges to StillQuality where the view renders" % name)
    return read_png(png)


read_png = ptvpvtest.read_png


def read_passes(path: str) -> dict:
    from pathtracedvolume.vtkPTVFilters import vtkPTVEXRPassReader
    from vtkmodules.util.numpy_support import vtk_to_numpy
    reader = vtkPTVEXRPassReader()
    reader.SetFileName(path)
    reader.Update()
    pd = reader.GetOutput().GetPointData()
    return {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)).copy()
            for i in range(pd.GetNumberOfArrays())}


def check_split_passes(remote: dict, builtin: dict) -> None:
    """A split volume's composited passes against one process's (see the module comment)."""
    for name in ("Depth", "Position", "Normal", "Albedo"):
        a, b = remote[name], builtin[name]
        scale = max(float(np.abs(b).max()), 1.0)
        off = float(np.mean(np.abs(a - b).reshape(len(a), -1).max(axis=1) > 1e-3 * scale))
        check(off <= 1e-3, "split: first-hit pass %s equals the builtin one (%.3f %% of pixels "
              "differ by > 1e-3 of its range)" % (name, 100 * off))
    mean_remote = float(remote["Radiance"].mean())
    mean_builtin = float(builtin["Radiance"].mean())
    check(abs(mean_remote - mean_builtin) <= 0.02 * mean_builtin,
          "split: mean Radiance %.5f within 2 %% of the builtin %.5f" % (mean_remote, mean_builtin))


class Server:
    """A pvserver child process; its output goes to a log file, watched for the ready line."""

    def __init__(self, port: int, log_path: str) -> None:
        self.port = port
        self.log_path = log_path
        self.lines: List[str] = []
        self.ready = threading.Event()
        command = ["pvserver", "--server-port=%d" % port, "--hostname=127.0.0.1",
                   "--force-offscreen-rendering"]
        if SERVER_RANKS > 1:
            command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np",
                       str(SERVER_RANKS)] + command
        print("starting:", " ".join(command), flush=True)
        # pvpython is itself an MPI singleton: its OMPI_/PMIX_ variables would make mpirun
        # refuse to start (a nested launch).
        env = {k: v for k, v in os.environ.items()
               if not k.startswith(("OMPI_", "PMIX_", "PRTE_", "OPAL_"))}
        self.process = subprocess.Popen(command, stdout=subprocess.PIPE,
                                        stderr=subprocess.STDOUT, text=True,
                                        start_new_session=True, env=env)
        self.thread = threading.Thread(target=self._pump, daemon=True)
        self.thread.start()

    def _pump(self) -> None:
        with open(self.log_path, "w") as log:
            for line in self.process.stdout:
                log.write(line)
                log.flush()
                self.lines.append(line.rstrip("\n"))
                if "Accepting connection" in line:
                    self.ready.set()

    def wait_ready(self, timeout: float = 60.0) -> bool:
        deadline = time.time() + timeout
        while time.time() < deadline:
            if self.ready.wait(0.2):
                return True
            if self.process.poll() is not None:
                return False
        return False

    def stop(self) -> Optional[int]:
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(15)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait(15)
        self.thread.join(5)
        return self.process.returncode


# --- 1. builtin -------------------------------------------------------------------------------
LoadPlugin(PLUGIN, remote=False, ns=globals())
# Presets live in the client's settings: import them once (again would warn about the name).
check(ImportPresets(os.path.join(SOURCE_DIR, "Data", "TransferFunctions", "head.json")),
      "ImportPresets(head.json)")
view, display = build_scene("builtin", remote=False)
builtin_image = render_frames(view, display, "builtin", remote=False)
builtin_passes = read_passes(os.path.join(TEMP, "builtin.exr"))
check(len(builtin_passes) >= 9 and "Radiance" in builtin_passes and "Denoised" in builtin_passes,
      "builtin.exr holds the traced and denoised passes: %s" % sorted(builtin_passes))
Delete(display)
Delete(view)
Disconnect()

# --- 2. client/server -------------------------------------------------------------------------
server = Server(free_port(), os.path.join(TEMP, "pvserver.log"))
try:
    ready = server.wait_ready()
    check(ready, "pvserver is accepting connections on 127.0.0.1:%d" % server.port)
    if ready:
        Connect("127.0.0.1", server.port)
        LoadPlugin(PLUGIN, remote=True, ns=globals())
        LoadPlugin(PLUGIN, remote=False, ns=globals())
        view, display = build_scene("remote", remote=True)
        check("Path Traced Volume" in list(display.GetProperty("Representation").Available),
              "the representation is offered in client/server mode")
        remote_image = render_frames(view, display, "remote", remote=True)
        check(remote_image.max() - remote_image.min() > 50 and remote_image.std() > 5,
              "the remote screenshot is not blank (range %.0f, std %.1f)"
              % (remote_image.max() - remote_image.min(), remote_image.std()))
        diff = np.abs(remote_image - builtin_image)
        print("remote vs builtin screenshot: mean |diff| %.3f/255, max %.0f"
              % (diff.mean(), diff.max()))
        check(diff.mean() <= MAX_MEAN_DIFF, "the remote image matches the builtin one")
        remote_passes = read_passes(os.path.join(TEMP, "remote.exr"))
        check(sorted(remote_passes) == sorted(builtin_passes),
              "remote.exr has the builtin passes")
        if SPLIT:
            check_split_passes(remote_passes, builtin_passes)
        else:
            # The tracer is deterministic: the same 8 frames give the same passes.
            for name in ("Radiance", "Depth", "Normal", "Denoised"):
                if name in remote_passes and name in builtin_passes:
                    d = float(np.abs(remote_passes[name] - builtin_passes[name]).max())
                    check(d < 1e-4, "pass %s: remote == builtin (max |diff| %.3g)" % (name, d))
        Disconnect()
finally:
    code = server.stop()
    print("pvserver stopped (exit code %s)" % code, flush=True)

errors = [line for line in server.lines
          if "ERR|" in line or "ERROR: In" in line or "WARN|" in line or "Warning: In" in line]
for line in errors:
    print("pvserver: " + line)
check(not errors, "pvserver logged no errors or warnings (%d)" % len(errors))

# The client's remote proxies (colour maps, ...) are released at exit, after the server has gone:
# their "Broken pipe" socket errors are expected then and kept off stderr.
from vtkmodules.vtkCommonCore import vtkLogger  # noqa: E402
vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)

if failures:
    print("%d check(s) failed" % len(failures))
    sys.exit(1)
print("PASS")
