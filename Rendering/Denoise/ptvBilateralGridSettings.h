/**
 * @file ptvBilateralGridSettings.h
 * @brief Private: what a bilateral-grid driver (CPU or CUDA) runs, and its phase timings.
 *        Plain structs, no VTK or CUDA header, so both drivers can include it.
 */
#ifndef ptvBilateralGridSettings_h
#define ptvBilateralGridSettings_h

#include "Kernels/ptvBilateralGrid.h"

namespace ptv
{
/// What to run: levels, their steps, the outlier clamp and the thread count.
struct BilateralGridSettings
{
  int Levels = 3;                                 ///< 1..3
  int SpatialStep[kMaxGridLevels] = { 4, 8, 16 }; ///< ss per level, 1..256
  int RangeStep[kMaxGridLevels] = { 4, 8, 16 };   ///< sr per level, 1..256
  double Clamp = 8.0;                             ///< outlier clamp factor, 0 = off
  int Threads = 0;                                ///< <= 0: every core
  /// CPU only: run the baseline (portable) build of the kernels instead of the best instruction
  /// set of this CPU. Also forced by the environment variable PTV_PORTABLE_KERNELS=1.
  bool Portable = false;
};

/// Wall-clock milliseconds of the phases of the last Apply.
struct BilateralGridTimings
{
  double Demodulate = 0.0; ///< sanitise, demodulate, mean luminance, clamp, guide copy
  double Splat = 0.0;      ///< all levels
  double Slice = 0.0;      ///< slice, blend and re-modulate
};

/// The settings' number of levels, clamped to 1..kMaxGridLevels.
inline int ClampedLevels(const BilateralGridSettings& s)
{
  return s.Levels < 1 ? 1 : (s.Levels > kMaxGridLevels ? kMaxGridLevels : s.Levels);
}

/// Level @a l of a @a width x @a height frame: steps clamped to 1..kMaxGridStep and the grid
/// size; Values and Weights are left null for the driver to point at its storage.
inline GridLevel LevelGeometry(const BilateralGridSettings& s, int l, int width, int height)
{
  auto clampStep = [](int v) { return v < 1 ? 1 : (v > kMaxGridStep ? kMaxGridStep : v); };
  GridLevel g{};
  g.SpatialStep = clampStep(s.SpatialStep[l]);
  g.RangeStep = clampStep(s.RangeStep[l]);
  g.Width = GridCells(width, g.SpatialStep);
  g.Height = GridCells(height, g.SpatialStep);
  g.Depth = GridDepth(g.RangeStep);
  return g;
}
}

#endif
