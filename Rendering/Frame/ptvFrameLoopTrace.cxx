// FrameLoop, one frame's trace (the CPU or CUDA tracer, the edge samples) and its accumulation
// (the running mean, or the reprojected history when only the camera moved); ptvFrameLoop.h
// lists the stages.
#include "ptvFrameLoop.h"

#include "ptvEdgeSamples.h"

#include "ptvKernelDispatch.h"

#include "vtkImageData.h"
#include "vtkRenderer.h"
#include "vtkTimerLog.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <string>

namespace ptv
{
namespace
{
double Now()
{
  return vtkTimerLog::GetUniversalTime();
}
}

//------------------------------------------------------------------------------
void FrameLoop::Trace(const FrameRequest& request, FrameMessages& messages)
{
  const double start = Now();
  // A first frame without history to carry is the mean itself: it is traced into the old
  // mean's storage, so that one set of traced passes is kept (process 0 keeps the frame).
  this->FrameIsMean = this->AccumulatedFrames == 0 && !this->ViewMoved &&
    !this->History.HasHistory() && this->Parallel.Shows();
  if (this->FrameIsMean)
  {
    this->Frame.TakeTracedPasses(this->Accumulated);
  }
  this->Frame.Resize(this->Params.Camera.Width, this->Params.Camera.Height);
  const int samples = request.Scene.SamplesPerFrame;
  const unsigned int firstSample = this->Parallel.FirstSample(this->SampleFrames, samples);
  // Edge samples when the frame is denoised (process 0 decides) or asked for.
  const int edgeSamples = this->Parallel.Agree(
    request.ComputeEdgeSamples || (request.Denoise && this->Parallel.Shows()) ? request.EdgeSamples
                                                                                : 1);
  std::string problem;
  this->Params.PieceStream = this->Parallel.PieceStream();
  const PieceView piece = this->Inputs.GetPieceView(this->Params);
  bool keep = false;
  if (this->Parallel.IsDistributed() && this->Parallel.IsParallel() && samples > 1)
  {
    // Pieces are composited sample by sample: a pixel's coverage in one piece and what lies
    // behind it in the next are correlated through the shared camera ray, so the "over" of two
    // means of several samples would not be the mean of the samples' "over".
    this->Sample.Resize(this->Params.Camera.Width, this->Params.Camera.Height);
    for (int s = 0; s < samples; ++s)
    {
      this->Tracer.Trace(this->Params, this->Inputs.GetVolumeVersion(),
        firstSample + static_cast<unsigned int>(s), 1, request.Threads, UsePortableKernels(false),
        request.Backend, this->Sample, problem);
      if (this->Parallel.GatherFrame(this->Sample, kTracedPassCount, piece, request.Threads))
      {
        this->Frame.Resize(this->Sample.GetWidth(), this->Sample.GetHeight());
        this->Frame.Accumulate(this->Sample, s + 1); // the frame's running mean
        keep = true;
      }
    }
  }
  else
  {
    this->Tracer.Trace(this->Params, this->Inputs.GetVolumeVersion(), firstSample, samples,
      request.Threads, UsePortableKernels(false), request.Backend, this->Frame, problem);
    // Several processes: process 0 gets the whole frame (their mean, or their pieces
    // composited) and accumulates it; the others only trace.
    keep = this->Parallel.GatherFrame(this->Frame, kTracedPassCount, piece, request.Threads);
  }
  this->TraceEdges(request, firstSample, edgeSamples, keep, piece);
  if (!problem.empty() && problem != this->BackendProblem)
  {
    messages.emplace_back(true, problem);
  }
  this->BackendProblem = problem;
  ++this->SampleFrames;
  ++this->AccumulatedFrames;
  ++this->LastRenderFrames;
  if (keep)
  {
    this->AccumulateFrame(request);
  }
  this->ViewMoved = false;
  this->CombinedValid = false;
  this->DenoisedValid = false;
  this->LastRenderTraced = true;
  this->LastTraceTime += 1000.0 * (Now() - start);
}

//------------------------------------------------------------------------------
void FrameLoop::TraceEdges(const FrameRequest& request, unsigned int firstSample,
  int edgeSamples, bool keep, const PieceView& piece)
{
  this->LastEdgeFraction = 0.0;
  this->EdgePixels.clear();
  this->EdgeSampleCount = 1;
  const bool pieces = this->Parallel.IsDistributed() && this->Parallel.IsParallel();
  if (edgeSamples < 2 || !(keep || pieces))
  {
    return;
  }
  const int samples = request.Scene.SamplesPerFrame;
  if (keep)
  {
    FindEdgePixels(this->Frame.Data(PassCoverage), this->Frame.GetWidth(),
      this->Frame.GetHeight(), request.Threads, this->EdgePixels);
  }
  if (pieces)
  {
    // Every piece traces the extra samples through its part of the same rays (the same
    // jitter, march offset and stream; its own events, PieceStream), and the processes composite
    // them sample by sample, like the frame's own samples (Trace): the edge pixels of the
    // composited frame, which process 0 found, get the samples one process would trace.
    this->Parallel.Agree(this->EdgePixels);
    if (this->EdgePixels.empty())
    {
      return;
    }
    TraceEdgeSampleList(this->Params, firstSample, samples, edgeSamples, this->EdgePixels,
      request.Threads, UsePortableKernels(false), this->EdgeList);
    if (!this->Parallel.GatherFrame(this->EdgeList, kTracedPassCount, piece, request.Threads))
    {
      this->EdgePixels.clear(); // the others' lists have been used
      return;
    }
  }
  this->SwapEdgeFirstHits(this->Frame, true); // keep the frame samples' own first hits
  if (pieces)
  {
    MergeEdgeSamples(
      this->EdgeList, samples, edgeSamples, this->EdgePixels, request.Threads, this->Frame);
  }
  else
  {
    // With the whole volume process 0 traces them for the samples of every process, which are
    // one block from its own first sample on (Ranks::FirstSample): N processes give the frame
    // of one with N times the samples.
    TraceEdgeSamples(this->Params, firstSample, samples * this->Parallel.GetSize(), edgeSamples,
      this->EdgePixels, request.Threads, UsePortableKernels(false), this->Frame);
  }
  this->EdgeSampleCount = std::min(edgeSamples, kMaxEdgeSamples);
  this->LastEdgeFraction = static_cast<double>(this->EdgePixels.size()) /
    (static_cast<double>(this->Frame.GetWidth()) * this->Frame.GetHeight());
}

//------------------------------------------------------------------------------
void FrameLoop::AccumulateFrame(const FrameRequest& request)
{
  const int width = this->Frame.GetWidth();
  const int height = this->Frame.GetHeight();
  // Without history the accumulated Radiance pass is the shown image's mean M, bit for bit:
  // the statistics read it there (before this frame joins it) instead of keeping their own.
  const bool plain = !this->ViewMoved && !this->History.HasHistory();
  this->Converging.AddFrame(this->Frame.Data(PassRadiance), width, height,
    this->AccumulatedFrames, request.Threads, plain,
    this->FrameIsMean ? nullptr : this->Accumulated.Data(PassRadiance));
  if (this->FrameIsMean)
  {
    this->Accumulated.TakeTracedPasses(this->Frame); // count 1: the frame is the mean
  }
  else if (this->ViewMoved)
  {
    const double reprojectStart = Now();
    this->Accumulated.Resize(width, height);
    this->ReprojectFrame(request);
    this->LastReprojectionTime += 1000.0 * (Now() - reprojectStart);
  }
  else if (this->History.HasHistory())
  {
    this->Accumulated.Resize(width, height);
    this->History.Accumulate(
      this->Accumulated, this->Frame, this->AccumulatedFrames, request.Threads);
  }
  else
  {
    this->Accumulated.Resize(width, height);
    this->Accumulated.Accumulate(this->Frame, this->AccumulatedFrames);
  }
  this->AccumulatedCamera = this->Params.Camera;
  this->LastViewFrames = this->AccumulatedFrames;
  this->CountPassesValid = false; // HistoryLength, SampleRatio: written when read
}

//------------------------------------------------------------------------------
void FrameLoop::FillCountPasses()
{
  PassBuffers& acc = this->Accumulated;
  const std::size_t pixels =
    static_cast<std::size_t>(acc.GetWidth()) * static_cast<std::size_t>(acc.GetHeight());
  if (this->CountPassesValid || pixels == 0)
  {
    return;
  }
  this->History.WriteCounts(
    acc.Ensure(PassHistoryLength), static_cast<int>(pixels), this->AccumulatedFrames);
  // The last frame's edge pixels hold EdgeSamples times a plain pixel's samples.
  float* ratio = acc.Ensure(PassSampleRatio);
  std::fill(ratio, ratio + pixels, 1.f);
  for (const std::uint32_t pixel : this->EdgePixels)
  {
    ratio[pixel] = static_cast<float>(this->EdgeSampleCount);
  }
  this->CountPassesValid = true;
}

//------------------------------------------------------------------------------
void FrameLoop::ReprojectFrame(const FrameRequest& request)
{
  // The new frame's point and albedo tests read its first hit: an edge pixel's mean of
  // several samples (a hit and a miss: a depth between the surface and the far plane) is not
  // one, so they read the frame sample's own for the time of the step.
  this->SwapEdgeFirstHits(this->Frame, false);
  // Edge pixels keep their new samples alone: their history lags behind the silhouette, which
  // moves with the view (docs/decisions.md).
  this->History.Reproject(this->AccumulatedCamera, this->Params.Camera, this->Params.StepWorld,
    request.MaximumHistory, this->LastViewFrames, this->Accumulated, this->Frame,
    request.Threads, this->EdgePixels.data(), this->EdgePixels.size());
  this->SwapEdgeFirstHits(this->Accumulated, false); // the frame's passes are there now
}

//------------------------------------------------------------------------------
void FrameLoop::SwapEdgeFirstHits(PassBuffers& frame, bool save)
{
  const std::size_t count = this->EdgePixels.size();
  if (save)
  {
    this->EdgeFirstHits.resize(4 * count);
  }
  if (this->EdgeFirstHits.size() != 4 * count)
  {
    return;
  }
  float* depth = frame.Data(PassDepth);
  float* albedo = frame.Data(PassAlbedo);
  for (std::size_t e = 0; e < count; ++e)
  {
    const std::size_t i = this->EdgePixels[e];
    float* kept = this->EdgeFirstHits.data() + 4 * e;
    if (save)
    {
      kept[0] = depth[i];
      std::copy(albedo + 3 * i, albedo + 3 * i + 3, kept + 1);
      continue;
    }
    std::swap(kept[0], depth[i]);
    for (int c = 0; c < 3; ++c)
    {
      std::swap(kept[1 + c], albedo[3 * i + c]);
    }
  }
}
}
