/**
 * @file ptvPassBuffers.h
 * @brief Private: the named render passes of one image, a per-frame sample store and the
 *        running-mean accumulation of frames.
 */
#ifndef ptvPassBuffers_h
#define ptvPassBuffers_h

#include "Kernels/ptvIntegrator.h"

#include <cstddef>
#include <vector>

namespace ptv
{
/// Stable pass order; names are what users see (vtkPathTracedVolumeMapper::GetPassName).
enum PassId
{
  PassRadiance = 0,
  PassAlpha,
  PassAlbedo,
  PassDepth,
  PassPosition,
  PassNormal,
  PassScatterDepth,
  PassScatterPosition,
  PassScatterNormal,
  PassCoverage,     ///< the camera ray's opacity (PixelSample::Coverage)
  PassFootprint,    ///< 0 where the pixel's footprint is empty space (PixelSample::Footprint)
  PassDenoised,     ///< produced by the denoiser from the traced passes (not accumulated)
  PassGuides,       ///< its guides, one level per component (unused levels 0)
  PassBlendWeights, ///< its blend weights (unused 0)
  PassConverged,    ///< Denoised mixed with Radiance per pixel by a learned blend (ptvConvergence)
  PassHistoryLength, ///< frames in each pixel's accumulated mean (ptvReprojection; capped history)
  PassDenoisedAlpha, ///< Alpha through the denoiser's grid: the opacity Denoised is drawn with
  PassSampleRatio,   ///< each pixel's samples per frame over a plain pixel's (EdgeSamples; 1)
  PassCount
};

/// Passes written by the tracer and accumulated; the others are derived from them.
constexpr int kTracedPassCount = PassDenoised;

/// Whether @a pass is one of the second event's (ScatterDepth, ScatterPosition,
/// ScatterNormal): kept only when asked for (PassBuffers::SetScatterPasses).
inline bool IsScatterPass(int pass)
{
  return pass >= PassScatterDepth && pass <= PassScatterNormal;
}

/// Whether @a pass is made by the denoiser (only available with Denoise on).
inline bool IsDenoiserPass(int pass)
{
  return (pass >= PassDenoised && pass <= PassConverged) || pass == PassDenoisedAlpha;
}

struct PassInfo
{
  const char* Name;
  int Components;
};

const PassInfo& GetPassInfo(int pass);

/// The traced passes' storage: one pointer per pass (PassId < kTracedPassCount), each pass
/// interleaved (GetPassInfo's components per pixel), pixels x fastest; the scatter passes'
/// are nullptr when they are not kept.
struct TracedPassPlanes
{
  float* Data[kTracedPassCount];
};

/// Write @a v at pixel @a pixel of a 3-component pass.
PTV_HD PTV_INLINE void StoreVec3(float* plane, std::size_t pixel, const Vec3& v)
{
  plane[3 * pixel + 0] = v.x;
  plane[3 * pixel + 1] = v.y;
  plane[3 * pixel + 2] = v.z;
}

/// Write @a s (already averaged over the frame's samples) at pixel index @a pixel: the one
/// mapping from a sample to the passes, used by PassBuffers::Store on the CPU and by the CUDA
/// tracer on the device.
PTV_HD PTV_INLINE void StoreSample(const TracedPassPlanes& planes, std::size_t pixel,
  const PixelSample& s)
{
  StoreVec3(planes.Data[PassRadiance], pixel, s.Radiance);
  planes.Data[PassAlpha][pixel] = s.Alpha;
  StoreVec3(planes.Data[PassAlbedo], pixel, s.Albedo);
  planes.Data[PassDepth][pixel] = s.Depth1;
  StoreVec3(planes.Data[PassPosition], pixel, s.Position1);
  StoreVec3(planes.Data[PassNormal], pixel, s.Normal1);
  if (planes.Data[PassScatterDepth])
  {
    planes.Data[PassScatterDepth][pixel] = s.Depth2;
    StoreVec3(planes.Data[PassScatterPosition], pixel, s.Position2);
    StoreVec3(planes.Data[PassScatterNormal], pixel, s.Normal2);
  }
  planes.Data[PassCoverage][pixel] = s.Coverage;
  planes.Data[PassFootprint][pixel] = s.Footprint;
}

/// Read a 3-component pass at pixel @a pixel.
PTV_HD PTV_INLINE Vec3 LoadVec3(const float* plane, std::size_t pixel)
{
  return MakeVec3(plane[3 * pixel + 0], plane[3 * pixel + 1], plane[3 * pixel + 2]);
}

/// The sample StoreSample() wrote at pixel index @a pixel (a frame's mean of its samples).
PTV_HD PTV_INLINE PixelSample LoadSample(const TracedPassPlanes& planes, std::size_t pixel)
{
  PixelSample s;
  s.Radiance = LoadVec3(planes.Data[PassRadiance], pixel);
  s.Alpha = planes.Data[PassAlpha][pixel];
  s.Albedo = LoadVec3(planes.Data[PassAlbedo], pixel);
  s.Depth1 = planes.Data[PassDepth][pixel];
  s.Position1 = LoadVec3(planes.Data[PassPosition], pixel);
  s.Normal1 = LoadVec3(planes.Data[PassNormal], pixel);
  if (planes.Data[PassScatterDepth])
  {
    s.Depth2 = planes.Data[PassScatterDepth][pixel];
    s.Position2 = LoadVec3(planes.Data[PassScatterPosition], pixel);
    s.Normal2 = LoadVec3(planes.Data[PassScatterNormal], pixel);
  }
  else
  {
    s.Depth2 = 0.0f;
    s.Position2 = s.Normal2 = MakeVec3(0.0f, 0.0f, 0.0f);
  }
  s.Coverage = planes.Data[PassCoverage][pixel];
  s.Footprint = planes.Data[PassFootprint][pixel];
  return s;
}

/// Whether @a depth (a Depth or ScatterDepth value) is a hit for the far distance @a far
/// (kHitFraction: Kernels/ptvTraceParams.h).
inline bool IsHit(float depth, float far)
{
  return depth < kHitFraction * far;
}

/// Index of the pass called @a name, or -1.
int FindPass(const char* name);

/// Which passes a PassBuffers keeps per pixel.
enum class PassSet
{
  All,   ///< an accumulation: every pass, the denoiser's Guides and BlendWeights on request
  Traced ///< the traced passes only: a frame's samples (the derived passes stay empty)
};

/// Whether a PassSet::All buffer makes @a pass only on request (Ensure): the denoiser keeps
/// its guides and weights in its own layout, and the frame loop the history's counts and the
/// edge pixels, written into these passes when they are read.
inline bool IsOnRequestPass(int pass)
{
  return pass == PassGuides || pass == PassBlendWeights || pass == PassHistoryLength ||
    pass == PassSampleRatio;
}

class PassBuffers
{
public:
  explicit PassBuffers(PassSet set = PassSet::All)
    : Set(set)
  {
  }

