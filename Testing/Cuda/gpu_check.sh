#!/bin/bash
# The CUDA path on a GPU machine that has nvcc but no VTK: builds ptvCudaCheck with nvcc alone,
# runs the CPU-vs-CUDA checks and the benchmark on captures written by ptvWriteCudaCaptures, then
# compute-sanitizer's memcheck and initcheck on the concrete's captures. Logs go to OUTDIR.
#
#   Testing/Cuda/gpu_check.sh CAPTURES(.tgz or folder) [OUTDIR] [PREBUILT_ptvCudaCheck]
#
# PREBUILT: a ptvCudaCheck built by this project's CMake build (CUDA architectures 80 and 90) is
# run first as well, so the check covers the binary CI compiles, not only a build made there.
# PTV_CUDA_ARCH (default sm_90) selects the architecture of the nvcc build.
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
captures=${1:?usage: gpu_check.sh CAPTURES [OUTDIR] [PREBUILT]}
out=${2:-.}
prebuilt=${3:-}
mkdir -p "$out"
if [ -f "$captures" ]; then
  dir=$(mktemp -d)
  tar xzf "$captures" -C "$dir" || exit 1
  captures=$dir
fi
files=("$captures"/*.ptvcap)
status=0

nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm,clocks.mem --format=csv \
  | tee "$out/gpu.txt"
nvcc --version | tail -2 | tee -a "$out/gpu.txt"

if [ -n "$prebuilt" ]; then
  echo "== prebuilt (CMake build) ptvCudaCheck"
  "$prebuilt" --bench --sizes 256 512 1024 2048 "${files[@]}" 2>&1 | tee "$out/prebuilt.log" \
    || status=1
fi

echo "== nvcc build ($root)"
bin=$(mktemp -d)/ptvCudaCheck
arch=${PTV_CUDA_ARCH:-sm_90}
includes=(-I"$root/Rendering")
for stage in Frame Trace Accumulate Denoise Display Parallel Support; do
  includes+=(-I"$root/Rendering/$stage")
done
nvcc -std=c++17 -O3 -arch="$arch" -Xptxas -v -Werror all-warnings "${includes[@]}" \
  "$root"/Rendering/Cuda/ptvCudaDevice.cu "$root"/Rendering/Cuda/ptvCudaTracer.cu \
  "$root"/Rendering/Cuda/ptvCudaBilateralGrid.cu "$root"/Testing/Cuda/ptvCudaCheck.cxx \
  "$root"/Testing/Cuda/ptvCudaCapture.cxx "$root"/Rendering/Accumulate/ptvPassBuffers.cxx \
  -o "$bin" > "$out/nvcc.log" 2>&1 || { cat "$out/nvcc.log"; exit 1; }
grep -E "Compiling entry|registers|stack frame" "$out/nvcc.log" | sed 's/ptxas info *: //' \
  | grep -v "^ *$" | head -40

echo "== nvcc-built ptvCudaCheck"
"$bin" --bench --sizes 256 512 1024 2048 "${files[@]}" 2>&1 | tee "$out/built.log" || status=1

# The sanitizers on the small-volume captures (every upload branch of the drivers), parity only.
small=("$captures"/concrete*.ptvcap)
if command -v compute-sanitizer > /dev/null; then
  for tool in memcheck initcheck; do
    echo "== compute-sanitizer $tool (parity on ${#small[@]} captures)"
    timeout 400 compute-sanitizer --tool $tool --error-exitcode 9 "$bin" "${small[@]}" \
      > "$out/$tool.log" 2>&1
    rc=$?
    grep -E "FAILED|ERROR SUMMARY" "$out/$tool.log" | tail -3
    echo "$tool exit $rc"
    [ $rc -eq 0 ] || status=1
  done
else
  echo "compute-sanitizer not found"
fi
exit $status
