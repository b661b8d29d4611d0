/**
 * @file ptvCudaParity.h
 * @brief How CPU and CUDA results are compared, shared by TestPTVCudaParity (through VTK) and
 *        ptvCudaCheck (captures, no VTK) so that both hold the drivers to the same criteria.
 *
 * The GPU contracts multiply-adds, so a sampled event can land one step apart in rare pixels:
 * first-event passes must agree almost everywhere and radiance closely; the bilateral grid runs
 * the same per-cell / per-pixel functions on both and must agree to float rounding.
 */
#ifndef ptvCudaParity_h
#define ptvCudaParity_h

#include <cmath>
#include <cstddef>

namespace ptv
{
namespace parity
{
constexpr double kDepthTolerance = 1e-4;  ///< relative, per value
constexpr double kNormalTolerance = 1e-3; ///< relative, per value
constexpr double kGridRelative = 1e-5;    ///< grid: max |CPU - CUDA| over the CPU's range

/// Fraction of the @a n values with |a - b| <= tol (1 + |a|).
inline double FractionClose(const float* a, const float* b, std::size_t n, double tol)
{
  std::size_t close = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    close += std::abs(a[i] - b[i]) <= tol * (1.0 + std::abs(a[i])) ? 1 : 0;
  }
  return n ? static_cast<double>(close) / n : 0.0;
}

/// Root mean squared difference of the @a n values.
inline double Rmse(const float* a, const float* b, std::size_t n)
{
  double s = 0.0;
  for (std::size_t i = 0; i < n; ++i)
  {
    s += (a[i] - b[i]) * static_cast<double>(a[i] - b[i]);
  }
  return n ? std::sqrt(s / n) : 0.0;
}

/// Whether a trace of @a samples spp passes, given FractionClose of its Depth and Normal passes
/// (at kDepthTolerance / kNormalTolerance) and the Rmse of its Radiance.
inline bool TraceAgrees(double depthClose, double normalClose, double rmse, int samples)
{
  return depthClose >= 0.995 && normalClose >= 0.99 && rmse <= (samples == 1 ? 0.05 : 0.02);
}
}
}

#endif
