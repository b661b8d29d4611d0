/**
 * @file ptvCudaCapture.h
 * @brief A traced scene and a denoiser frame saved for the CUDA check: the kernels' inputs and
 *        the CPU drivers' results, read back without VTK.
 *
 * ptvWriteCudaCaptures builds the inputs from a real dataset through the mapper's own code
 * (ptvFrameInputs: TraceParams and the arrays behind it), traces them with the CPU driver's
 * baseline build (bit-reproducible: no FMA) and runs the CPU bilateral grid on GuideNet's guides
 * of that frame. ptvCudaCheck reads the file on a machine with a GPU and no VTK, runs the CUDA
 * drivers on the same inputs and compares. The file is raw host bytes (TraceParams as laid out
 * by this build, little-endian); ReadCapture refuses a file of another layout.
 */
#ifndef ptvCudaCapture_h
#define ptvCudaCapture_h

#include "Kernels/ptvBilateralGrid.h"
#include "Kernels/ptvTraceParams.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ptv
{
/// The traced passes a capture keeps per sample count, and their components.
enum CapturedPass
{
  CapturedRadiance = 0, ///< 3
  CapturedDepth,        ///< 1
  CapturedNormal,       ///< 3
  CapturedPassCount
};

struct TraceCapture
{
  std::string Name; ///< the dataset
  /// The kernel's parameters; after ReadCapture (or PointParams) its pointers refer to the
  /// vectors below (nullptr where a vector is empty).
  TraceParams Params{};
  std::vector<float> Scalars, Colors, ColorScalars, TransferRGBA, GradientOpacity, StepRGBA,
    ShadowAlpha, ColorTableRGBA, MaxDistance;
  std::vector<int8_t> Occupancy;

  /// The CPU driver's means of samples 0 .. Samples[k]-1 (the Width x Height of Params.Camera).
  int Samples[2] = { 1, 16 };
  std::vector<float> Cpu[2][CapturedPassCount];

  /// A bilateral-grid frame of the same size: the 1-spp Radiance and Albedo passes, GuideNet's
  /// guides (GuideLevels interleaved, [0, 255]) and blend weights (GuideLevels - 1), the steps,
  /// and the CPU grid's output for 1 level (guide 0 only) and for all levels.
  std::vector<float> Radiance, Albedo, Guides, Weights;
  int GuideLevels = 0;
  int SpatialStep[kMaxGridLevels] = { 4, 8, 16 };
  int RangeStep[kMaxGridLevels] = { 4, 8, 16 };
  float Clamp = 8.f;
  std::vector<float> GridCpu[2]; ///< [0]: 1 level, [1]: GuideLevels levels

  int Width() const { return this->Params.Camera.Width; }
  int Height() const { return this->Params.Camera.Height; }
};

/// Point @a c.Params' pointers at its vectors (nullptr for an empty vector).
void PointParams(TraceCapture& c);

/// Guide level 0 of @a c (its 1-level guides).
std::vector<float> FirstGuide(const TraceCapture& c);

/// Write @a c to @a file atomically (a temporary file renamed); false + @a error on failure.
bool WriteCapture(const std::string& file, const TraceCapture& c, std::string& error);

/// Read @a file into @a c and point its parameters; false + @a error (which says what is wrong)
/// for a missing, truncated or foreign file or one whose sizes disagree.
bool ReadCapture(const std::string& file, TraceCapture& c, std::string& error);
}

#endif
