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
bool FrameLoop::ReportOnce(const std::string& error, const char* fixedPrefix)
{
  if (error.empty())
  {
    if (this->LastError.rfind(fixedPrefix, 0) == 0)
    {
      this->LastError.clear();
    }
    return false;
  }
  if (error == this->LastError)
  {
    return false;
  }
  this->LastError = error;
  return true;
}

//------------------------------------------------------------------------------
void FrameLoop::ResetAccumulation()
{
  this->AccumulatedFrames = 0;
  this->SampleFrames = 0;
  this->LastViewFrames = 0;
  this->StillConverged = false;
  this->EstimatedQuality = 0.0;
  this->Signature.Clear();
  this->History.Reset();
  this->ViewMoved = false;
}

//------------------------------------------------------------------------------
void FrameLoop::Render(vtkRenderer* ren, vtkVolume* vol, vtkImageData* image,
  vtkDataArray* scalars, bool cellScalars, const FrameRequest& asked, FrameMessages& messages)
{
  // Several processes: the same decisions everywhere (process 0's) and threads shared per host;
  // only process 0 accumulates, denoises (Combine) and draws (below).
  this->Parallel.SetController(asked.Controller);
  this->Parallel.SetDistributed(asked.Distributed);
  FrameRequest request = asked;
  request.Threads = this->Parallel.Threads(asked.Threads);
  request.Still = this->Parallel.Agree(asked.Still) != 0;
  this->LastRenderTraced = false;
  this->LastRenderFrames = 0;
  this->LastTraceTime = 0.0;
  this->LastDenoiseTime = 0.0;
  this->LastReprojectionTime = 0.0;
  auto fail = [this, &messages](const std::string& error)
  {
    if (this->ReportOnce(error))
    {
      messages.emplace_back(true, error);
    }
  };

  // 1. Scene -> kernel inputs. With several processes every one takes part in each collective
  // call below, whether or not its own inputs are usable; any failure stops everyone's frame.
  std::string error;
  vtkIdType nonFinite = 0;
  vtkVolumeProperty* property = vol->GetProperty();
  const bool dependent = property && !property->GetIndependentComponents();
  bool ok = true;
  if (scalars && cellScalars)
  {
    error = "cell scalars are not supported; convert them with vtkCellDataToPointData";
    ok = false;
  }
  ok = ok && this->Inputs.UpdateVolume(image, scalars, dependent, error, nonFinite);
  if (request.Distributed)
  {
    // Every piece classifies over the whole volume's range, is lit by its bounds, and samples
    // its camera rays on the whole volume's grid (its extent: WholeExtent, or the union of the
    // pieces').
    // (min, max) pairs, neutral in the reduction until this piece gives its own.
    const double inf = std::numeric_limits<double>::infinity();
    double ranges[4] = { inf, -inf, inf, -inf };
    double bounds[6] = { inf, -inf, inf, -inf, inf, -inf };
    double extent[6] = { inf, -inf, inf, -inf, inf, -inf };
    if (ok)
    {
      this->Inputs.GetLocalRanges(ranges);
      vol->GetBounds(bounds);
      auto empty = [](const int* e) { return e[0] > e[1] || e[2] > e[3] || e[4] > e[5]; };
      const int* piece = request.Scene.PieceExtent;
      const int* given = request.Scene.WholeExtent;
      const int* own = empty(given) ? (empty(piece) ? image->GetExtent() : piece) : given;
      std::copy(own, own + 6, extent);
    }
    const bool all = this->Parallel.Share(ok, ranges, bounds, extent);
    if (ok && all)
    {
      this->Inputs.SetWholeVolume(ranges, bounds, extent);
    }
    ok = ok && all;
  }
  else if (ok)
  {
    this->Inputs.SetWholeVolume(nullptr, nullptr, nullptr);
  }
  ok = ok &&
    this->Inputs.UpdateTransfer(vol->GetProperty(), request.Scene.EmptySpaceSkipping,
      request.Scene.Iso, request.Scene.IsoValues, error);
  if (ok && nonFinite > 0 && nonFinite != this->LastNonFinite)
  {
    messages.emplace_back(false,
      std::to_string(nonFinite) + " voxels are NaN or infinite; they are rendered transparent.");
  }
  if (ok)
  {
    this->LastNonFinite = nonFinite;
  }

  // The Coverage pass: asked for (CoverageMarch), or read by the denoiser's model (its
  // "coverage" channel). Process 0, which denoises, decides for everyone.
  request.Scene.CoverageMarch =
    this->Parallel.Agree(request.Scene.CoverageMarch ||
      (request.Denoise && this->Parallel.Shows() &&
        this->Denoising.ReadsChannel(this->SettingsOf(request), "coverage"))) != 0;
  // The Footprint pass: asked for (FootprintRays), or for the denoiser, which keeps the
  // pixels it marks empty black (DenoiserFootprint).
  request.Scene.FootprintRays = this->Parallel.Agree(request.Scene.FootprintRays ||
                                  (request.Denoise && request.Denoiser.Footprint &&
                                    this->Parallel.Shows())) != 0;

  int width = 0, height = 0, x0 = 0, y0 = 0;
  ren->GetTiledSizeAndOrigin(&width, &height, &x0, &y0);
  FrameSignature signature;
  const bool empty = width <= 0 || height <= 0; // shows nothing; not an error
  if (ok && !empty)
  {
    this->ZBuffer.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    if (!this->Drawing.ReadDepth(ren, x0, y0, width, height, this->ZBuffer.data()))
    {
      this->ZBuffer.clear(); // no opaque-geometry clipping this frame
    }
    ok = this->Inputs.Build(ren, vol, image, request.Scene, width, height, this->ZBuffer,
      this->Params, signature, error);
  }
  if (!ok && !error.empty())
  {
    fail(error);
  }
  if (!this->Parallel.AllTrue(ok && !empty) || !ok || empty)
  {
    return;
  }
  this->LastError.clear();
  // Compared with the frame that started the accumulation, so slow drifts cannot pile up.
  const auto change = static_cast<FrameSignature::Change>(
    this->Parallel.Agree(static_cast<int>(signature.Compare(this->Signature))));
  if (change == FrameSignature::Change::View && request.TemporalReprojection &&
    this->AccumulatedFrames > 0)
  {
    this->AccumulatedFrames = 0; // a new view: its own running mean, on top of the history
    this->StillConverged = false;
    this->EstimatedQuality = 0.0;
    this->ViewMoved = true;
    this->Signature = std::move(signature);
  }
  else if (change != FrameSignature::Change::None)
  {
    this->ResetAccumulation();
    this->Signature = std::move(signature);
  }

  // 2.-3. Trace and accumulate (a still render: until converged), 4. denoise and combine.
  if (this->Parallel.Agree(this->AccumulatedFrames < request.MaximumAccumulatedFrames &&
        !(request.Still && this->StillConverged)))
  {
    this->Trace(request, messages);
  }
  if (request.Still)
  {
    this->Refine(request, messages);
  }
  this->Combine(request, messages);

  // 5.-6. What the window shows (with several processes: process 0's; the others add nothing
  // to the composited image).
  if (!this->Parallel.Shows())
  {
    return;
  }
  const int shownPass = this->ShownPass(request, messages);
  // Denoised and Converged are drawn with their own opacity (DenoiseFrame, Combine).
  const std::size_t pixels = static_cast<std::size_t>(this->Accumulated.GetWidth()) *
    static_cast<std::size_t>(this->Accumulated.GetHeight());
  const bool convergedAlpha = this->CombinedValid && this->CombinedWithDenoiser &&
    this->ConvergedAlpha.size() == pixels;
  const float* shownAlpha = shownPass == PassDenoised ? this->Accumulated.Data(PassDenoisedAlpha)
    : shownPass == PassConverged && convergedAlpha ? this->ConvergedAlpha.data()
                                                   : nullptr;
  this->Shown.Update(ren, this->Accumulated, shownPass, this->Params.Camera,
    this->Inputs.GetWorldBounds(), request.Threads, shownAlpha);
  this->Drawing.Draw(ren, width, height, this->Shown.GetColor(), this->Shown.GetDepth(),
    this->Shown.GetCovered());
}

