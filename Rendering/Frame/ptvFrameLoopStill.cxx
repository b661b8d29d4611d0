// FrameLoop, a still render: frames until the shown image's estimated quality reaches its
// target, the frame cap or the time budget, with progress and the window's abort check;
// ptvFrameLoop.h lists the stages.
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
void FrameLoop::Refine(const FrameRequest& request, FrameMessages& messages)
{
  const int cap = std::min(request.MaximumAccumulatedFrames, request.MaximumStillFrames);
  const double start = Now();
  double predicted = std::max(cap, 1); // frames this still will take, as far as is known
  // The fraction shown never goes back, though the predicted frame count may grow.
  double shown = 0.0;
  auto progress = [&request, &shown](double fraction)
  {
    shown = std::max(shown, std::min(1.0, fraction));
    if (request.Progress)
    {
      request.Progress(shown);
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
}
