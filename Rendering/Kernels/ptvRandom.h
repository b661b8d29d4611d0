/**
 * @file ptvRandom.h
 * @brief Counter-based random numbers: a PCG32 stream keyed by (pixel, frame, seed) only.
 *
 * MakeRng() hashes the key into the initial PCG32 state (the seed also picks the stream
 * increment), so a pixel's random sequence never depends on which thread, block or tile traced
 * it; re-rendering a frame reproduces it bit for bit. For a fixed seed the map
 * (pixel, frame) -> initial state is a bijection (a 64-bit SplitMix finaliser of the packed
 * pair), so no two pixels/frames share a starting point. NextFloat() takes the 24 high bits of
 * the PCG32 output, giving floats in [0, 1) exactly representable as k / 2^24.
 */
#ifndef ptvRandom_h
#define ptvRandom_h

#include "ptvKernelCommon.h"

namespace ptv
{
/// PCG32 (O'Neill 2014, XSH-RR output) state; Inc must be odd.
struct Rng
{
  uint64_t State;
  uint64_t Inc;
};

/// 32-bit hash (Jarzynski & Olano 2020, "pcg_hash").
PTV_HD PTV_INLINE uint32_t PcgHash(uint32_t v)
{
  const uint32_t state = v * 747796405u + 2891336453u;
  const uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

/// SplitMix64 finaliser: a bijection on 64-bit words with good avalanche.
PTV_HD PTV_INLINE uint64_t Mix64(uint64_t z)
{
  z = (z ^ (z >> 30u)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27u)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31u);
}

/// Next 32 random bits; advances the LCG state by one step.
PTV_HD PTV_INLINE uint32_t NextUint(Rng& rng)
{
  const uint64_t old = rng.State;
  rng.State = old * 6364136223846793005ull + rng.Inc;
  const uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
  const uint32_t rot = static_cast<uint32_t>(old >> 59u);
  return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}

/// Uniform float in [0, 1) from the 24 high bits of the next output.
PTV_HD PTV_INLINE float NextFloat(Rng& rng)
{
  return static_cast<float>(NextUint(rng) >> 8u) * (1.f / 16777216.f);
}

/// The generator of one pixel sample; depends on (pixelIndex, frame, seed) and nothing else.
PTV_HD PTV_INLINE Rng MakeRng(uint32_t pixelIndex, uint32_t frame, uint32_t seed)
{
  const uint64_t seedKey = Mix64((static_cast<uint64_t>(PcgHash(seed)) << 32u) ^ seed ^
    0x9e3779b97f4a7c15ull);
  const uint64_t key = (static_cast<uint64_t>(pixelIndex) << 32u) | frame;
  Rng rng;
  rng.State = 0u;
  rng.Inc = (Mix64(seedKey ^ 0xd1b54a32d192ed03ull) << 1u) | 1u;
  // pcg32_srandom: step, add the initial state, step.
  NextUint(rng);
  rng.State += Mix64(key ^ seedKey);
  NextUint(rng);
  return rng;
}
}

#endif
