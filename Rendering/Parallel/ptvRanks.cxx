#include "ptvRanks.h"

#include "ptvPassBuffers.h"
#include "ptvThreads.h"

#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"

#include <algorithm>
#include <cstring>
#include <thread>

#include <unistd.h>

namespace ptv
{
//------------------------------------------------------------------------------
Ranks::Ranks() = default;
Ranks::~Ranks() = default;

//------------------------------------------------------------------------------
void Ranks::SetController(vtkMultiProcessController* controller)
{
  if (controller == this->Controller)
  {
    return;
  }
  this->Controller = controller;
  this->Rank = controller ? controller->GetLocalProcessId() : 0;
  this->Size = controller ? std::max(controller->GetNumberOfProcesses(), 1) : 1;
  this->LocalRanks = 0;
}

//------------------------------------------------------------------------------
vtkMultiProcessController* Ranks::GetController() const
{
  return this->Controller;
}

//------------------------------------------------------------------------------
int Ranks::Threads(int requested)
{
  if (requested > 0 || !this->IsParallel())
  {
    return requested;
  }
  if (this->LocalRanks == 0)
  {
    constexpr int kName = 256;
    char name[kName] = {};
    gethostname(name, kName - 1);
    std::vector<char> all(static_cast<std::size_t>(kName) * this->Size);
    this->Controller->AllGather(name, all.data(), kName);
    this->LocalRanks = 0;
    for (int r = 0; r < this->Size; ++r)
    {
      this->LocalRanks += std::strncmp(all.data() + kName * r, name, kName) == 0 ? 1 : 0;
    }
  }
  // The host's cores shared by its ranks, within this rank's affinity (mpirun binds each rank
  // to one core unless told --bind-to none).
  const int host = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return std::max(1, std::min(AvailableCores(), host / std::max(this->LocalRanks, 1)));
}

//------------------------------------------------------------------------------
unsigned int Ranks::FirstSample(unsigned int frame, int samples) const
{
  if (this->Distributed)
  {
    // Every piece traces the same camera rays; PieceStream() keeps the rest independent.
    return frame * static_cast<unsigned int>(samples);
  }
  return (frame * static_cast<unsigned int>(this->Size) + static_cast<unsigned int>(this->Rank)) *
    static_cast<unsigned int>(samples);
}

//------------------------------------------------------------------------------
bool Ranks::Share(bool ok, double ranges[4], double bounds[6], double extent[6])
{
  if (!this->IsParallel())
  {
    return ok;
  }
  // One MIN reduction: ok, then (min, max) pairs as (min, -max).
  constexpr int kCount = 1 + 4 + 6 + 6;
  double local[kCount];
  double* pairs[3] = { ranges, bounds, extent };
  const int sizes[3] = { 4, 6, 6 };
  local[0] = ok ? 1.0 : 0.0;
  for (int a = 0, k = 1; a < 3; ++a)
  {
    for (int i = 0; i < sizes[a]; ++i, ++k)
    {
      local[k] = (i % 2 ? -1.0 : 1.0) * pairs[a][i];
    }
  }
  double all[kCount];
  this->Controller->AllReduce(local, all, kCount, vtkCommunicator::MIN_OP);
  for (int a = 0, k = 1; a < 3; ++a)
  {
    for (int i = 0; i < sizes[a]; ++i, ++k)
    {
      pairs[a][i] = (i % 2 ? -1.0 : 1.0) * all[k];
    }
  }
  return all[0] > 0.0;
}

//------------------------------------------------------------------------------
bool Ranks::AllTrue(bool ok)
{
  if (!this->IsParallel())
  {
    return ok;
  }
  int local = ok ? 1 : 0;
  int all = 0;
  this->Controller->AllReduce(&local, &all, 1, vtkCommunicator::MIN_OP);
  return all != 0;
}

//------------------------------------------------------------------------------
bool Ranks::GatherFrame(PassBuffers& frame, int passes, const PieceView& piece, int threads)
{
  if (!this->IsParallel())
  {
    return true;
  }
  if (this->Distributed)
  {
    return this->CompositeFrame(frame, passes, piece, threads);
  }
  const std::size_t pixels =
    static_cast<std::size_t>(frame.GetWidth()) * static_cast<std::size_t>(frame.GetHeight());
  const float scale = 1.0f / static_cast<float>(this->Size);
  for (int p = 0; p < passes; ++p)
  {
    if (!frame.Data(p))
    {
      continue; // not kept (the same passes on every process)
    }
    const std::size_t n = pixels * static_cast<std::size_t>(GetPassInfo(p).Components);
    this->Sum.resize(this->Rank == 0 ? n : 0);
    this->Controller->Reduce(frame.Data(p), this->Sum.data(), static_cast<vtkIdType>(n),
      vtkCommunicator::SUM_OP, 0);
    if (this->Rank == 0)
    {
      float* out = frame.Data(p);
      for (std::size_t i = 0; i < n; ++i)
      {
        out[i] = this->Sum[i] * scale;
      }
    }
  }
  return this->Rank == 0;
}

//------------------------------------------------------------------------------
int Ranks::Agree(int value)
{
  if (this->IsParallel())
  {
    this->Controller->Broadcast(&value, 1, 0);
  }
  return value;
}

//------------------------------------------------------------------------------
void Ranks::Agree(std::vector<std::uint32_t>& values)
{
  if (!this->IsParallel())
  {
    return;
  }
  int count = this->Rank == 0 ? static_cast<int>(values.size()) : 0;
  this->Controller->Broadcast(&count, 1, 0);
  values.resize(static_cast<std::size_t>(count));
  if (count > 0)
  {
    static_assert(sizeof(unsigned int) == sizeof(std::uint32_t), "32-bit unsigned int");
    this->Controller->Broadcast(
      reinterpret_cast<unsigned int*>(values.data()), static_cast<vtkIdType>(count), 0);
  }
}
}
