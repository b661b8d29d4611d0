/**
 * @file ptvIsosurface.h
 * @brief Isosurfaces (vtkVolumeMapper::ISOSURFACE_BLEND): surfaces where the interpolated scalar
 *        equals one of the property's iso values, each a surface with the colour and opacity
 *        the transfer function gives at its value.
 *
 * A march finds the surfaces it crosses between two consecutive samples with scalars a and b:
 * value v is crossed when (a >= v) != (b >= v), at the fraction f = (v - a) / (b - a) of the
 * step (linear between the samples, as VTK's GPU mapper does). Several values crossed in one
 * step are met in order along the ray. A surface of opacity alpha (the scalar-opacity function
 * at v, used as a coverage, not per unit distance) scatters with probability alpha and lets the
 * ray through otherwise, so translucent nested surfaces composite front to back; a transmittance
 * ray multiplies 1 - alpha per crossing. Surfaces with alpha = 0 are invisible.
 *
 * Empty-space skipping stays exact: a brick is occupied when a visible iso value lies in its
 * value range (footprint plus a one-voxel border), and a crossing between two samples at most
 * one voxel apart on every axis puts that value in the range of both samples' bricks, so both
 * are visited. Every iso march therefore steps one voxel (StepWorld), shadow rays included.
 */
#ifndef ptvIsosurface_h
#define ptvIsosurface_h

#include "ptvKernelCommon.h"
#include "ptvTransferTable.h"

namespace ptv
{
constexpr int kMaxIsoValues = 8;

struct IsoSurfaces
{
  int Count = 0;                 ///< 0: composite rendering (no isosurfaces)
  float Values[kMaxIsoValues];   ///< in increasing order
};

/**
 * Call visit(fraction, value) for every iso value crossed from scalar @a a to scalar @a b, in
 * the order the ray meets them (increasing fraction in [0, 1]); stop early when visit returns
 * true, and return whether it did.
 */
template <class Visit>
PTV_HD PTV_INLINE bool ForEachCrossing(const IsoSurfaces& iso, float a, float b, Visit&& visit)
{
  if (!(a == a) || !(b == b) || a == b)
  {
    return false; // NaN ("no data") or a flat step crosses nothing
  }
  const bool rising = b > a;
  for (int n = 0; n < iso.Count; ++n)
  {
    const int i = rising ? n : iso.Count - 1 - n; // met in order along the ray
    const float v = iso.Values[i];
    if ((a >= v) != (b >= v) && visit((v - a) / (b - a), v))
    {
      return true;
    }
  }
  return false;
}

/// Whether any iso value with a visible surface lies in [lo, hi] (occupancy of a brick).
PTV_HD PTV_INLINE bool IsoInRange(const IsoSurfaces& iso, const TransferTable& tf, float lo,
  float hi)
{
  for (int i = 0; i < iso.Count; ++i)
  {
    const float v = iso.Values[i];
    if (v >= lo && v <= hi && LookupTransfer(tf, v).Opacity > 0.f)
    {
      return true;
    }
  }
  return false;
}
}

#endif
