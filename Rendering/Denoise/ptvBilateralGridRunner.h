/**
 * @file ptvBilateralGridRunner.h
 * @brief Private: run the bilateral grid on the CUDA device when asked and able, else on the
 *        CPU -- the one place that chooses between ptvCudaBilateralGrid and ptvBilateralGridCpu
 *        (used by ptvDenoiser).
 */
#ifndef ptvBilateralGridRunner_h
#define ptvBilateralGridRunner_h

#include "ptvBilateralGridCpu.h"
#include "ptvCudaBilateralGrid.h"

#include <string>

namespace ptv
{
class BilateralGridRunner
{
public:
  /**
   * BilateralGridCpu::Apply, on CUDA when @a useCuda. If CUDA cannot run, @a cudaError says why
   * (it is cleared otherwise) and the CPU computes the result. The opacity (@a alphaIn,
   * @a alphaOut) rides along on the CPU only: whether it did is GetLastAlphaDone().
   */
  void Apply(const BilateralGridSettings& settings, bool useCuda, int width, int height,
    const float* radiance, const float* albedo, const float* guides, const float* weights,
    float* out, std::string& cudaError, const float* alphaIn = nullptr, float* alphaOut = nullptr)
  {
    cudaError.clear();
    this->OnCuda = useCuda &&
      this->Cuda.Apply(
        settings, width, height, radiance, albedo, guides, weights, out, cudaError);
    if (!this->OnCuda)
    {
      this->Cpu.Apply(
        settings, width, height, radiance, albedo, guides, weights, out, alphaIn, alphaOut);
    }
    this->AlphaDone = !this->OnCuda && alphaIn && alphaOut;
  }

  /// Whether the last Apply filtered the opacity too (asked for, and run on the CPU).
  bool GetLastAlphaDone() const { return this->AlphaDone; }

  /// Whether the last Apply ran on the CUDA device.
  bool GetLastOnCuda() const { return this->OnCuda; }

  /// The CPU kernels' instruction set of the last CPU Apply ("" before one).
  const char* GetCpuKernelTarget() const { return this->Cpu.GetLastKernelTarget(); }

  const BilateralGridTimings& GetLastTimings() const
  {
    return this->OnCuda ? this->Cuda.GetLastTimings() : this->Cpu.GetLastTimings();
  }

private:
  BilateralGridCpu Cpu;
  CudaBilateralGrid Cuda;
  bool OnCuda = false;
  bool AlphaDone = false;
};
}

#endif
