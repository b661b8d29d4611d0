#!/usr/bin/env bash
# One idempotent setup for PathTracedVolume on Debian bookworm (root, no GPU needed):
#   apt packages -> Python venv -> ONNX Runtime (headers + library) -> [CUDA 13 toolchain]
#   -> real datasets (.vti) -> CMake configure + build in build/.
# Every download is pinned and checksummed; everything fetched lives in ignored folders
# (.venv/, .deps/, .cache/, build/) so a second run only redoes what is missing.
#
# Usage: scripts/setup.sh [--cuda] [--no-build] [--no-data]
#   --cuda      also fetch the pinned CUDA 13 toolchain and build with PTV_ENABLE_CUDA=ON
#   --no-build  stop after dependencies and data
#   --no-data   skip the dataset fetch/convert step
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
DEPS="$ROOT/.deps"
VENV="$ROOT/.venv"
BUILD="${PTV_BUILD_DIR:-$ROOT/build}"
PY=/usr/bin/python3 # Debian's interpreter: the only one that sees ParaView, torch, ...

WITH_CUDA=0
DO_BUILD=1
DO_DATA=1
for arg in "$@"; do
  case "$arg" in
    --cuda) WITH_CUDA=1 ;;
    --no-build) DO_BUILD=0 ;;
    --no-data) DO_DATA=0 ;;
    -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
    *) echo "setup.sh: unknown argument '$arg' (see --help)" >&2; exit 2 ;;
  esac
done

log() { printf '\n== %s\n' "$*"; }

# Pinned versions and checksums ------------------------------------------------------------
ORT_VERSION=1.21.1                       # PyPI wheel providing libonnxruntime.so
ORT_DEV_DEB=libonnxruntime-dev           # headers, from Debian trixie (1.21.0+dfsg-1)
ORT_DEV_VERSION=1.21.0+dfsg-1
ORT_DEV_SHA256=14f7d959d5deacbcf1504830d4189f91fc67382b399ed9ae9d3aa9c4050ced08
CUDA_PKGS=(nvidia-cuda-nvcc==13.0.88 nvidia-nvvm==13.0.88 nvidia-cuda-crt==13.0.88
           nvidia-cuda-runtime==13.0.96 nvidia-cuda-cccl==13.0.85)
PIP_PKGS=("onnxruntime==$ORT_VERSION" pytest==8.3.3 tqdm==4.67.1 pyoidn==2.5.1.0 OpenEXR==3.3.5)

APT_PKGS=(paraview paraview-dev python3-paraview libopenvdb-dev libopenexr-dev xvfb xauth
  libgl1-mesa-dri python3-torch python3-onnx python3-numpy python3-matplotlib python3-skimage
  python3-venv libglew-dev libopenmpi-dev openmpi-bin libdouble-conversion-dev liblz4-dev libtiff-dev
  libutfcpp-dev libboost-iostreams-dev python3-imath cmake ninja-build g++ unzip libhwy-dev
  qtbase5-dev qttools5-dev libqt5opengl5-dev)  # Qt5: the plugin's GUI part (~5 MB download)

# 1. apt ----------------------------------------------------------------------------------
log "apt packages"
missing=()
for p in "${APT_PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}"
  apt-get update -q
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
else
  echo "all ${#APT_PKGS[@]} packages present"
fi

# 2. venv ---------------------------------------------------------------------------------
log "Python venv ($VENV)"
if [[ ! -x "$VENV/bin/python" ]]; then
  "$PY" -m venv --system-site-packages "$VENV"
fi
stamp="$VENV/.ptv-pip-$(echo "${PIP_PKGS[*]}" | md5sum | cut -c1-12)"
if [[ ! -f "$stamp" ]]; then
  "$VENV/bin/python" -m pip install -q --disable-pip-version-check "${PIP_PKGS[@]}"
  touch "$stamp"
fi
echo "venv ready: $("$VENV/bin/python" -c 'import onnxruntime, pytest; print("onnxruntime", onnxruntime.__version__, "pytest", pytest.__version__)')"

