/**
 * @file ptvScalarChannel.h
 * @brief Private: one component of a volume's scalar array as the float voxels the kernels
 *        sample, stored as it is where float holds it, else shifted (and scaled).
 *
 * The range is taken in the array's own precision. A channel whose magnitude exceeds 1000x its
 * span (or 1e30), or whose span is below 1e-30 or above 1e30, is stored as (v - min), times
 * 1 / span for the last two: an offset such as 1e10 + [0, 100] would otherwise round to a few
 * values or overflow. Data float holds as it is is stored bit for bit.
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
}

#endif
