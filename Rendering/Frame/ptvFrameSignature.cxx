#include "ptvFrameSignature.h"

#include <algorithm>
#include <cmath>

namespace ptv
{
//------------------------------------------------------------------------------
FrameSignature::Change FrameSignature::Compare(const FrameSignature& other) const
{
  auto close = [](const std::vector<double>& x, const std::vector<double>& y)
  {
    if (x.size() != y.size())
    {
      return false;
    }
    for (std::size_t i = 0; i < x.size(); ++i)
    {
      const double a = x[i], b = y[i];
      if (std::abs(a - b) > 1e-6 * std::max({ 1.0, std::abs(a), std::abs(b) }))
      {
        return false;
      }
    }
    return true;
  };
  if (this->Exact != other.Exact || !close(this->Approximate, other.Approximate))
  {
    return Change::Scene;
  }
  if (!close(this->View, other.View))
  {
    return Change::View;
  }
  return this->ViewExact == other.ViewExact ? Change::None : Change::Scene;
}
}