# 3. ONNX Runtime C/C++ ---------------------------------------------------------------------
log "ONNX Runtime $ORT_VERSION (library from the wheel, headers from Debian trixie)"
ORT="$DEPS/onnxruntime"
mkdir -p "$ORT/lib"
ort_lib="$("$VENV/bin/python" - <<'EOF'
import glob, os, onnxruntime
libs = sorted(glob.glob(os.path.join(os.path.dirname(onnxruntime.__file__), "capi", "libonnxruntime.so*")))
print(libs[0] if libs else "")
EOF
)"
[[ -n "$ort_lib" ]] || { echo "setup.sh: libonnxruntime.so not found in the onnxruntime wheel" >&2; exit 1; }
ln -sfn "$ort_lib" "$ORT/lib/libonnxruntime.so.1"
ln -sfn libonnxruntime.so.1 "$ORT/lib/libonnxruntime.so"
if [[ ! -f "$ORT/include/onnxruntime_cxx_api.h" ]]; then
  apt_dir="$DEPS/apt-trixie"
  mkdir -p "$apt_dir/lists/partial" "$apt_dir/cache/archives/partial" "$apt_dir/debs"
  echo "deb [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] http://deb.debian.org/debian trixie main" \
    > "$apt_dir/sources.list"
  aopt=(-o "Dir::Etc::sourcelist=$apt_dir/sources.list" -o "Dir::Etc::sourceparts=-"
        -o "Dir::State::Lists=$apt_dir/lists" -o "Dir::Cache=$apt_dir/cache")
  apt-get -q "${aopt[@]}" update
  (cd "$apt_dir/debs" && apt-get -q "${aopt[@]}" download "$ORT_DEV_DEB=$ORT_DEV_VERSION")
  deb="$(ls "$apt_dir"/debs/${ORT_DEV_DEB}_*.deb)"
  got="$(sha256sum "$deb" | cut -d' ' -f1)"
  if [[ "$got" != "$ORT_DEV_SHA256" ]]; then
    echo "setup.sh: checksum mismatch for $deb: expected $ORT_DEV_SHA256, got $got" >&2
    exit 1
  fi
  rm -rf "$apt_dir/x" && dpkg-deb -x "$deb" "$apt_dir/x"
  rm -rf "$ORT/include" && cp -r "$apt_dir/x/usr/include/onnxruntime" "$ORT/include"
fi
echo "ORT headers: $ORT/include, library: $(readlink "$ORT/lib/libonnxruntime.so.1")"

# 4. CUDA 13 toolchain (compile-only on machines without a GPU) ------------------------------
CUDA_ARGS=()
if ((WITH_CUDA)); then
  log "CUDA 13 toolchain"
  CUDA_DIR="$DEPS/cuda"
  cstamp="$CUDA_DIR/.ptv-$(echo "${CUDA_PKGS[*]}" | md5sum | cut -c1-12)"
  if [[ ! -f "$cstamp" ]]; then
    rm -rf "$CUDA_DIR"
    "$VENV/bin/python" -m pip install -q --disable-pip-version-check --no-deps --target "$CUDA_DIR" "${CUDA_PKGS[@]}"
    cu="$CUDA_DIR/nvidia/cu13"
    ln -sfn lib "$cu/lib64"
    ln -sf libcudart.so.13 "$cu/lib/libcudart.so"
    touch "$cstamp"
  fi
  NVCC="$CUDA_DIR/nvidia/cu13/bin/nvcc"
  "$NVCC" --version | tail -2
  CUDA_ARGS=(-DPTV_ENABLE_CUDA=ON "-DCMAKE_CUDA_COMPILER=$NVCC")
fi

# 5. Datasets -------------------------------------------------------------------------------
if ((DO_DATA)); then
  log "datasets"
  "$VENV/bin/python" "$ROOT/scripts/fetch_datasets.py"
fi

# 6. Configure + build ------------------------------------------------------------------------
if ((DO_BUILD)); then
  log "configure + build ($BUILD)"
  cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DPython3_EXECUTABLE=/usr/bin/python3 "-DPTV_ONNXRUNTIME_ROOT=$ORT" \
    "-DPTV_VENV_PYTHON=$VENV/bin/python" "${CUDA_ARGS[@]}"
  cmake --build "$BUILD" -j "$(nproc)"
fi
log "setup done"
