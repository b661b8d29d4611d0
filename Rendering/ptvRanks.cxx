#include "ptvRanks.h"

#include "ptvPassBuffers.h"
#include "ptvThreads.h"

#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"

#include <algorithm>
#include <cstring>

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
  return std::max(1, ResolvedThreads(0) / std::max(this->LocalRanks, 1));
}

//------------------------------------------------------------------------------
unsigned int Ranks::FirstSample(unsigned int frame, int samples) const
{
  return (frame * static_cast<unsigned int>(this->Size) + static_cast<unsigned int>(this->Rank)) *
    static_cast<unsigned int>(samples);
}

//------------------------------------------------------------------------------
void Ranks::AverageFrame(PassBuffers& frame, int passes)
{
  if (!this->IsParallel())
  {
    return;
  }
  const std::size_t pixels =
    static_cast<std::size_t>(frame.GetWidth()) * static_cast<std::size_t>(frame.GetHeight());
  const float scale = 1.0f / static_cast<float>(this->Size);
  for (int p = 0; p < passes; ++p)
  {
    const std::size_t n = pixels * static_cast<std::size_t>(GetPassInfo(p).Components);
    this->Sum.resize(n);
    this->Controller->AllReduce(frame.Data(p), this->Sum.data(), static_cast<vtkIdType>(n),
      vtkCommunicator::SUM_OP);
    float* out = frame.Data(p);
    for (std::size_t i = 0; i < n; ++i)
    {
      out[i] = this->Sum[i] * scale;
    }
  }
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
