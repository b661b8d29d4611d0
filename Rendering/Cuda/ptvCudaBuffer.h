/**
 * @file ptvCudaBuffer.h
 * @brief Private to Rendering/Cuda: one explicit device allocation (no managed memory), grown
 *        when needed and reused across frames, plus error-to-string helpers.
 */
#ifndef ptvCudaBuffer_h
#define ptvCudaBuffer_h

#include <cuda_runtime.h>

#include <cstddef>
#include <string>

namespace ptv
{
struct DeviceBuffer
{
  void* Ptr = nullptr;
  std::size_t Bytes = 0;

  /// Make room for @a bytes (reallocates only to grow).
  cudaError_t Fit(std::size_t bytes)
  {
    if (this->Ptr && bytes <= this->Bytes)
    {
      return cudaSuccess;
    }
    this->Free();
    const cudaError_t e = cudaMalloc(&this->Ptr, bytes > 0 ? bytes : 1);
    if (e != cudaSuccess)
    {
      this->Ptr = nullptr;
      return e;
    }
    this->Bytes = bytes;
    return cudaSuccess;
  }

  /// Fit, then copy @a bytes from the host.
  cudaError_t Upload(const void* host, std::size_t bytes)
  {
    const cudaError_t e = this->Fit(bytes);
    return e != cudaSuccess ? e : cudaMemcpy(this->Ptr, host, bytes, cudaMemcpyHostToDevice);
  }

  template <typename T>
  T* As() const
  {
    return static_cast<T*>(this->Ptr);
  }

  void Free()
  {
    if (this->Ptr)
    {
      cudaFree(this->Ptr);
    }
    this->Ptr = nullptr;
    this->Bytes = 0;
  }
};

/// True on success; otherwise sets @a error to "CUDA <what>: <message>" and clears the error.
inline bool CudaOk(cudaError_t e, const char* what, std::string& error)
{
  if (e == cudaSuccess)
  {
    return true;
  }
  error = std::string("CUDA ") + what + ": " + cudaGetErrorString(e);
  cudaGetLastError(); // clear the sticky-free error state
  return false;
}
}

#endif
