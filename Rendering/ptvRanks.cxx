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
  return (frame * static_cast<unsigned int>(this->Size) + static_cast<unsigned int>(this->Rank)) *
    static_cast<unsigned int>(samples);
}

//------------------------------------------------------------------------------
bool Ranks::GatherFrame(PassBuffers& frame, int passes)
{
  if (!this->IsParallel())
  {
    return true;
  }
  const std::size_t pixels =
    static_cast<std::size_t>(frame.GetWidth()) * static_cast<std::size_t>(frame.GetHeight());
  const float scale = 1.0f / static_cast<float>(this->Size);
  for (int p = 0; p < passes; ++p)
  {
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
}
