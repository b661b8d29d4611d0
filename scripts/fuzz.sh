#!/usr/bin/env bash
# libFuzzer runs of the file readers/converters, bounded in time and memory.
#   C++ (clang-14 + libFuzzer, ASan + UBSan; Testing/Fuzz/, built in build-fuzz/):
#     fuzz_openvdb_reader   bytes as a .vdb -> vtkPTVOpenVDBReader
#     fuzz_vdb_converter    bytes -> vtkImageData -> vtkPTVOpenVDBWriter -> reader, round trip
#     fuzz_exr_pass_reader  bytes as an .exr -> vtkPTVEXRPassReader
#     fuzz_exr_pass_roundtrip  bytes -> pass image -> vtkPTVEXRPassWriter -> reader, round trip
#   Python (atheris, libFuzzer's engine for Python; Testing/Fuzz/fuzz_exr_io.py):
#     fuzz_exr_io           bytes as an .exr -> ptv_training.exr_io.read_exr / verify_view_file
# Seeds: Testing/Fuzz/corpus/<harness>/ (small, committed); the growing corpus and any crash
# artifacts stay in build-fuzz/. A finding exits non-zero and leaves build-fuzz/artifacts/<file>.
# The OpenVDB reader runs in fork mode past crashes (-fork=1 -ignore_crashes=1 -ignore_ooms=1):
# inside a grid's topology/data OpenVDB allocates compressed blocks with a size read from the file
# (io::bloscFromStream / zipFromStream / readData) before it can check it. A normal build gets the
# memory untouched or std::bad_alloc, and the reader reports the library's error; ASan aborts
# instead (its operator new never throws). Afterwards every new artifact is replayed and triaged:
# such an allocation is counted as the known limitation, OpenVDB 10.0's bloscFromStream overflow
# as the known upstream defect (docs/reliability.md); anything else is a finding and fails the
# script. The EXR pass reader has no known limitation left (its header is checked before OpenEXR
# allocates anything, ptvEXRLayout.cxx): any crash or out-of-memory stops its run and fails.
# Usage: scripts/fuzz.sh [seconds per harness, default 300] [harness...]
# Needs: apt-get install clang-14 libclang-rt-14-dev (libFuzzer); pip install atheris (done here
# into .deps/atheris when missing).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${PTV_FUZZ_BUILD_DIR:-$ROOT/build-fuzz}"
LOCK="${PTV_BUILD_LOCK:-/tmp/ptv-build.lock}"
SECONDS_EACH="${1:-300}"
shift || true
HARNESSES=("$@")
((${#HARNESSES[@]})) || HARNESSES=(fuzz_openvdb_reader fuzz_vdb_converter fuzz_exr_pass_reader
  fuzz_exr_pass_roundtrip fuzz_exr_io)
# Memory caps: a corrupt .vdb once made OpenVDB allocate 24 GB; a capped run reports that as
# "out-of-memory (malloc(...))" instead of taking the machine down.
LIMITS=(-rss_limit_mb=2048 -malloc_limit_mb=1024 -timeout=20 -max_len=16384 -print_final_stats=1)

if ! command -v clang++-14 >/dev/null; then
  echo "fuzz.sh: clang++-14 missing: apt-get install -y clang-14 libclang-rt-14-dev" >&2
  exit 2
fi
if [[ ! -f "$BUILD/CMakeCache.txt" ]]; then
  flock "$LOCK" cmake -S "$ROOT/Testing/Fuzz" -B "$BUILD" -G Ninja \
    -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=RelWithDebInfo
fi
flock "$LOCK" cmake --build "$BUILD" -j "$(nproc)"
mkdir -p "$BUILD/artifacts"
export TMPDIR="$BUILD/tmp" && mkdir -p "$TMPDIR"
export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=0"
export LSAN_OPTIONS="suppressions=$ROOT/scripts/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"

rc=0
for h in "${HARNESSES[@]}"; do
  corpus="$BUILD/corpus/$h"
  mkdir -p "$corpus"
  seeds="$ROOT/Testing/Fuzz/corpus/$h"
  echo "== $h: ${SECONDS_EACH} s"
  if [[ "$h" == fuzz_exr_io ]]; then
    if [[ ! -d "$ROOT/.deps/atheris/atheris" ]]; then
      "$ROOT/.venv/bin/python" -m pip install -q --disable-pip-version-check \
        --target "$ROOT/.deps/atheris" atheris==2.3.0
    fi
    cmd=(env "PYTHONPATH=$ROOT/.deps/atheris:$ROOT/Training" ASAN_OPTIONS=detect_leaks=0
      "$ROOT/.venv/bin/python" "$ROOT/Testing/Fuzz/fuzz_exr_io.py")
  else
    cmd=("$BUILD/$h")
  fi
  extra=()
  known_stack=""
  [[ "$h" == fuzz_openvdb_reader ]] &&
    known_stack="openvdb::v[0-9_]+::io::(bloscFromStream|zipFromStream|readData)"
  [[ -n "$known_stack" ]] && extra=(-fork=1 -ignore_crashes=1 -ignore_ooms=1)
  before="$(ls "$BUILD/artifacts" | grep "^$h-" || true)"
  set +e
  "${cmd[@]}" "${LIMITS[@]}" "${extra[@]}" -max_total_time="$SECONDS_EACH" \
    -artifact_prefix="$BUILD/artifacts/$h-" "$corpus" "$seeds" > "$BUILD/$h.log" 2>&1
  status=$?
  set -e
  grep -E "^(#[0-9]+ *DONE|stat::|==[0-9]+==ERROR|SUMMARY|Done [0-9]+ runs)|artifact|INFO: Seed|^#[0-9]+: cov" \
    "$BUILD/$h.log" | tail -n 40 || true
  if ((${#extra[@]})); then
    # Fork mode: triage the new artifacts (see the top).
    known=0 unknown=0 upstream=0
    for a in $(ls "$BUILD/artifacts" | grep "^$h-" || true); do
      grep -qxF "$a" <<<"$before" && continue
      "${cmd[@]}" -rss_limit_mb=2048 -malloc_limit_mb=1024 -runs=1 "$BUILD/artifacts/$a" \
        > "$BUILD/triage.log" 2>&1 || true
      if grep -qE "allocation-size-too-big|out-of-memory" "$BUILD/triage.log" &&
        grep -qE "$known_stack" "$BUILD/triage.log"; then
        known=$((known + 1))
      elif [[ "$h" == fuzz_openvdb_reader ]] &&
        grep -qE "ERROR: AddressSanitizer: heap-buffer-overflow" "$BUILD/triage.log" &&
        grep -qE "#[0-3] .* in openvdb::v[0-9_]+::io::bloscFromStream" "$BUILD/triage.log"; then
        # OpenVDB 10.0 (Debian bookworm) reads an uncompressed block's declared size into the
        # destination before comparing it with the destination's size (fixed upstream: the
        # check now comes first). Counted and listed, see docs/reliability.md.
        upstream=$((upstream + 1))
        echo "UPSTREAM (OpenVDB bloscFromStream overflow): $BUILD/artifacts/$a"
      else
        unknown=$((unknown + 1))
        echo "FINDING: $BUILD/artifacts/$a"
        grep -E "ERROR|SUMMARY|runtime error|#[0-9] " "$BUILD/triage.log" | head -n 12
      fi
    done
    echo "== $h: $known artifact(s) of the known library allocation, $upstream of the known" \
      "upstream OpenVDB overflow, $unknown other finding(s)"
    status=$((unknown > 0))
  fi
  echo "== $h: exit $status (log: $BUILD/$h.log)"
  ((status == 0)) || rc=1
done
exit $rc
