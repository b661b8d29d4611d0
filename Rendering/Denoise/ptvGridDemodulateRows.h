/**
 * @file ptvGridDemodulateRows.h
 * @brief Private: the CPU bilateral grid's first phase for one image row (sanitise, demodulate,
 *        sum the luminance), compiled for every x86-64 instruction set by Google Highway and
 *        chosen at run time.
 *
 * The semantics are steps 1 and 2 of Kernels/ptvBilateralGrid.h (SanitizeRadiance,
 * SanitizeAlbedo, Demodulate, Luminance); every lane computes what the scalar definition does,
 * so the demodulated pixels are the same bits on every target. Only the order of the row's
 * luminance sum differs (per vector in float, then the vectors in double): the outlier limit
 * derived from it moves by a few 1e-8 relative at most.
 */
#ifndef ptvGridDemodulateRows_h
#define ptvGridDemodulateRows_h

#include <cstddef>

namespace ptv
{
/// The row's result: sum of the demodulated luminance (double) and how many pixels are lit
/// (luminance > 0).
struct DemodulatedRow
{
  double Luminance = 0.0;
  std::size_t Lit = 0;
};

/**
 * Writes (r, g, b, 1) per pixel of one row into @a demod4 (4 * @a width floats) from
 * interleaved RGB @a radiance and @a albedo (3 * @a width floats; @a albedo null: no
 * demodulation). @a portable: the baseline build instead of the best instruction set of this CPU.
 */
DemodulatedRow DemodulateRow(const float* radiance, const float* albedo, std::size_t width,
  float* demod4, bool portable);
}

#endif
