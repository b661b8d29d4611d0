/**
 * @file ptvBackend.h
 * @brief Private: where frames are traced, numbered as vtkPathTracedVolumeMapper::BACKEND_*
 *        (the mapper checks the numbers), so the frame's units need not include the public class.
 */
#ifndef ptvBackend_h
#define ptvBackend_h

namespace ptv
{
constexpr int kBackendAuto = 0; ///< CUDA when built with it and a usable device exists, else CPU
constexpr int kBackendCpu = 1;
constexpr int kBackendCuda = 2;
}

#endif