//------------------------------------------------------------------------------
void FrameLoop::Trace(const FrameRequest& request, FrameMessages& messages)
{
  const double start = Now();
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
    // jitter, march offset and stream; its own events, PieceStream), and process 0 composites
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
  this->Accumulated.Resize(width, height);
  this->Converging.AddFrame(
    this->Frame.Data(PassRadiance), width, height, this->AccumulatedFrames, request.Threads);
  if (this->ViewMoved)
  {
    const double reprojectStart = Now();
    this->ReprojectFrame(request);
    this->LastReprojectionTime += 1000.0 * (Now() - reprojectStart);
  }
  else if (this->History.HasHistory())
  {
    this->History.Accumulate(
      this->Accumulated, this->Frame, this->AccumulatedFrames, request.Threads);
  }
  else
  {
    this->Accumulated.Accumulate(this->Frame, this->AccumulatedFrames);
  }
  this->AccumulatedCamera = this->Params.Camera;
  this->LastViewFrames = this->AccumulatedFrames;
  this->History.WriteCounts(this->Accumulated.Data(PassHistoryLength), width * height,
    this->AccumulatedFrames);
  // The last frame's edge pixels hold EdgeSamples times a plain pixel's samples (the
  // SampleRatio pass; with KeepEdgeMeans the denoiser leans them towards their own means).
  float* ratio = this->Accumulated.Data(PassSampleRatio);
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  std::fill(ratio, ratio + pixels, 1.f);
  for (const std::uint32_t pixel : this->EdgePixels)
  {
    ratio[pixel] = static_cast<float>(this->EdgeSampleCount);
  }
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

//------------------------------------------------------------------------------
DenoiserSettings FrameLoop::SettingsOf(const FrameRequest& request) const
{
  DenoiserSettings settings = request.Denoiser;
  settings.Threads = request.Threads;
  settings.UseCuda = this->GetActiveBackend() == "CUDA"; // the grid follows the tracer
  return settings;
}

//------------------------------------------------------------------------------
bool FrameLoop::DenoiseFrame(const FrameRequest& request, FrameMessages& messages)
{
  const std::vector<std::string> key = { request.Denoiser.ModelFile,
    std::to_string(request.Denoiser.Levels), std::to_string(request.Threads),
    request.Denoiser.UseNetwork ? "net" : "fixed", request.Denoiser.Footprint ? "fp" : "",
    request.KeepEdgeMeans ? "means" : "" };
  if (this->DenoisedValid && key == this->DenoiseKey)
  {
    return true; // nothing new to denoise
  }
  const DenoiserSettings settings = this->SettingsOf(request);
  PassBuffers& acc = this->Accumulated;
  const int width = acc.GetWidth();
  const int height = acc.GetHeight();
  const float* passes[PassCount] = {};
  for (int p = 0; p < kTracedPassCount; ++p)
  {
    passes[p] = acc.Data(p);
  }
  passes[PassHistoryLength] = acc.Data(PassHistoryLength); // a model's "history" channel
  // With KeepEdgeMeans the edge pixels of the first frame lean towards their own means
  // (SampleRatio); from the second frame on the Converged pass mixes every pixel's mean in.
  if (request.KeepEdgeMeans && this->AccumulatedFrames < 2)
  {
    passes[PassSampleRatio] = acc.Data(PassSampleRatio);
  }
  const double start = Now();
  std::string error;
  // With the opacity it is drawn with: Alpha through the same grid (one frame's alpha is 0 or 1
  // per pixel, which would punch the denoised image back to its coverage).
  if (!this->Denoising.Run(settings, passes, width, height, acc.Data(PassDenoised), error,
        nullptr, acc.Data(PassDenoisedAlpha)))
  {
    messages.emplace_back(true, "Denoising failed: " + error);
    return false;
  }
  const std::string warning = this->Denoising.TakeWarning();
  if (!warning.empty())
  {
    messages.emplace_back(false, warning);
  }
  // Guides (one level per component) and blend weights, zero-padded to 3 and 2 components.
  const int levels = this->Denoising.GetLevels();
  const std::vector<float>& guideIn = this->Denoising.GetGuides();
  const std::vector<float>& weightIn = this->Denoising.GetWeights();
  float* guides = acc.Data(PassGuides);
  float* weights = acc.Data(PassBlendWeights);
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  for (std::size_t k = 0; k < n; ++k)
  {
    for (int l = 0; l < 3; ++l)
    {
      guides[3 * k + l] = l < levels ? guideIn[k * levels + l] : 0.0f;
    }
    for (int l = 0; l < 2; ++l)
    {
      weights[2 * k + l] = l < levels - 1 ? weightIn[k * (levels - 1) + l] : 0.0f;
    }
  }
  this->DenoisedValid = true;
  this->CombinedValid = false;
  this->DenoiseKey = key;
  this->LastDenoiseTime += 1000.0 * (Now() - start);
  return true;
}

//------------------------------------------------------------------------------
void FrameLoop::Combine(const FrameRequest& request, FrameMessages& messages)
{
  if (this->AccumulatedFrames == 0 || !this->Parallel.Shows()) // the others keep no passes
  {
    return;
  }
  const bool denoised = request.Denoise && this->DenoiseFrame(request, messages);
  // Only still renders need the estimate (their stopping rule): interactive frames skip it.
  const bool estimate = request.Still;
  if (this->CombinedValid && this->CombinedWithDenoiser == denoised &&
    (this->CombinedWithEstimate || !estimate))
  {
    return;
  }
  PassBuffers& acc = this->Accumulated;
  this->EstimatedQuality = this->Converging.Combine(denoised ? acc.Data(PassDenoised) : nullptr,
    this->AccumulatedFrames, denoised ? acc.Data(PassConverged) : nullptr, request.Threads,
    estimate);
  this->CombinedWithEstimate = estimate;
  if (denoised)
  {
    const std::size_t n =
      static_cast<std::size_t>(acc.GetWidth()) * static_cast<std::size_t>(acc.GetHeight());
    this->ConvergedAlpha.resize(n);
    this->Converging.BlendAlpha(acc.Data(PassAlpha), acc.Data(PassDenoisedAlpha), n,
      this->ConvergedAlpha.data(), request.Threads);
  }
  this->CombinedValid = true;
  this->CombinedWithDenoiser = denoised;
}

//------------------------------------------------------------------------------
void FrameLoop::Refine(const FrameRequest& request, FrameMessages& messages)
{
  const int cap = std::min(request.MaximumAccumulatedFrames, request.MaximumStillFrames);
  const double start = Now();
  double predicted = std::max(cap, 1); // frames this still will take, as far as is known
  auto progress = [&request](double fraction)
  {
    if (request.Progress)
    {
      request.Progress(std::min(1.0, std::max(0.0, fraction)));
    }
  };
  // The least a still traces: Convergence::kMinimumStillSamples samples per pixel (counted in
  // samples: SamplesPerFrame 4096 needs no more than 2 frames), and 2 frames for the estimate.
  const int samples = std::max(request.Scene.SamplesPerFrame, 1);
  const int minimum =
    std::max(2, (Convergence::kMinimumStillSamples + samples - 1) / samples);
  // Estimates cost a denoise each: the first after that minimum, then where the 1/frames decay
  // of the error predicts the target, at most 1.5x on.
  int next = std::max(minimum, this->AccumulatedFrames);
  enum Decision
  {
    Continue,
    Converged,
    Stop
  };
  // A projection has no Monte Carlo noise, only the pixel jitter's antialiasing: its minimum is
  // the whole still.
  const bool projection = request.Scene.Projection > 0;
  while (!this->StillConverged)
  {
    const int k = this->AccumulatedFrames;
    int decision = Continue;
    if (projection)
    {
      decision = k >= minimum ? Converged : k >= cap ? Stop : Continue;
    }
    else if (k >= next || k >= cap)
    {
      this->Combine(request, messages);
      const double quality = this->EstimatedQuality;
      if (k >= minimum && quality >= request.StillQuality)
      {
        decision = Converged;
      }
      else if (k >= cap)
      {
        decision = Stop;
      }
      const double needed =
        quality > 0.0 ? k * std::pow(10.0, (request.StillQuality - quality) / 10.0) : 2.0 * k;
      predicted = std::min<double>(cap, std::max<double>(needed, k + 1));
      next = std::min(cap,
        std::max(k + 1, std::min(static_cast<int>(std::ceil(needed)), (3 * k + 1) / 2)));
    }
    const bool overBudget =
      request.StillTimeBudget > 0.0 && Now() - start >= request.StillTimeBudget;
    if (decision == Continue && overBudget)
    {
      decision = Stop;
    }
    if (decision == Continue && request.Abort && request.Abort())
    {
      decision = Stop; // the render window's abort check (vtkRenderWindow::CheckAbortStatus)
    }
    decision = this->Parallel.Agree(decision); // process 0 estimates (it alone denoises)
    if (decision != Continue)
    {
      this->StillConverged = decision == Converged;
      if (!this->StillConverged && overBudget && k < cap &&
        this->ReportedBudget != request.StillTimeBudget)
      {
        this->ReportedBudget = request.StillTimeBudget; // said once per budget
        std::ostringstream text;
        text << "the still render stopped at its time budget (StillTimeBudget "
             << request.StillTimeBudget << " s) after " << k << " frames, estimated "
             << this->EstimatedQuality << " dB of StillQuality " << request.StillQuality
             << " dB; raise StillTimeBudget (0: no limit) or lower StillQuality for more.";
        messages.emplace_back(false, text.str());
      }
      break;
    }
    this->Trace(request, messages);
    progress(this->AccumulatedFrames / predicted);
  }
  progress(1.0);
}

//------------------------------------------------------------------------------
int FrameLoop::ShownPass(const FrameRequest& request, FrameMessages& messages)
{
  const int radiance = !(request.Denoise && this->DenoisedValid) ? PassRadiance
    : this->CombinedValid && this->CombinedWithDenoiser    ? PassConverged
                                                           : PassDenoised;
  if (request.DisplayPass.empty())
  {
    this->DisplayProblem.clear();
    return radiance;
  }
  std::string problem;
  int shown = FindPass(request.DisplayPass.c_str());
  if (shown < 0)
  {
    problem = "unknown DisplayPass '" + request.DisplayPass +
      "'; showing the default image (see GetPassName for the names)";
  }
  else if (IsDenoiserPass(shown) && !this->DenoisedValid)
  {
    problem = "DisplayPass '" + request.DisplayPass + "' needs Denoise on; showing Radiance";
  }
  // Its own memory, not ReportOnce's: a frame whose inputs are fine clears that one.
  if (problem != this->DisplayProblem && !problem.empty())
  {
    messages.emplace_back(true, problem);
  }
  this->DisplayProblem = problem;
  return problem.empty() ? shown : radiance; // what an empty DisplayPass shows
}

//------------------------------------------------------------------------------
void FrameLoop::ReleaseGraphicsResources(vtkWindow* window)
{
  this->Drawing.ReleaseGraphicsResources(window);
  this->Tracer.Release();
}
}
