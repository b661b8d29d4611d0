/**
 * @file ptvGuideUpsampleRows.h
 * @brief Private: the guide upsampler's row kernels, compiled for every x86-64 instruction set by
 *        Google Highway and chosen at run time (like ptvBilateralGridRows.h).
 *
 * The file is compiled without floating-point contraction, so every target rounds each product
 * and sum as the scalar definition in ptvGuideUpsample.h does.
 */
#ifndef ptvGuideUpsampleRows_h
#define ptvGuideUpsampleRows_h

#include <cstddef>

namespace ptv
{
/// One output row of the bilinear upsampling: rows @a r0 and @a r1 of a network plane, the row
/// weight @a ly and the column tables (x0, x1, lx per output pixel).
struct UpsampleRowInput
{
  const float* R0;
  const float* R1;
  float LY;
  const int* X0;
  const int* X1;
  const float* LX;
  int Width;
  float Factor;    ///< the guide scale (1 for weights)
  int Stride = 0;  ///< 2: the tables follow the stride-2 pattern (interior pairs vectorised)
  int NetWidth = 0; ///< pixels in R0 and R1
};

/**
 * out[x] = ((1 - ly) * top + ly * bottom) * factor, top = (1 - lx) r0[x0] + lx r0[x1] (bottom
 * likewise from r1), for x < Width. With Stride 2 the tables of pixels 2k and 2k + 1 are
 * (k - 1, k, 0.75) and (k, k + 1, 0.25) for 1 <= k <= NetWidth - 2 (PyTorch's rule at scale 2,
 * exact in float), so those pairs are computed from three shifted loads, without the tables.
 */
void UpsampleRow(const UpsampleRowInput& in, float* out, bool portable);

/// out[count * x + c] = rows[c][x] for x < @a width, c < @a count (1 to 3).
void InterleaveRows(const float* const* rows, int count, int width, float* out, bool portable);
}

#endif
