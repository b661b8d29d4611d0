#include "ptvFrameLoop.h"

#include "ptvEdgeSamples.h"

#include "ptvKernelDispatch.h"

#include "vtkImageData.h"
#include "vtkRenderer.h"
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
  // pixels it marks empty black (docs/decisions.md).
  request.Scene.FootprintRays = this->Parallel.Agree(request.Scene.FootprintRays ||
                                  (request.Denoise && this->Parallel.Shows())) != 0;

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
    std::vector<float>().swap(this->ZBuffer); // read into the rays' limits: not kept
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
  // The scatter passes are kept per pixel only when something reads them; a change of that
  // starts the accumulation again (the passes just kept would hold no history).
  const bool scatter = this->KeepsScatterPasses(request);
  if (scatter != this->Accumulated.GetScatterPasses())
  {
    this->ResetAccumulation();
    for (PassBuffers* buffers :
      { &this->Frame, &this->Sample, &this->EdgeList, &this->Accumulated })
    {
      buffers->SetScatterPasses(scatter);
    }
  }

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
  if (IsOnRequestPass(shownPass))
  {
    this->FillGuidePasses();
    this->FillCountPasses();
  }
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
  this->Drawing.Draw(ren, width, height, this->Shown.GetColor(), this->Shown.GetAlpha(),
    [this](int x0, int y0, int x1, int y1, float* out)
    { this->Shown.WindowDepth(x0, y0, x1, y1, out); },
    this->Shown.GetCovered());
  this->Shown.Release();
}

//------------------------------------------------------------------------------
bool FrameLoop::KeepsScatterPasses(const FrameRequest& request)
{
  const bool shown = IsScatterPass(FindPass(request.DisplayPass.c_str()));
  const bool read = request.Denoise && this->Parallel.Shows() &&
    this->Denoising.ReadsChannelStartingWith(this->SettingsOf(request), "scatter_");
  return this->Parallel.Agree(request.ScatterPasses || shown || read) != 0;
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
