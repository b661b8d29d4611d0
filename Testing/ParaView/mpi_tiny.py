"""pvbatch script run under MPI by mpi_distributed.py: a 2 x 2 x 2-point Wavelet shown as "Path
Traced Volume" with ReplicateVolumeLimit 0 on more ranks than ParaView can split it into. A rank
without a piece would not render and leave the others waiting in a collective; the
representation replicates such a volume instead. Renders 2 frames and writes ``--out``/info.json
(accumulated frames, NumberOfSamplingRanks, VTK messages). Only rank 0 runs this script."""
import argparse
import json
import os
import sys

from paraview.simple import *  # noqa: F401,F403 (pvbatch convention)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ptvpvtest  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", required=True)
args = parser.parse_args()

vtk_messages = ptvpvtest.collect_vtk_messages()
LoadPlugin(os.environ["PTV_PLUGIN"], remote=False, ns=globals())
wavelet = Wavelet(WholeExtent=[0, 1, 0, 1, 0, 1])
view = CreateView("RenderView")
view.ViewSize = [32, 32]
display = Show(wavelet, view)
display.SetRepresentationType("Path Traced Volume")
ColorBy(display, ("POINTS", "RTData"))
display.ReplicateVolumeLimit = 0
display.ConvergeStillRenders = 0
display.Denoise = 0
Render(view)
Render(view)
display.UpdatePropertyInformation()
os.makedirs(args.out, exist_ok=True)
with open(os.path.join(args.out, "info.json"), "w") as f:
    json.dump({"frames": display.GetProperty("AccumulatedFrames").GetData(),
               "sampling_ranks": display.GetProperty("NumberOfSamplingRanks").GetData(),
               "messages": list(vtk_messages)}, f)
