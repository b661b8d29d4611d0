#include "ptvScalarChannel.h"

#include "Kernels/ptvVolumeGrid.h"

#include "vtkArrayDispatch.h"
#include "vtkDataArray.h"
#include "vtkDataArrayRange.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ptv
{
namespace
{
// One component of any numeric array as float (out[stride * i] = (v - shift) * scale),
// non-finite values as NaN ("no data").
struct ChannelToFloat
{
  template <typename ArrayT>
  void operator()(ArrayT* array, int component, double shift, double scale, float* out,
    int stride)
  {
    const auto tuples = vtk::DataArrayTupleRange(array);
    const vtkIdType n = static_cast<vtkIdType>(tuples.size());
    const bool plain = shift == 0.0 && scale == 1.0;
    vtkSMPTools::For(0, n,
      [&](vtkIdType b, vtkIdType e)
      {
        for (vtkIdType i = b; i < e; ++i)
        {
          const double v = static_cast<double>(tuples[i][component]);
          const float f = plain ? static_cast<float>(tuples[i][component])
                                : static_cast<float>((v - shift) * scale);
          out[stride * i] =
            std::isfinite(v) && std::isfinite(f) ? f : std::numeric_limits<float>::quiet_NaN();
        }
      });
  }
};

// A channel's finite range in the array's own precision and its count of non-finite values
// (in parallel: a 2 GiB volume is scanned before its first frame).
struct ChannelRange
{
  template <typename ArrayT>
  void operator()(ArrayT* array, int component, double range[2], vtkIdType& nonFinite)
  {
    struct Partial
    {
      double Lo = std::numeric_limits<double>::infinity();
      double Hi = -std::numeric_limits<double>::infinity();
      vtkIdType Bad = 0;
    };
    const auto tuples = vtk::DataArrayTupleRange(array);
    vtkSMPThreadLocal<Partial> partials;
    vtkSMPTools::For(0, static_cast<vtkIdType>(tuples.size()),
      [&](vtkIdType b, vtkIdType e)
      {
        Partial& part = partials.Local();
        for (vtkIdType i = b; i < e; ++i)
        {
          const double v = static_cast<double>(tuples[i][component]);
          if (!std::isfinite(v))
          {
            ++part.Bad;
            continue;
          }
          part.Lo = std::min(part.Lo, v);
          part.Hi = std::max(part.Hi, v);
        }
      });
    Partial all;
    for (const Partial& part : partials)
    {
      all.Lo = std::min(all.Lo, part.Lo);
      all.Hi = std::max(all.Hi, part.Hi);
      all.Bad += part.Bad;
    }
    range[0] = all.Lo;
    range[1] = all.Hi;
    nonFinite = all.Bad;
  }
};

// How a channel of finite range @a range is stored as float, (v - shift) * scale: as it is
// (0, 1) while float holds it to well below the table's resolution; else shifted to start at 0
// (an offset such as 1e10 + [0, 100] would otherwise round to a few values, or overflow), and
// scaled to [0, 1] when its span itself is outside float's comfortable range.
void StoredAs(const double range[2], double& shift, double& scale)
{
  shift = 0.0;
  scale = 1.0;
  if (!(range[1] >= range[0]))
  {
    return; // no finite value
  }
  const double span = range[1] - range[0];
  const double magnitude = std::max(std::abs(range[0]), std::abs(range[1]));
  const bool tinyOrHuge = span > 0.0 && (span < 1e-30 || span > 1e30);
  if (magnitude > 1e30 || magnitude > 1000.0 * span || tinyOrHuge)
  {
    shift = range[0];
  }
  if (tinyOrHuge)
  {
    scale = 1.0 / span;
  }
}
}

//------------------------------------------------------------------------------
void ChannelRangeOf(vtkDataArray* array, int component, double range[2], vtkIdType& nonFinite)
{
  ChannelRange ranger;
  if (!vtkArrayDispatch::Dispatch::Execute(array, ranger, component, range, nonFinite))
  {
    ranger(array, component, range, nonFinite); // generic vtkDataArray path
  }
}

//------------------------------------------------------------------------------
int InPlaceScalarType(
  vtkDataArray* array, const double range[2], vtkIdType nonFinite, vtkIdType integerVoxels)
{
  if (!array || array->GetNumberOfComponents() != 1 || !array->HasStandardMemoryLayout())
  {
    return -1;
  }
  const bool big = array->GetNumberOfTuples() >= integerVoxels;
  switch (array->GetDataType())
  {
    case VTK_UNSIGNED_CHAR:
      return big ? kScalarUInt8 : -1;
    case VTK_SIGNED_CHAR:
      return big ? kScalarInt8 : -1;
    case VTK_UNSIGNED_SHORT:
      return big ? kScalarUInt16 : -1;
    case VTK_SHORT:
      return big ? kScalarInt16 : -1;
    case VTK_FLOAT:
    {
      // In place only where the copy would hold the same bits: no NaN / infinity to turn into
      // "no data", no shift or scale (StoredAs).
      double shift, scale;
      StoredAs(range, shift, scale);
      return nonFinite == 0 && shift == 0.0 && scale == 1.0 ? kScalarFloat : -1;
    }
    default:
      return -1;
  }
}

//------------------------------------------------------------------------------
void CopyChannel(vtkDataArray* array, int component, float factor, float* out, int stride,
  double range[2], vtkIdType& nonFinite, double& shift, double& scale)
{
  ChannelRangeOf(array, component, range, nonFinite);
  StoreChannel(array, component, factor, out, stride, range, shift, scale);
}

//------------------------------------------------------------------------------
void StoreChannel(vtkDataArray* array, int component, float factor, float* out, int stride,
  const double range[2], double& shift, double& scale)
{
  StoredAs(range, shift, scale);
  if (factor != 1.0f)
  {
    shift = 0.0; // RGB colour (factor 1/255): stored as it is, then scaled
    scale = factor;
  }
  ChannelToFloat worker;
  if (!vtkArrayDispatch::Dispatch::Execute(array, worker, component, shift, scale, out, stride))
  {
    worker(array, component, shift, scale, out, stride);
  }
}
}