  /// Reallocate for a new size (contents cleared); for the same size, only the kept passes
  /// that hold no storage (handed away by TakeTracedPasses) are allocated, zeros.
  void Resize(int width, int height);

  /// Set every value to 0.
  void Clear();

  /// Allocate an on-request pass (IsOnRequestPass) of the current size, zeros; its values.
  float* Ensure(int pass);

  /// Keep the scatter passes (IsScatterPass) per pixel, zeros when they appear; without them
  /// the tracer stores nothing there. Default on.
  void SetScatterPasses(bool keep);
  bool GetScatterPasses() const { return this->Scatter; }

  int GetWidth() const { return this->Width; }
  int GetHeight() const { return this->Height; }
  /// A pass's values (nullptr for a pass not kept: a derived pass of a PassSet::Traced
  /// buffer, an on-request pass before Ensure).
  float* Data(int pass)
  {
    return this->Buffers[pass].empty() ? nullptr : this->Buffers[pass].data();
  }
  const float* Data(int pass) const
  {
    return this->Buffers[pass].empty() ? nullptr : this->Buffers[pass].data();
  }
  /// The traced passes' pointers (valid until the next Resize or Accumulate).
  TracedPassPlanes Planes();

  /// Write @a s (already averaged over the frame's samples) at pixel index @a pixel.
  void Store(int pixel, const PixelSample& s);

  /**
   * Running mean of the traced passes: this += (frame - this) / count (count >= 1; same size).
   * For count == 1 the buffers are swapped instead of copied (the interactive case: every frame
   * is a first frame), which leaves @a frame's traced passes unspecified; the next trace
   * overwrites every pixel of them.
   */
  void Accumulate(PassBuffers& frame, int count);

  /**
   * Take @a other's traced passes and size without a copy: this buffer's own traced passes are
   * released first and @a other keeps none until its next Resize; the other passes are sized
   * to it (zeros where reallocated). A restarting accumulation takes its first frame as its
   * mean, and the next frame traces into the old mean's storage, with one set of traced
   * passes between them.
   */
  void TakeTracedPasses(PassBuffers& other);

  /// Exchange the buffers of @a pass with @a other's (same size).
  void Swap(int pass, PassBuffers& other) { this->Buffers[pass].swap(other.Buffers[pass]); }

private:
  /// (Re)allocate the kept passes from @a first on, zeros, and free the others; with
  /// @a keepValues the passes already of this size keep theirs.
  void Allocate(bool keepValues, int first = 0);

  PassSet Set = PassSet::All;
  bool Scatter = true;
  int Width = 0;
  int Height = 0;
  std::vector<float> Buffers[PassCount];
};
}

#endif
