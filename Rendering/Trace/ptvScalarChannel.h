/**
 * @file ptvScalarChannel.h
 * @brief Private: one component of a volume's scalar array as the float voxels the kernels
 *        sample, stored as it is where float holds it, else shifted (and scaled).
 *
 * The range is taken in the array's own precision. A channel whose magnitude exceeds 1000x its
 * span (or 1e30), or whose span is below 1e-30 or above 1e30, is stored as (v - min), times
 * 1 / span for the last two: an offset such as 1e10 + [0, 100] would otherwise round to a few
 * values or overflow. Data float holds as it is is stored bit for bit; 8- and 16-bit integer
 * data and such float data are read in place instead when they are one contiguous component
 * (InPlaceScalarType).
 */
#ifndef ptvScalarChannel_h
#define ptvScalarChannel_h

#include "vtkType.h" // for vtkIdType

class vtkDataArray;

namespace ptv
{
/**
 * Component @a component of @a array into @a out (every @a stride th float), any array type:
 * its finite range in @a range, its non-finite values (NaN in @a out) counted in @a nonFinite,
 * and how it is stored, (v - @a shift) * @a scale. A @a factor other than 1 (RGB colour data,
 * 1/255) stores v * factor instead.
 */
void CopyChannel(vtkDataArray* array, int component, float factor, float* out, int stride,
  double range[2], vtkIdType& nonFinite, double& shift, double& scale);

/// CopyChannel with the channel's finite @a range already known (ChannelRangeOf).
void StoreChannel(vtkDataArray* array, int component, float factor, float* out, int stride,
  const double range[2], double& shift, double& scale);

/// Component @a component's finite range in @a range and its count of non-finite values.
void ChannelRangeOf(vtkDataArray* array, int component, double range[2], vtkIdType& nonFinite);

/// Integer volumes of at least this many voxels (a 256 MiB float copy) are read in place.
constexpr vtkIdType kInPlaceIntegerVoxels = vtkIdType(1) << 26;

/**
 * The kernels' ScalarType (Kernels/ptvVolumeGrid.h) that reads @a array's memory in place: a
 * one-component array in contiguous memory of floats that are all finite and stored as they
 * are (@a range, @a nonFinite from ChannelRangeOf), or of 8- or 16-bit integers with at least
 * @a integerVoxels values (smaller ones are copied: the kernels sample float voxels faster);
 * else -1 (the channel is copied with CopyChannel).
 */
int InPlaceScalarType(vtkDataArray* array, const double range[2], vtkIdType nonFinite,
  vtkIdType integerVoxels = kInPlaceIntegerVoxels);
}

#endif
