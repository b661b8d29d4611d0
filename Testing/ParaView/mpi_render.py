"""pvbatch script run under MPI by test_mpi.py (``mpirun -np N pvbatch mpi_render.py ...``): the head
CT shown as "Path Traced Volume" (two-band preset, front view), ``--frames`` traced frames at
``--size``, then rank 0 writes the passes (EXR, WritePasses) and a screenshot.

Arguments: ``--out DIR`` (passes.exr, screenshot.png, info.json), ``--frames F``,
``--size S``, ``--spp-per-frame K`` (the representation's SamplesPerFrame), ``--replicate-limit
MB`` (ReplicateVolumeLimit; 0: each rank renders its own piece), ``--ghost-layers G``
(GhostLayers of such a piece), ``--seed S``, ``--denoise 0|1``,
``--threads T``, ``--still-budget S``. The view renders at full resolution without FXAA (pvbatch
under MPI would otherwise reduce and smooth the composited image). Same environment as the other
ParaView tests (PTV_PLUGIN, PTV_CACHE_DIR, PYTHONPATH). Only rank 0 runs this script; the other
ranks follow its proxies.
"""
import argparse
import json
import os
import sys
import time

from paraview.simple import *  # noqa: F401,F403 (pvbatch convention)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ptvpvtest  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", required=True)
parser.add_argument("--frames", type=int, default=16)
parser.add_argument("--size", type=int, default=256)
parser.add_argument("--spp-per-frame", type=int, default=1)
parser.add_argument("--replicate-limit", type=float, default=None)
parser.add_argument("--ghost-layers", type=int, default=None,
                    help="GhostLayers of a volume split across ranks (default: the property's)")
parser.add_argument("--seed", type=int, default=None, help="the representation's Seed")
parser.add_argument("--denoise", type=int, default=0)
parser.add_argument("--edge-samples", type=int, default=None,
                    help="the representation's EdgeSamples (default its own)")
parser.add_argument("--threads", type=int, default=0)
parser.add_argument("--still-budget", type=float, default=0.0,
                    help="> 0: still renders converge (StillQuality 60 dB, never reached) for at "
                         "most this many seconds")
args = parser.parse_args()

vtk_messages = ptvpvtest.collect_vtk_messages()
LoadPlugin(os.environ["PTV_PLUGIN"], remote=False, ns=globals())
from vtkmodules.vtkParallelCore import vtkMultiProcessController  # noqa: E402

controller = vtkMultiProcessController.GetGlobalController()
ranks = controller.GetNumberOfProcesses() if controller else 1
os.makedirs(args.out, exist_ok=True)

reader, view, display = ptvpvtest.head_scene(size=[args.size, args.size])
view.UseFXAA = 0
view.StillRenderImageReductionFactor = 1
display.ConvergeStillRenders = 1 if args.still_budget > 0 else 0
if args.still_budget > 0:
    display.StillQuality = 60.0
    display.StillTimeBudget = args.still_budget
    display.MaximumStillFrames = 256
display.ProgressiveRefinement = 0
display.MaximumAccumulatedFrames = 256 if args.still_budget > 0 else args.frames
display.SamplesPerFrame = args.spp_per_frame
display.Denoise = args.denoise
display.NumberOfThreads = args.threads
if args.replicate_limit is not None:
    display.ReplicateVolumeLimit = args.replicate_limit
if args.seed is not None:
    display.Seed = args.seed
if args.edge_samples is not None:
    display.EdgeSamples = args.edge_samples
if args.ghost_layers is not None:
    display.GhostLayers = args.ghost_layers

Render(view)  # the first frame (and the pipeline update)
start = time.perf_counter()
for _ in range(args.frames - 1):
    Render(view)
seconds = time.perf_counter() - start



def frames() -> int:
    display.UpdatePropertyInformation()
    return display.GetProperty("AccumulatedFrames").GetData()


display.PassesFileName = os.path.join(args.out, "passes.exr")
display.SMProxy.InvokeCommand("WritePasses")
before = frames()
SaveScreenshot(os.path.join(args.out, "screenshot.png"), view, ImageResolution=[args.size] * 2)
display.UpdatePropertyInformation()
import pathtracedvolume.vtkPTVRendering  # noqa: E402,F401 (wraps the mapper's class)
mapper = display.GetClientSideObject().GetActiveRepresentation().GetActor().GetMapper()  # rank 0
piece = {"input_extent": list(mapper.GetInput().GetExtent()),
         "piece_extent": list(mapper.GetPieceExtent()),
         "whole_extent": list(mapper.GetWholeExtent()),
         "distributed": bool(mapper.GetDistributedVolume()),
         "edge_fraction": mapper.GetStatistics().GetLastEdgeFraction()}
info = {"ranks": ranks, "rank0": piece, "frames": args.frames, "seconds_after_first": seconds,
        "accumulated_before_screenshot": before, "accumulated_after_screenshot": frames(),
        "sampling_ranks": display.GetProperty("NumberOfSamplingRanks").GetData(),
        "messages": list(vtk_messages)}
with open(os.path.join(args.out, "info.json"), "w") as f:
    json.dump(info, f, indent=1)
print(f"{ranks} ranks: {args.frames} frames, {seconds:.2f} s after the first", flush=True)
